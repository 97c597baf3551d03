#include <suturesim/rod/cross_section.h>

#include <cmath>

namespace suturesim::rod
{
  double
  CrossSection::area() const
  {
    return M_PI * radius * radius;
  }

  double
  CrossSection::second_moment() const
  {
    return M_PI * std::pow(radius, 4) / 4;
  }

  SectionStiffness
  CrossSection::stiffness() const
  {
    const double G     = E / (2 * (1 + nu));
    const double kappa = 6 * (1 + nu) / (7 + 6 * nu); // Cowper (1966), solid circle
    SectionStiffness s;
    const double ea = EA > 0 ? EA : E * area();
    const double ga = GA > 0 ? GA : kappa * G * area();
    const double ei = EI > 0 ? EI : E * second_moment();
    const double gj = GJ > 0 ? GJ : G * 2 * second_moment();
    s.force << ea, ga, ga;
    s.moment << gj, ei, ei;
    return s;
  }

  double
  CrossSection::mass_per_length() const
  {
    return density * area();
  }

  Vec3
  CrossSection::rotational_inertia_per_length() const
  {
    const double I = second_moment();
    return density * Vec3(2 * I, I, I);
  }

  const std::vector<SuturePreset> &
  preset_table()
  {
    // Diameters: the middle of the USP range of each size (references.md: 2-0
    // 0.250–0.299, 3-0 0.200–0.249, 4-0 0.150–0.199, 5-0 0.100–0.149, 6-0 0.070–0.079 mm).
    // Moduli: monofilament nylon/polypropylene "of order 1–5 GPa", taken as 3 GPa as in
    // issue 3's 3-0 example; silk 8.7 GPa initial modulus (Naleway et al. 2015, J Biomed
    // Mater Res B 103:735). Braided silk bends far more easily than a solid section; the
    // preset is the solid bound (references.md). Densities are not in references.md:
    // nylon 6 1140 kg/m³, silk fibroin 1300 kg/m³ (polymer handbook values); Poisson's
    // ratio 0.4 for both (typical of semicrystalline polymers). Change them per scene.
    static const std::vector<SuturePreset> table = [] {
      std::vector<SuturePreset> t;
      const std::vector<std::pair<std::string, double>> sizes{
        {"2-0", 0.2745e-3}, {"3-0", 0.2245e-3}, {"4-0", 0.1745e-3}, {"5-0", 0.1245e-3}, {"6-0", 0.0745e-3}};
      for (const auto &[size, d] : sizes)
        {
          t.push_back({size + " monofilament", d, 3e9, 0.4, 1140,
                       "USP diameter range midpoint; E of order 1-5 GPa (references.md)"});
          t.push_back({size + " silk", d, 8.7e9, 0.4, 1300,
                       "USP diameter range midpoint; E = 8.7 GPa (Naleway et al. 2015)"});
        }
      return t;
    }();
    return table;
  }
} // namespace suturesim::rod
