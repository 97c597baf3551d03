#pragma once
/**
 * @file
 * Volumetric strain energies Ψ_vol(J) = κ·G(J) of decoupled hyperelastic materials. The
 * registered choices (source/tissue/volumetric_energy.cc):
 *  - "simo-taylor-1991": G = ¼(J² − 1 − 2 ln J) (Simo & Taylor 1991; the energy of the
 *    compressible Cook's membrane benchmark, Pelteret & McBride 2016), the default;
 *  - "quadratic": G = ½(J − 1)²;
 *  - "logarithmic": G = ½(ln J)².
 * All give p = Ψ'(1 + ε) ≈ κε for small volume change ε.
 */

#include <suturesim/core/registry.h>

#include <memory>

namespace suturesim::tissue
{
  class VolumetricEnergy
  {
  public:
    /// Created with the bulk modulus κ (Pa).
    using Registry = suturesim::Registry<VolumetricEnergy, double>;

    virtual ~VolumetricEnergy() = default;

    /// Ψ_vol(J) (Pa).
    virtual double
    energy(double J) const = 0;

    /// Pressure p = dΨ_vol/dJ (Pa).
    virtual double
    pressure(double J) const = 0;

    /// dp/dJ = d²Ψ_vol/dJ² (Pa).
    virtual double
    pressure_derivative(double J) const = 0;
  };
} // namespace suturesim::tissue
