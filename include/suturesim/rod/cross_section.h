#pragma once
/**
 * @file
 * Solid circular suture cross-section: radius r → A = πr², I = πr⁴/4, J = 2I, and the
 * section stiffnesses EA, κGA (Cowper 1966, J. Appl. Mech. 33:335, κ = 6(1+ν)/(7+6ν) for
 * a circle), EI, GJ; or the four stiffnesses given directly. Named suture presets (USP
 * size + material) fill radius, E, ν and density; their values and sources are listed in
 * preset_table() and in the parameter help.
 */

#include <suturesim/rod/rod_element.h>

#include <string>
#include <vector>

namespace suturesim::rod
{
  struct CrossSection
  {
    double radius  = 0.1125e-3; ///< m
    double E       = 3e9;       ///< Young's modulus, Pa
    double nu      = 0.4;       ///< Poisson's ratio
    double density = 1140;      ///< kg/m³
    // stiffnesses given directly (0: from the section), N and N m²
    double EA = 0, GA = 0, EI = 0, GJ = 0;

    double
    area() const;
    double
    second_moment() const;
    SectionStiffness
    stiffness() const;
    double
    mass_per_length() const;
    /// ρ(J, I, I), kg m
    Vec3
    rotational_inertia_per_length() const;
  };

  struct SuturePreset
  {
    std::string name;
    double      diameter; ///< m
    double      E;        ///< Pa
    double      nu;
    double      density;  ///< kg/m³
    std::string source;
  };

  /// "2-0 monofilament" … "6-0 silk": every preset with its sources.
  const std::vector<SuturePreset> &
  preset_table();
} // namespace suturesim::rod
