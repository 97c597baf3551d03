/**
 * The accurate suture tied by seed 002's knot planner (Model = accurate, Bodies = suture,
 * a Knot): the Cosserat rod of rod/ with self-contact, its first end held, its last node
 * the grasper the planner moves (knot/planner.h), the same instructions, clearance and
 * speed as the realtime path reads from the same scene file. A plan that moves the first
 * end too (the square and granny knots) holds the first node in a grasper as well, its
 * tangent led opposite to its motion (the rope trails it), and reads the pull on the end
 * that moves.
 *
 * Each step Δt (Time/Step size) asks the planner where the end goes from the rod's
 * nodes of the last accepted state and the rope's pull on the end, moves the last node
 * there (its frame led along the motion, led_frame()), applies the scene's loads and a
 * prescribed first end's motion, and solves the rod to equilibrium (Newton's
 * corrections capped at the radius and 0.25 rad) with the viscous drag of Suture/Stabilization
 * (rod/viscous_drag.h): the drag stands for what the seed's rope lies on and keeps a
 * slack rope's position determined, so that the rod is dragged along by its end as the
 * seed's follow-the-leader rope is, instead of springing to the elastica its two ends
 * alone would give. A step that fails is undone (the planner too) and halved
 * (core/cutback_stepper.h). The record is the accurate suture's (scene/suture_recorder.h)
 * with metrics.knot and the knot_crossing events of the realtime path.
 */
#include <suturesim/core/cutback_stepper.h>
#include <suturesim/core/error.h>
#include <suturesim/knot/planner.h>
#include <suturesim/rod/rod_integrator.h>
#include <suturesim/rod/viscous_drag.h>
#include <suturesim/scene/knot_parameters.h>
#include <suturesim/scene/scenario.h>
#include <suturesim/scene/suture_recorder.h>
#include <suturesim/scene/timed_run.h>

#include <algorithm>

namespace suturesim::scene
{
  using namespace dealii;

  namespace
  {
    Eigen::Matrix3Xd
    rope(const rod::RodModel &model)
    {
      Eigen::Matrix3Xd x(3, model.n_nodes());
      for (std::size_t i = 0; i < model.n_nodes(); ++i)
        x.col(i) = model.positions()[i];
      return x;
    }

    /// The grasper's frame at the end's next position: @p q with its tangent d₁ turned
    /// (the least rotation) onto the end's @p move seen in the plane of normal @p n. The
    /// grasper leads the end along its motion, as the seed's follow-the-leader rope's
    /// last link follows its end, and holds it level: the height is the planner's to
    /// change (its factor 3) by bending the thread, not by pointing the end up or down.
    rod::Quat
    led_frame(const rod::Quat &q, const rod::Vec3 &move, const rod::Vec3 &n)
    {
      const rod::Vec3 along = move - n * n.dot(move);
      if (along.norm() == 0)
        return q;
      return (rod::Quat::FromTwoVectors(q * rod::Vec3::UnitX(), along) * q).normalized();
    }

    /// How the rod's strands met over the run, tracked per accepted state: the steps with
    /// a pair in contact (contact_steps) and the least centreline distance of a pair over
    /// the diameter (least_distance_over_diameter; 1: touching, below: the strands overlap
    /// by that share of the diameter); written with metrics.knot of the last state
    /// (knot::knot_metrics()) and the planner's knot_crossing events once, when the run
    /// ends or fails (the diagram is read once, not every step).
    class KnotRecord
    {
    public:
      KnotRecord(const knot::KnotPlanner &planner, const rod::RodModel &model, nlohmann::json &summary)
        : planner(planner)
        , model(model)
        , summary(summary)
      {}

      /// After an accepted state (its contact pairs assembled).
      void
      accepted()
      {
        const auto  &pairs    = model.contact().pairs();
        const double diameter = 2 * model.contact().parameters().radius;
        for (const auto &c : pairs)
          least = std::min(least, c.distance / diameter);
        steps += !pairs.empty();
      }

      /// metrics.knot of the model's state (the last accepted one) and the events.
      void
      finish() const
      {
        auto &k                           = summary["metrics"]["knot"] = knot::knot_metrics(planner, rope(model));
        k["contact_steps"]                = steps;
        k["least_distance_over_diameter"] = least;
        auto &list                        = summary["events"];
        if (!list.is_array())
          list = nlohmann::json::array();
        for (const auto &e : knot::knot_events(planner))
          list.push_back(e);
      }

    private:
      const knot::KnotPlanner &planner;
      const rod::RodModel     &model;
      nlohmann::json          &summary;
      std::size_t              steps = 0;
      double                   least = 1;
    };

    /// One run of the planner on the rod: each step (attempt()) moves the last node
    /// where the planner sends it and solves; a failed attempt is undone, the planner
    /// with it (undo()); an accepted state is recorded and gives the planner the rope's
    /// pull on its end (accept()). The steps are core/cutback_stepper.h's.
    class PlannedTie
    {
    public:
      PlannedTie(const SceneParameters &scene, rod::RodProblem &p, knot::KnotPlanner &planner,
                 rod::StateObserver &observer, KnotRecord &record)
        : p(p)
        , model(p.model)
        , planner(planner)
        , observer(observer)
        , record(record)
        , normal(scene.knot.normal.normalized())
        , last(model.n_nodes() - 1)
        , drag(model, scene.suture.stabilization)
        , before(planner)
        , newton(scene.suture.newton)
        , terms([this](std::size_t i, const rod::Vec3 &x, const rod::Quat &, rod::Vec6 &r, rod::Mat6 &J) {
          drag.add(i, x, r, J);
        })
      {
        // a Newton correction is capped at the suture's radius (half the contact
        // distance: no strand jumps through another within one iteration) and 0.25 rad
        newton.max_displacement = scene.suture.section.radius;
        newton.max_rotation     = 0.25;
      }

      void
      run()
      {
        p.set_time(0);
        model.constrain(last, {{true, true, true, true, true, true}});
        if (planner.moves_first_end())
          model.constrain(0, {{true, true, true, true, true, true}});
        observer.accepted(0, {{"time", 0.0}, {"newton_iterations", 0}}, nullptr); // assembles the contact pairs
        record.accepted();
        model.commit_contact();
        StepHooks hooks;
        hooks.attempt = [&](const double t_new, const double dt) { return attempt(t_new, dt); };
        hooks.undo    = [&](const StepAttempt &, double, double) { undo(); };
        hooks.accept  = [&](const double t_new, const double dt, unsigned) { accept(t_new, dt); };
        hooks.fail    = [&](const double t_new, const unsigned cutbacks, const std::string &reason) {
          throw SolverError("knot step from t = " + std::to_string(t) + " s to " + std::to_string(t_new) +
                            " s failed after " + std::to_string(cutbacks) + " step halvings: " + reason +
                            "; the last converged state is kept");
        };
        hooks.keep = [&](const double t_now) { return observer.keep(t_now); };
        run_with_cutbacks({p.time.end_time, p.time.step_size, p.time.max_cutbacks, 0, 0, 4, p.time.maximum_steps},
                          hooks);
      }

    private:
      rod::RodProblem         &p;
      rod::RodModel           &model;
      knot::KnotPlanner       &planner;
      rod::StateObserver      &observer;
      KnotRecord              &record;
      const rod::Vec3          normal;
      const std::size_t        last;
      rod::ViscousDrag         drag;
      knot::KnotPlanner        before;
      rod::NewtonParameters    newton;
      const rod::NodalTerms    terms; // the drag, added to each node's residual and tangent
      rod::NewtonResult        result;
      std::vector<rod::Vec3>   start;
      std::vector<rod::Quat>   turn;
      double                   t         = 0;
      double                   end_force = 0;

      StepAttempt
      attempt(const double t_new, const double dt)
      {
        start  = model.positions();
        turn   = model.rotations();
        before = planner;
        p.set_time(t_new); // the loads, and a prescribed first end's motion
        const knot::Ends to = planner.move(rope(model), t_new, dt, end_force);
        model.set_node(last, to.last, led_frame(turn[last], to.last - start[last], normal));
        // the first end's tangent points into the rope, which trails behind it
        if (planner.moves_first_end())
          model.set_node(0, to.first, led_frame(turn[0], start[0] - to.first, normal));
        drag.begin_step(&start, dt);
        result = model.solve(newton, &terms);
        p.newton_iterations += result.iterations;
        return result.converged ? StepAttempt{} : StepAttempt{StepAttempt::Outcome::failed, result.reason};
      }

      void
      undo()
      {
        for (std::size_t i = 0; i < start.size(); ++i)
          model.set_node(i, start[i], turn[i]);
        p.set_time(t);
        planner = before;
      }

      void
      accept(const double t_new, const double dt)
      {
        t = t_new;
        // the static residual (the drag left out), assembled once: the supports'
        // reactions the recorder writes, the rope's pull on the grasper the planner reads
        const Eigen::VectorXd r = model.residual();
        end_force               = r.segment<3>(6 * (planner.moving_first_end() ? 0 : last)).norm();
        observer.accepted(t, {{"time", t}, {"newton_iterations", result.iterations}, {"residual", result.residual},
                              {"step_size", dt}, {"stabilization_force", drag.total_force(model.positions())}},
                          &r);
        record.accepted();
        model.commit_contact();
      }
    };

    class AccurateKnot : public Scenario
    {
    public:
      AccurateKnot(ParameterHandler &prm, SceneParameters &s)
        : scene(s)
      {
        scene.scope("Closure").require(!scene.closure.present(), "Gap probes",
                                       "wound closure needs the suture in the tissue: Bodies = tissue and suture");
        scene.parse_bodies(prm);
        scene.parse_time(prm);
        KnotParameters::check(scene);
        const ParameterScope suture = scene.scope("Suture");
        suture.require(scene.suture.stabilization > 0, "Stabilization",
                       "the accurate knot is tied against a drag on the rope (what it lies on): must be > 0 N s/m^2");
        suture.subsection("Self-contact")
          .require(scene.suture.contact.enabled, "Enabled",
                   "the accurate knot needs the rod's self-contact (true), or its strands pass through each other");
        const ParameterScope time = scene.scope("Time");
        time.require(scene.time.integrator == "quasi-static", "Integrator",
                     "the accurate knot is tied in quasi-static steps (quasi-static)");
        time.require(scene.time.step_size * scene.knot.speed < scene.knot.clearance, "Step size",
                     "the planner's end would move more than Knot/Clearance per step: must be < Clearance/Speed = " +
                       std::to_string(scene.knot.clearance / scene.knot.speed) + " s");
      }

      void
      run(io::Recorder &recorder) override
      {
        run_timed(recorder, [&](TimerOutput &timer, ConditionalOStream &pcout) {
          SutureRun          suture(scene, recorder, pcout, " tied by the knot planner (" + scene.knot.knot + ")");
          TimerOutput::Scope section(timer, "suture");
          knot::KnotPlanner  planner(scene.knot);
          KnotRecord         record(planner, suture.problem.model, recorder.summary());
          try
            {
              PlannedTie(scene, suture.problem, planner, suture.observer, record).run();
            }
          catch (...)
            {
              record.finish();
              throw;
            }
          record.finish();
        });
      }

    private:
      SceneParameters &scene;
    };

    const bool registered = Scenario::Registry::instance().add(
      {"accurate knot",
       "the Cosserat-rod suture tied by seed 002's knot planner (Model = accurate, Bodies = suture, a Knot)",
       nullptr,
       [](const SceneParameters &s) { return s.model == "accurate" && s.bodies == "suture" && s.knot.knot != "none"; },
       [](ParameterHandler &prm, SceneParameters &s) { return std::unique_ptr<Scenario>(new AccurateKnot(prm, s)); }});
  } // namespace
} // namespace suturesim::scene
