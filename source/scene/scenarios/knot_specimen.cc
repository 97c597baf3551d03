/**
 * A knot specimen (Model = accurate, Bodies = knot specimen): the suture of the Suture
 * subsection (its Cross section and Self-contact) laid as an open overhand knot, tied
 * into a naturally straight rod and pulled tight by its last end (rod/knot_tightening.h),
 * its end force against end shortening compared with the tight-knot law of Audoly,
 * Clauvelin & Neukirch (PRL 99, 164301, 2007).
 *
 * Records: forces.csv (one row per pull step: the pull, the shortening, the end
 * force, R where the rope leaves the braid, ε = √(h/R), F h²/B and the law's value, the
 * least centreline distance of the strands in contact over 2h), suture.pvd (the rod at
 * every step, its time the pull in m), and summary.json's metrics.knot_tightening and
 * metrics.knot (the knot's diagram seen across the tails after the pull, for
 * postprocess/plot_knot.py; "tied": its Gauss code is the overhand's, O1 U2 O3 U1 O2
 * U3, or that code's mirror image).
 */
#include <suturesim/core/error.h>
#include <suturesim/knot/planner.h>
#include <suturesim/rod/knot_tightening.h>
#include <suturesim/scene/run_summary.h>
#include <suturesim/scene/scenario.h>
#include <suturesim/scene/suture_recorder.h>
#include <suturesim/scene/timed_run.h>

#include <algorithm>
#include <cmath>

namespace suturesim::scene
{
  using namespace dealii;

  namespace
  {
    struct Specimen
    {
      double size = 0, tail = 0, element = 0, pretension = 0, pull_step = 0, pull_distance = 0, drag = 0;

      static void
      declare(ParameterHandler &prm)
      {
        // the defaults are rod::KnotTighteningParameters' (one place)
        const rod::KnotTighteningParameters d;
        const auto text = [](const double v) { return Utilities::to_string(v); };
        prm.enter_subsection("Knot specimen");
        prm.declare_entry("Knot", "overhand", Patterns::Selection("overhand"),
                          "The knot laid: overhand, the trefoil (sin t + 2 sin 2t, cos t - 2 cos 2t, -sin 3t) a cut "
                          "open at the tip of a lobe, with straight tails along the tangent there. Unit: none.");
        prm.declare_entry("Knot size", text(d.knot_size), Patterns::Double(0),
                          "a, the trefoil's scale (its lobes reach 3a from its centre; its strands pass 1.21 a apart). "
                          "Unit: m. Range: > 0, with 1.21 a > 2.2 Suture/Cross section/Radius.");
        prm.declare_entry("Tail length", text(d.tail), Patterns::Double(0), "Each straight tail. Unit: m. Range: > 0.");
        prm.declare_entry("Element length", text(d.element), Patterns::Double(0),
                          "Of the rod's elements (the laid curve resampled). Unit: m. Range: > 0, at most the "
                          "suture's diameter (contacts are found between segments).");
        prm.declare_entry("Pretension", text(d.pretension), Patterns::Double(0),
                          "F0, the end tension under which the knot is tied (ramped up on the stress-free knot, "
                          "then held while its rest shape is straightened). Unit: N. Range: > 0.");
        prm.declare_entry("Pull step", text(d.pull_step), Patterns::Double(0),
                          "The last end's displacement per recorded step (halved within the step while a solve "
                          "fails). Unit: m. Range: > 0.");
        prm.declare_entry("Pull distance", "0.05", Patterns::Double(0),
                          "How far the last end is pulled after the knot is tied. Unit: m. Range: > 0.");
        prm.declare_entry("Drag", text(d.drag), Patterns::Double(0),
                          "The viscous drag per unit length of the pseudo-time steps (of 1 s) that solve each "
                          "stage to equilibrium; an equilibrium is reached when no node's drag exceeds 1e-5 B/h^2. "
                          "Unit: N s/m^2. Range: > 0.");
        prm.leave_subsection();
      }

      void
      parse(ParameterHandler &prm, const ParameterScope &scope)
      {
        prm.enter_subsection("Knot specimen");
        size          = prm.get_double("Knot size");
        tail          = prm.get_double("Tail length");
        element       = prm.get_double("Element length");
        pretension    = prm.get_double("Pretension");
        pull_step     = prm.get_double("Pull step");
        pull_distance = prm.get_double("Pull distance");
        drag          = prm.get_double("Drag");
        prm.leave_subsection();
        scope.require(pull_distance >= pull_step, "Pull distance", "must be at least the Pull step");
      }
    };

    class KnotSpecimen : public Scenario
    {
    public:
      KnotSpecimen(ParameterHandler &prm, SceneParameters &s)
        : scene(s)
      {
        scene.scope("Needle").require(!scene.needle.present(), "Shape", "a knot specimen has no needle");
        scene.scope("Closure").require(!scene.closure.present(), "Gap probes", "a knot specimen has no wound");
        const ParameterScope scope = scene.scope("Knot specimen");
        specimen.parse(prm, scope);
        prm.enter_subsection("Suture");
        scene.suture.parse(prm, scene.scope("Suture"));
        prm.leave_subsection();
        const double r = scene.suture.section.radius;
        scene.scope("Suture/Self-contact")
          .require(scene.suture.contact.enabled, "Enabled", "must be true: the knot's strands hold by contact");
        scope.require(1.2143 * specimen.size > 2.2 * r, "Knot size",
                      "lays strands closer than 1.1 diameters (1.21 a < 2.2 r = " + std::to_string(2.2 * r) + " m)");
        scope.require(specimen.element <= 2 * r, "Element length",
                      "must be at most the suture's diameter " + std::to_string(2 * r) + " m");
      }

      void
      run(io::Recorder &recorder) override
      {
        run_timed(recorder, [&](TimerOutput &timer, ConditionalOStream &pcout) {
          rod::KnotTighteningParameters p;
          p.radius     = scene.suture.section.radius;
          p.section    = scene.suture.section.stiffness();
          p.contact    = scene.suture.contact;
          p.knot_size  = specimen.size;
          p.tail       = specimen.tail;
          p.element    = specimen.element;
          p.pretension = specimen.pretension;
          p.pull_step  = specimen.pull_step;
          p.drag       = specimen.drag;
          rod::KnotTightening knot(p);
          RunSummary          summary(recorder.summary());
          summary.begin(scene);
          const double h = p.radius, B = knot.bending_stiffness(), mu = p.contact.friction;
          pcout << "suturesim: scene '" << scene.name << "', an overhand knot in a rod of " << knot.model().n_elements()
                << " elements, h = " << h << " m, B = " << B << " N m^2, mu = " << mu << "\n";
          {
            TimerOutput::Scope section(timer, "tie");
            if (!knot.tie())
              throw SolverError(knot.failure());
          }
          recorder.set_columns({"pulled [m]", "shortening [m]", "force [N]", "braid_exit_radius [m]", "eps [1]",
                                "force_scaled [1]", "audoly_force_scaled [1]", "least_distance_over_2h [1]",
                                "contact_nodes [1]", "newton_iterations [1]"});
          write_suture_vtu(knot.model(), h, 0, 0, recorder);
          Curve curve;
          TimerOutput::Scope section(timer, "pull");
          const int steps = static_cast<int>(std::round(specimen.pull_distance / specimen.pull_step));
          for (int k = 1; k <= steps; ++k)
            {
              if (!knot.pull())
                {
                  finish(recorder, curve, knot);
                  throw SolverError(knot.failure());
                }
              const rod::KnotState s = knot.state();
              if (s.contacts == 0)
                {
                  finish(recorder, curve, knot);
                  throw SolverError("the knot came undone after pulling " + std::to_string(s.pulled) + " m");
                }
              const double eps = std::sqrt(h / s.radius), fbar = s.force * h * h / B;
              const double law = rod::KnotTightening::audoly_tension(eps, mu);
              recorder.add_row({s.pulled, s.shortening, s.force, s.radius, eps, fbar, law, s.closest,
                                double(s.contacts), double(s.iterations)});
              write_suture_vtu(knot.model(), h, k, s.pulled, recorder); // ParaView's time: the pull, m
              curve.add(fbar / law, s.closest, s.force * s.radius * s.radius / B);
              pcout << "  pulled " << s.pulled << " m: F = " << s.force << " N, R = " << s.radius
                    << " m, eps = " << eps << ", F/law = " << fbar / law << "\n";
            }
          finish(recorder, curve, knot);
        });
      }

    private:
      SceneParameters &scene;
      Specimen         specimen;

      /// The law's ratios, the least distance, F R²/B over the pull.
      struct Curve
      {
        std::vector<double> ratios, prefactors;
        double              least = 1;
        void
        add(const double ratio, const double closest, const double prefactor)
        {
          ratios.push_back(ratio);
          prefactors.push_back(prefactor);
          least = std::min(least, closest);
        }
      };

      static Eigen::Matrix3Xd
      rope(const rod::RodModel &model)
      {
        Eigen::Matrix3Xd x(3, model.n_nodes());
        for (std::size_t i = 0; i < model.n_nodes(); ++i)
          x.col(i) = model.positions()[i];
        return x;
      }

      static void
      finish(io::Recorder &recorder, const Curve &curve, const rod::KnotTightening &knot)
      {
        // the overhand's code as seed 002's planner ties it, or its mirror image (O and U
        // swapped: the same knot seen from the plane's other side, or tied the other way)
        const knot::Projection projection(rod::KnotTightening::projection_normal());
        const std::string      planned = knot::tied_code(knot::instructions("overhand")).text();
        std::string            mirror  = planned;
        for (char &c : mirror)
          c = c == 'O' ? 'U' : c == 'U' ? 'O' : c;
        nlohmann::json m        = knot::diagram_metrics(rope(knot.model()), projection);
        m["knot"]               = "overhand (laid)";
        m["planned_gauss_code"] = planned + " or " + mirror;
        m["tied"]               = m["gauss_code"] == planned || m["gauss_code"] == mirror;
        auto &metrics                 = recorder.summary()["metrics"];
        metrics["knot"]               = m;
        auto &t                       = metrics["knot_tightening"];
        t["steps"]                    = curve.ratios.size();
        t["least_distance_over_2h"]   = curve.least;
        t["interpenetration_over_radius"] = std::max(0.0, 2 * (1 - curve.least));
        if (curve.ratios.empty())
          return;
        const auto [lo, hi]     = std::minmax_element(curve.ratios.begin(), curve.ratios.end());
        t["audoly_ratio_range"] = {*lo, *hi};
        double mean             = 0;
        for (const double f : curve.prefactors)
          mean += f / curve.prefactors.size();
        t["force_radius_squared_over_B"] = mean;
      }
    };

    const bool registered = Scenario::Registry::instance().add(
      {"knot specimen",
       "an overhand knot laid in the suture, tied into a straight rod and pulled tight, against Audoly et al. 2007 "
       "(Model = accurate, Bodies = knot specimen)",
       Specimen::declare,
       [](const SceneParameters &s) { return s.model == "accurate" && s.bodies == "knot specimen"; },
       [](ParameterHandler &prm, SceneParameters &s) { return std::unique_ptr<Scenario>(new KnotSpecimen(prm, s)); }});
  } // namespace
} // namespace suturesim::scene
