/**
 * A knot specimen (Model = accurate, Bodies = knot specimen): the suture of the Suture
 * subsection (its Cross section and Self-contact) laid as an open overhand, figure-eight
 * or cinquefoil knot, tied into a naturally straight rod and pulled tight by its last end
 * (rod/knot_tightening.h), its end force against end shortening; the overhand's compared
 * with the tight-knot law of Audoly, Clauvelin & Neukirch (PRL 99, 164301, 2007).
 *
 * Records: forces.csv (one row per pull step: the pull, the shortening, the end
 * force, R where the rope leaves the braid, ε = √(h/R), F h²/B and, for the overhand,
 * the law's value, the least centreline distance of the strands in contact over 2h,
 * R₀ where the loop's tension vanishes, the first integral's spread and the ends'
 * imbalance: rod::KnotState),
 * suture.pvd (the rod at every step, its time the pull in m), and summary.json's
 * metrics.knot_tightening and metrics.knot (the knot's diagram seen across the tails
 * after the pull, for postprocess/plot_knot.py; "reads_planned_code": its reduced Gauss
 * code is the code seed 002's planner ties for that knot, or its mirror image's, cut open
 * somewhere, knot::GaussCode::is_cut_of(); "tied": its knot determinant is the planned
 * knot's, knot::GaussCode::determinant()).
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
      std::string knot;
      double size = 0, tail = 0, element = 0, pretension = 0, pull_step = 0, pull_distance = 0, drag = 0;

      static void
      declare(ParameterHandler &prm)
      {
        // the defaults are rod::KnotTighteningParameters' (one place)
        const rod::KnotTighteningParameters d;
        const auto text = [](const double v) { return Utilities::to_string(v); };
        prm.enter_subsection("Knot specimen");
        std::string names;
        for (const auto &k : rod::KnotTightening::laid_knots())
          names += (names.empty() ? "" : "|") + k;
        prm.declare_entry("Knot", d.knot, Patterns::Selection(names),
                          "The knot laid, cut open where it is furthest from its axis, with straight tails along the "
                          "tangent there: overhand, the trefoil (sin t + 2 sin 2t, cos t - 2 cos 2t, -sin 3t) a cut at "
                          "the tip of a lobe; figure-eight, ((2 + cos 2t) cos 3t, (2 + cos 2t) sin 3t, sin 4t) a cut at "
                          "t = 0; cinquefoil, the (2, 5) torus knot ((2 + cos 5t) cos 2t, (2 + cos 5t) sin 2t, -sin 5t) "
                          "a cut at t = 0. Unit: none. Range: " +
                            Utilities::replace_in_string(names, "|", ", ") + ".");
        prm.declare_entry("Knot size", text(d.knot_size), Patterns::Double(0),
                          "a, the knot's scale (all reach 3a from their axis; the trefoil's strands pass 1.2143 a "
                          "apart, the figure-eight's 1.1408 a, the cinquefoil's 1.1287 a, and laid cut open at least "
                          "0.95 of that). Unit: m. "
                          "Range: > 0, with the laid distance > 2.2 Suture/Cross section/Radius.");
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
                          "stage to equilibrium; an equilibrium is reached when neither any node's drag nor their sum "
                          "exceeds 1e-5 B/h^2. "
                          "Unit: N s/m^2. Range: > 0.");
        prm.leave_subsection();
      }

      void
      parse(ParameterHandler &prm, const ParameterScope &scope)
      {
        prm.enter_subsection("Knot specimen");
        knot          = prm.get("Knot");
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
        const double clearance = rod::KnotTightening::strand_clearance(specimen.knot);
        scope.require(clearance * specimen.size > 2.2 * r, "Knot size",
                      "lays the " + specimen.knot + "'s strands closer than 1.1 diameters (" +
                        std::to_string(clearance) + " a < 2.2 r = " + std::to_string(2.2 * r) + " m)");
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
          p.knot       = specimen.knot;
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
          pcout << "suturesim: scene '" << scene.name << "', " << specimen.knot << " knot in a rod of "
                << knot.model().n_elements()
                << " elements, h = " << h << " m, B = " << B << " N m^2, mu = " << mu << "\n";
          {
            TimerOutput::Scope section(timer, "tie");
            if (!knot.tie())
              throw SolverError(knot.failure());
          }
          // Audoly et al.'s law is the trefoil's: the other knots' curves are recorded without it
          const bool trefoil = specimen.knot == "overhand";
          std::vector<std::string> columns{"pulled [m]", "shortening [m]", "force [N]", "braid_exit_radius [m]",
                                           "eps [1]", "force_scaled [1]", "audoly_force_scaled [1]",
                                           "least_distance_over_2h [1]", "contact_nodes [1]", "newton_iterations [1]",
                                           "loop_zero_tension_radius [m]", "first_integral_spread [1]",
                                           "end_force_imbalance [1]"};
          if (!trefoil)
            columns.erase(columns.begin() + 6);
          recorder.set_columns(columns);
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
              std::vector<double> row{s.pulled,         s.shortening,       s.force, s.radius, eps, fbar, law,
                                      s.closest,        double(s.contacts), double(s.iterations),
                                      s.loop_radius,    s.first_integral_spread, s.end_force_imbalance};
              if (!trefoil)
                row.erase(row.begin() + 6);
              recorder.add_row(row);
              write_suture_vtu(knot.model(), h, k, s.pulled, recorder); // ParaView's time: the pull, m
              curve.add(trefoil ? fbar / law : 0, s.closest, s.force * s.radius * s.radius / B,
                        s.force * s.loop_radius * s.loop_radius / B, s.first_integral_spread);
              pcout << "  pulled " << s.pulled << " m: F = " << s.force << " N, R = " << s.radius
                    << " m, eps = " << eps << ", F R^2/B = " << s.force * s.radius * s.radius / B
                    << ", F R0^2/B = " << s.force * s.loop_radius * s.loop_radius / B
                    << (trefoil ? ", F/law = " + std::to_string(fbar / law) : std::string()) << "\n";
            }
          finish(recorder, curve, knot);
        });
      }

    private:
      SceneParameters &scene;
      Specimen         specimen;

      /// The law's ratios, the least distance, F R²/B and F R₀²/B (where R₀ is read),
      /// the first integral's largest spread, over the pull.
      struct Curve
      {
        std::vector<double> ratios, prefactors, loop_prefactors;
        double              least = 1, spread = 0;
        void
        add(const double ratio, const double closest, const double prefactor, const double loop_prefactor,
            const double first_integral_spread)
        {
          ratios.push_back(ratio);
          prefactors.push_back(prefactor);
          if (loop_prefactor > 0)
            loop_prefactors.push_back(loop_prefactor);
          least  = std::min(least, closest);
          spread = std::max(spread, first_integral_spread);
        }
        static double
        mean(const std::vector<double> &v)
        {
          double m = 0;
          for (const double x : v)
            m += x / v.size();
          return m;
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

      void
      finish(io::Recorder &recorder, const Curve &curve, const rod::KnotTightening &knot) const
      {
        // "reads_planned_code": the code seed 002's planner ties for the knot, or its
        // mirror image's (O and U swapped: seen from the plane's other side, or tied the
        // other way), cut open anywhere (the trefoil's cuts all read one code, the
        // figure-eight's eight). Pulled tight, a knot seen along a fixed plane may keep
        // crossings the reductions cannot remove; "tied" asks only that the knot be the
        // planned one as its determinant tells, which every diagram of it gives, and
        // that it show at least the planned knot's crossings
        const knot::Projection projection(knot.projection_normal());
        const knot::GaussCode  planned = knot::tied_code(knot::instructions(specimen.knot));
        nlohmann::json         m       = knot::diagram_metrics(rope(knot.model()), projection);
        const knot::GaussCode  code    = knot::GaussCode::parse(m["gauss_code"].get<std::string>());
        m["knot"]                      = specimen.knot + " (laid)";
        m["planned_gauss_code"]        = planned.text();
        m["planned_determinant"]       = planned.determinant();
        m["reads_planned_code"]        = code.is_cut_of(planned);
        m["tied"] = code.determinant() == planned.determinant() && code.crossings() >= planned.crossings();
        auto &metrics                 = recorder.summary()["metrics"];
        metrics["knot"]               = m;
        auto &t                       = metrics["knot_tightening"];
        t["steps"]                    = curve.ratios.size();
        t["least_distance_over_2h"]   = curve.least;
        t["interpenetration_over_radius"] = std::max(0.0, 2 * (1 - curve.least));
        if (curve.prefactors.empty())
          return;
        if (specimen.knot == "overhand")
          {
            const auto [lo, hi]     = std::minmax_element(curve.ratios.begin(), curve.ratios.end());
            t["audoly_ratio_range"] = {*lo, *hi};
          }
        t["force_radius_squared_over_B"] = Curve::mean(curve.prefactors);
        t["first_integral_spread"]       = curve.spread;
        if (!curve.loop_prefactors.empty())
          t["force_loop_radius_squared_over_B"] = Curve::mean(curve.loop_prefactors);
      }
    };

    const bool registered = Scenario::Registry::instance().add(
      {"knot specimen",
       "an overhand, figure-eight or cinquefoil knot laid in the suture, tied into a straight rod and pulled tight (the overhand "
       "against Audoly et al. 2007) "
       "(Model = accurate, Bodies = knot specimen)",
       Specimen::declare,
       [](const SceneParameters &s) { return s.model == "accurate" && s.bodies == "knot specimen"; },
       [](ParameterHandler &prm, SceneParameters &s) { return std::unique_ptr<Scenario>(new KnotSpecimen(prm, s)); }});
  } // namespace
} // namespace suturesim::scene
