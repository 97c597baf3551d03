#pragma once
/**
 * @file
 * Continuum tear criteria of the accurate path. A criterion reads the state of one
 * material point (deformation gradient F, Cauchy stress σ, strain energy Ψ per
 * reference volume) and returns a measure m with the direction n a tear would open
 * against (the crack plane's normal, current configuration). A tear starts where the
 * process-zone average of m (process_zone.h) reaches the criterion's critical value m_c.
 *
 * The average is what makes onset a property of the tissue rather than of the mesh: a
 * pierce point loads the tissue at a point, so the local maximum of every measure below
 * grows without bound under refinement, while its mean over a zone of fixed radius ℓ
 * has a limit. This is the volume method of the theory of critical distances (Taylor,
 * The Theory of Critical Distances, Elsevier 2007, §2.4) and the nonlocal averaging of
 * Pijaudier-Cabot & Bažant (J Eng Mech 113:1512, 1987).
 *
 * Criteria register themselves, one source file each in source/tearing/criteria/, with
 * their equation and the source of their default critical value.
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/core/registry.h>

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace suturesim::tearing
{
  /// The critical energy release rate's default and help, one text for the two places a
  /// scene sets G_c: the fracture-energy criterion (Tearing/fracture-energy) and the
  /// tissue's phase field (Tissue/Phase field).
  inline constexpr const char *default_toughness = "1.1e3";
  inline constexpr const char *toughness_help =
    "Critical energy release rate G_c; default porcine skin cut by a needle (1.1 kJ/m^2; tear tests give "
    "17-30 kJ/m^2, porcine liver 76-225 J/m^2). Unit: J/m^2. Range: > 0.";

  using Tensor2    = dealii::Tensor<2, 3>;
  using SymTensor2 = dealii::SymmetricTensor<2, 3>;
  using Vector3    = dealii::Tensor<1, 3>;

  /// What a criterion may read at one material point.
  struct MaterialPointState
  {
    /// Deformation gradient F = I + ∇u (1).
    Tensor2 F;
    /// Cauchy stress σ (Pa).
    SymTensor2 cauchy_stress;
    /// Strain energy Ψ per reference volume (J/m³).
    double energy = 0;
  };

  /// A criterion's measure at a point and the unit normal of the plane a tear would open
  /// along there (current configuration; its sign is arbitrary).
  struct Measure
  {
    double  value = 0;
    Vector3 direction;
  };

  class TearCriterion
  {
  public:
    /// Created from the criterion's own subsection; checks fail through the scope.
    using Registry = suturesim::Registry<TearCriterion, const dealii::ParameterHandler &, const ParameterScope &>;

    virtual ~TearCriterion() = default;

    virtual Measure
    measure(const MaterialPointState &state) const = 0;

    /// The critical value m_c of the measure averaged over a process zone of radius
    /// @p process_zone_radius (m). Only energy-release criteria depend on the radius.
    virtual double
    critical_value(double process_zone_radius) const = 0;

    /// SI unit of the measure, for output headers.
    virtual std::string
    unit() const = 0;
  };

  /// The largest eigenvalue of a symmetric tensor and its unit eigenvector.
  std::pair<double, Vector3>
  largest_principal(const SymTensor2 &A);

  /// The criteria a scene selects, each by its registered name, and the process zone.
  struct TearCriteria
  {
    /// Declares "Criteria", "Process zone radius" and every registered criterion's
    /// subsection into the current subsection.
    static void
    declare_parameters(dealii::ParameterHandler &prm);

    /// Reads them from the current subsection (the one declared into).
    static TearCriteria
    parse_parameters(const dealii::ParameterHandler &prm, const ParameterScope &scope);

    /// ℓ (m): the radius of the zone around each pierce tract the measures are averaged over.
    double                                                                    process_zone_radius = 0;
    std::vector<std::pair<std::string, std::shared_ptr<const TearCriterion>>> criteria;
  };
} // namespace suturesim::tearing
