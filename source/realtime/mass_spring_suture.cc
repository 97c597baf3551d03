/**
 * The linear mass-spring suture of seed 001 §3: "the nodes are simply arranged linearly,
 * one after another, and joined together with edge-springs", home springs zero, gravity
 * on each node; seed 001 chose this simplest of its models. The spring of one link is
 * k = EA/l unless a softer one is given: the seeds soften it on purpose, since a stiff
 * chain forces a tiny explicit time step (seed 001 §7: "too stretchy", but a higher
 * constant "would greatly increase the instability").
 */
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/suture_model.h>

namespace suturesim::realtime
{
  namespace
  {
    class MassSpringSuture : public SutureModel
    {
    public:
      explicit MassSpringSuture(const ParameterValues &p)
        : stretch(p.real("Stretch stiffness"))
      {}

    protected:
      void
      add_interactions(System &s, const std::uint32_t first) override
      {
        auto springs = std::make_unique<SpringSet>("suture springs");
        for (std::uint32_t i = first; i + 1 < s.suture.end; ++i)
          springs->add(i, i + 1, link, stretch > 0 ? stretch : axial_stiffness);
        s.interactions.push_back(std::move(springs));
      }

    private:
      double stretch;
    };

    const bool registered = SutureModel::Registry::instance().add(
      {"mass-spring",
       "linear chain of masses joined by springs (seed 001 sec. 3), no bending; "
       "k = EA/l per link unless softened.",
       [](ParameterDeclarations &d) {
         d.add_real("Stretch stiffness", 0, 0, 1e12,
                    "Spring stiffness of one link; 0 = EA/l from the suture's section. "
                    "Unit: N/m. Range: >= 0.");
       },
       [](const ParameterValues &p) { return std::unique_ptr<SutureModel>(new MassSpringSuture(p)); }});
  } // namespace
} // namespace suturesim::realtime
