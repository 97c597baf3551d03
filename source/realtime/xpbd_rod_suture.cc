/**
 * A rod of stretch and bending constraints for XPBD: distance constraints with
 * compliance l/EA per link and the curvature constraint b = x_{i−1} − 2x_i + x_{i+1}
 * with compliance l³/EI per interior node (curvature_springs.h). No twist: a round
 * monofilament's twist does not couple to its centreline until it is much twisted,
 * which suturing avoids. Under the force-based integrators the same energies act as
 * forces, with their stability limit.
 */
#include <suturesim/realtime/curvature_springs.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/suture_model.h>

#include <cmath>
#include <limits>

namespace suturesim::realtime
{
  namespace
  {
    class XpbdRod : public SutureModel
    {
    public:
      explicit XpbdRod(const ParameterValues &p)
        : stretch(p.real("Stretch stiffness"))
        , bending(p.real("Bending stiffness"))
      {}

    protected:
      void
      add_interactions(System &s, const std::uint32_t first) override
      {
        auto springs = std::make_unique<SpringSet>("suture springs");
        for (std::uint32_t i = first; i + 1 < s.suture.end; ++i)
          springs->add(i, i + 1, link, stretch > 0 ? stretch : axial_stiffness);
        s.interactions.push_back(std::move(springs));
        const double c = bending > 0 ? bending : shape.EI / std::pow(link, 3);
        if (c > 0)
          {
            auto curvature = std::make_unique<CurvatureSprings>();
            for (std::uint32_t i = first + 1; i + 1 < s.suture.end; ++i)
              curvature->add(i - 1, i, i + 1, c);
            s.interactions.push_back(std::move(curvature));
          }
      }

    private:
      double stretch, bending;
    };

    const bool registered = SutureModel::Registry::instance().add(
      {"xpbd-rod",
       "stretch (compliance l/EA) and bending (x_{i-1} - 2 x_i + x_{i+1}, compliance "
       "l^3/EI) constraints, solved by XPBD or as forces.",
       [](ParameterDeclarations &d) {
         d.add_real("Stretch stiffness", 0, 0, 1e12,
                    "Stiffness of one link; 0 = EA/l. Unit: N/m. Range: >= 0.");
         d.add_real("Bending stiffness", 0, 0, 1e12,
                    "c of the curvature energy c/2 |x_{i-1} - 2 x_i + x_{i+1}|^2; "
                    "0 = EI/l^3. Unit: N/m. Range: >= 0.");
       },
       [](const ParameterValues &p) { return std::unique_ptr<SutureModel>(new XpbdRod(p)); }});
  } // namespace
} // namespace suturesim::realtime
