// Parameters: declare → print → parse round trip of the whole scene tree, and the
// defaults declared through the in-class initialisers parse back to those initialisers
// (conventions.md §2).
#include <suturesim/core/error.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/scene/needle_parameters.h>
#include <suturesim/scene/realtime_settings.h>
#include <suturesim/scene/simulation.h>
#include <suturesim/scene/wound_closure.h>
#include <suturesim/tissue/linear_solver.h>
#include <suturesim/core/time_parameters.h>
#include <suturesim/tissue/time_integrator.h>
#include <suturesim/tissue/tissue_model.h>

#include <gtest/gtest.h>

#include "run_scene.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace suturesim;

namespace
{
  std::string
  print(const dealii::ParameterHandler &prm)
  {
    std::ostringstream out;
    prm.print_parameters(out, dealii::ParameterHandler::PRM);
    return out.str();
  }
} // namespace

TEST(Parameters, RoundTripOfEveryShippedScene)
{
  // Every scene in parameters/ and benchmarks/<case>/. With model sections the printed
  // state is the common text and the chosen section merged, and reads back as itself.
  namespace fs = std::filesystem;
  std::vector<std::string> scenes;
  for (const auto &entry : fs::recursive_directory_iterator(test_support::source_path("parameters")))
    if (entry.path().extension() == ".prm" && entry.path().parent_path().filename() != "studies" &&
        entry.path().parent_path().filename() != "calibration") // study and calibration files
      scenes.push_back(entry.path().string());
  for (const auto &entry : fs::recursive_directory_iterator(test_support::source_path("benchmarks")))
    if (entry.path().extension() == ".prm")
      scenes.push_back(entry.path().string());
  std::printf("[ round trip ] %zu shipped scenes\n", scenes.size());
  EXPECT_GE(scenes.size(), 9u) << "shipped scenes went missing";
  for (const auto &scene : scenes)
    {
      dealii::ParameterHandler first;
      scene::Simulation::declare_parameters(first);
      const auto file = ParameterFile::from_file(first, scene);
      scene::Simulation parsed(first, file);
      const std::string printed = print(first);

      dealii::ParameterHandler second;
      scene::Simulation::declare_parameters(second);
      ParameterFile again(second, printed, "printed.prm", ".");
      scene::Simulation reparsed(second, again);
      EXPECT_EQ(print(second), printed) << scene;
      EXPECT_EQ(reparsed.name(), parsed.name()) << scene;
    }
}

TEST(Parameters, DeclaredDefaultsAreTheInClassDefaults)
{
  dealii::ParameterHandler prm;
  tissue::NewtonParameters::declare(prm);
  prm.enter_subsection("Linear");
  tissue::LinearSolver::Parameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Time");
  TimeParameters::declare(prm, {{"quasi-static", "load stepping"}});
  prm.leave_subsection();
  ParameterFile file(prm, "", "empty.prm", ".");
  const ParameterScope scope(file, "");

  tissue::NewtonParameters newton, newton_default;
  newton.max_iterations = 0;
  newton.parse(prm, scope);
  EXPECT_EQ(newton.max_iterations, newton_default.max_iterations);
  EXPECT_EQ(newton.residual_tolerance, newton_default.residual_tolerance);
  EXPECT_EQ(newton.absolute_residual_tolerance, newton_default.absolute_residual_tolerance);
  EXPECT_EQ(newton.increment_tolerance, newton_default.increment_tolerance);
  EXPECT_EQ(newton.line_search, newton_default.line_search);
  EXPECT_EQ(newton.max_backtracks, newton_default.max_backtracks);

  prm.enter_subsection("Linear");
  tissue::LinearSolver::Parameters linear, linear_default;
  linear.method = "";
  linear.parse(prm, scope);
  prm.leave_subsection();
  EXPECT_EQ(linear.method, linear_default.method);
  EXPECT_EQ(linear.factorization, linear_default.factorization);
  EXPECT_EQ(linear.preconditioner, linear_default.preconditioner);
  EXPECT_EQ(linear.tolerance, linear_default.tolerance);
  EXPECT_EQ(linear.max_iterations, linear_default.max_iterations);

  prm.enter_subsection("Time");
  TimeParameters time, time_default;
  time.end_time = -1;
  time.parse(prm, scope);
  prm.leave_subsection();
  EXPECT_EQ(time.integrator, time_default.integrator);
  EXPECT_EQ(time.end_time, time_default.end_time);
  EXPECT_EQ(time.step_size, time_default.step_size);
  EXPECT_EQ(time.max_cutbacks, time_default.max_cutbacks);
  EXPECT_EQ(time.output_interval, time_default.output_interval);
}

TEST(Parameters, NeedleClosureAndRealtimeDefaultsAreTheInClassDefaults)
{
  // The needle, its puncture and friction laws (declared by coupling/), the closure and
  // the realtime settings declare their defaults through their in-class initialisers: an
  // empty scene parses back to exactly those (a default written twice would drift).
  dealii::ParameterHandler prm;
  scene::NeedleParameters::declare(prm);
  scene::ClosureParameters::declare(prm);
  prm.enter_subsection("Realtime");
  scene::RealtimeSettings::declare(prm);
  prm.leave_subsection();
  ParameterFile        file(prm, "", "empty.prm", ".");
  const ParameterScope root(file, "");

  scene::NeedleParameters needle;
  const scene::NeedleParameters d;
  needle.radius = needle.transverse_stiffness = needle.coupling_tolerance = -1;
  needle.puncture.threshold = needle.friction.mu = needle.pass.bite_depth = -1;
  needle.parse(prm, root);
  EXPECT_EQ(needle.shape, d.shape);
  EXPECT_EQ(needle.radius, d.radius);
  EXPECT_EQ(needle.wire_diameter, d.wire_diameter);
  EXPECT_EQ(needle.attach_suture, d.attach_suture);
  EXPECT_EQ(needle.motion, d.motion);
  EXPECT_EQ(needle.keyframe_text, d.keyframe_text);
  const auto &p = needle.pass, &q = d.pass;
  EXPECT_EQ(p.entry, q.entry);
  EXPECT_EQ(p.normal, q.normal);
  EXPECT_EQ(p.bite_direction, q.bite_direction);
  EXPECT_EQ(p.bite_depth, q.bite_depth);
  EXPECT_EQ(p.entry_angle, q.entry_angle); // pi/2 to the last digit, not deal.II's six
  EXPECT_EQ(p.start_time, q.start_time);
  EXPECT_EQ(p.angular_speed, q.angular_speed);
  EXPECT_EQ(p.approach, q.approach);
  EXPECT_EQ(p.pull, q.pull);
  EXPECT_EQ(p.pull_duration, q.pull_duration);
  EXPECT_EQ(p.tighten, q.tighten);
  EXPECT_EQ(p.tighten_duration, q.tighten_duration);
  EXPECT_EQ(needle.puncture.threshold, d.puncture.threshold);
  EXPECT_EQ(needle.puncture.stiffness, d.puncture.stiffness);
  EXPECT_EQ(needle.puncture.reach, d.puncture.reach);
  EXPECT_EQ(needle.friction.mu, d.friction.mu);
  EXPECT_EQ(needle.friction.stiffness, d.friction.stiffness);
  EXPECT_EQ(needle.friction.grip, d.friction.grip);
  EXPECT_EQ(needle.transverse_stiffness, d.transverse_stiffness);
  EXPECT_EQ(needle.spacing, d.spacing);
  EXPECT_EQ(needle.recorded, d.recorded);
  EXPECT_EQ(needle.enforcement, d.enforcement);
  EXPECT_EQ(needle.coupling_tolerance, d.coupling_tolerance);
  EXPECT_EQ(needle.coupling_iterations, d.coupling_iterations);

  scene::ClosureParameters closure;
  const scene::ClosureParameters c;
  closure.closure_gap = closure.face_contact_stiffness = -1;
  closure.parse(prm, root);
  EXPECT_EQ(closure.pairs.size(), c.pairs.size());
  EXPECT_EQ(closure.closure_gap, c.closure_gap);
  EXPECT_EQ(closure.start_time, c.start_time);
  EXPECT_EQ(closure.tie_off, c.tie_off);
  EXPECT_EQ(closure.tie_off_gap, c.tie_off_gap);
  EXPECT_EQ(closure.tie_off_every_pair, c.tie_off_every_pair);
  EXPECT_EQ(closure.face_contact, c.face_contact);
  EXPECT_EQ(closure.face_contact_stiffness, c.face_contact_stiffness);
  EXPECT_EQ(closure.face_contact_margin, c.face_contact_margin);

  scene::RealtimeSettings realtime;
  const scene::RealtimeSettings r;
  realtime.rate = realtime.contact_depth = realtime.pierce_mass_ratio = realtime.tearing.strength = -1;
  prm.enter_subsection("Realtime");
  realtime.parse(prm, root.subsection("Realtime"));
  prm.leave_subsection();
  EXPECT_EQ(realtime.tissue_model, r.tissue_model);
  EXPECT_EQ(realtime.integrator, r.integrator);
  EXPECT_EQ(realtime.suture_model, r.suture_model);
  EXPECT_EQ(realtime.pierce_model, r.pierce_model);
  EXPECT_EQ(realtime.self_collision, r.self_collision);
  EXPECT_EQ(realtime.pierce_mass_ratio, r.pierce_mass_ratio);
  EXPECT_EQ(realtime.contact, r.contact);
  EXPECT_EQ(realtime.contact_stiffness, r.contact_stiffness);
  EXPECT_EQ(realtime.contact_depth, r.contact_depth);
  EXPECT_EQ(realtime.rate, r.rate);
  EXPECT_EQ(realtime.substeps, r.substeps);
  EXPECT_EQ(realtime.refuse_above_limit, r.refuse_above_limit);
  EXPECT_EQ(realtime.pacing, r.pacing);
  EXPECT_EQ(realtime.tearing.strength, r.tearing.strength);
}

TEST(Parameters, EveryHelpTextNamesAUnitOrChoice)
{
  // --help lists each parameter with its documentation: every numeric entry says its
  // unit ("Unit:"), selections list their choices.
  dealii::ParameterHandler prm;
  scene::Simulation::declare_parameters(prm);
  std::ostringstream out;
  prm.print_parameters(out, dealii::ParameterHandler::JSON);
  const std::string json = out.str();
  std::istringstream in(json);
  nlohmann::json tree = nlohmann::json::parse(json);
  std::vector<std::string> missing;
  std::function<void(const nlohmann::json &, const std::string &)> walk =
    [&](const nlohmann::json &node, const std::string &path) {
      for (auto it = node.begin(); it != node.end(); ++it)
        {
          if (!it->is_object())
            continue;
          if (it->contains("value"))
            {
              const std::string doc     = (*it)["documentation"];
              const std::string pattern = (*it)["pattern_description"];
              const bool selection = pattern.find("Selection") != std::string::npos;
              const bool is_bool   = pattern.find("Bool") != std::string::npos;
              const bool function  = path.find("function") != std::string::npos;
              if (doc.find("Unit:") == std::string::npos && !selection && !is_bool && !function)
                missing.push_back(path + it.key());
            }
          else
            walk(*it, path + it.key() + "/");
        }
    };
  walk(tree, "");
  EXPECT_TRUE(missing.empty()) << ::testing::PrintToString(missing);
}

namespace
{
  /// "Model" (a|b) and Time/{End time, Step size}, as a scene declares them.
  void
  declare_two_paths(dealii::ParameterHandler &prm)
  {
    prm.declare_entry("Model", "a", dealii::Patterns::Selection("a|b"));
    prm.enter_subsection("Time");
    prm.declare_entry("End time", "1", dealii::Patterns::Double(0));
    prm.declare_entry("Step size", "0.1", dealii::Patterns::Double(0));
    prm.leave_subsection();
  }

  const std::string two_paths = "set Model = a\n"             // 1
                                "subsection Time\n"           // 2
                                "  set End time = 2\n"        // 3
                                "  set Step size = 0.5\n"     // 4
                                "end\n"                       // 5
                                "subsection Model b\n"        // 6
                                "  subsection Time\n"         // 7
                                "    set Step size = 0.02\n"  // 8
                                "  end\n"                     // 9
                                "end\n"                       // 10
                                "subsection Model a\n"        // 11
                                "  subsection Time\n"         // 12
                                "    set End time = 3\n"      // 13
                                "  end\n"                     // 14
                                "end\n";                      // 15

  std::pair<double, double>
  times(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Time");
    const std::pair<double, double> t{prm.get_double("End time"), prm.get_double("Step size")};
    prm.leave_subsection();
    return t;
  }
} // namespace

TEST(Parameters, ModelSectionIsReadInItsPathOnlyAndTheCommandLineGoesOverIt)
{
  // the file's Model = a: section a over the common text, section b not read
  {
    dealii::ParameterHandler prm;
    declare_two_paths(prm);
    const ParameterFile file(prm, two_paths, "two.prm", ".");
    EXPECT_EQ(times(prm), std::make_pair(3.0, 0.5));
    EXPECT_EQ(file.line_of("Time/End time"), 13);  // messages name the section's line
    EXPECT_EQ(file.line_of("Time/Step size"), 4);
  }
  // Model = b from the command line selects section b; an override of a key that
  // section b sets goes over the section
  {
    dealii::ParameterHandler prm;
    declare_two_paths(prm);
    const ParameterFile file(prm, two_paths, "two.prm", ".", {"Model=b"});
    EXPECT_EQ(prm.get("Model"), "b");
    EXPECT_EQ(times(prm), std::make_pair(2.0, 0.02));
    EXPECT_EQ(file.line_of("Time/Step size"), 8);
  }
  {
    dealii::ParameterHandler prm;
    declare_two_paths(prm);
    const ParameterFile file(prm, two_paths, "two.prm", ".", {"Model=b", "Time/Step size=0.01"});
    EXPECT_EQ(times(prm), std::make_pair(2.0, 0.01));
  }
}

TEST(Parameters, AModelScopedOverrideIsReadInItsPathOnlyUnderThePlainOnes)
{
  const auto with = [](const std::vector<std::string> &command_line) {
    dealii::ParameterHandler prm;
    declare_two_paths(prm);
    const ParameterFile file(prm, two_paths, "two.prm", ".", command_line);
    return times(prm);
  };
  // "Model b/..." replaces section b's value in path b, and is not read in path a
  EXPECT_EQ(with({"Model=b", "Model b/Time/Step size=0.04"}), std::make_pair(2.0, 0.04));
  EXPECT_EQ(with({"Model b/Time/Step size=0.04"}), std::make_pair(3.0, 0.5));
  // also for a key its section does not set, and for a path without a section
  EXPECT_EQ(with({"Model a/Time/Step size=0.3"}), std::make_pair(3.0, 0.3));
  // a plain override (a case's own setting) goes over it, in either order
  EXPECT_EQ(with({"Model=b", "Time/Step size=0.01", "Model b/Time/Step size=0.04"}), std::make_pair(2.0, 0.01));
  EXPECT_EQ(with({"Model=b", "Model b/Time/Step size=0.04", "Time/Step size=0.01"}), std::make_pair(2.0, 0.01));
  // checked in every path: an unknown model path, key or bad value is an error
  for (const std::string bad : {"Model c/Time/Step size=1", "Model b/Time/Nonsense=1", "Model b/Time/Step size=-1",
                                "Model b/Model=a"})
    {
      std::string message;
      try
        {
          with({bad});
        }
      catch (const InputError &e)
        {
          message = e.what();
        }
      EXPECT_NE(message.find("--set"), std::string::npos) << bad << ": " << message;
    }
}

TEST(Parameters, TheStitchRunsEachPathAtItsOwnResolution)
{
  // parameters/stitch_interrupted.prm: one file, tetrahedra of 1.5 mm and a soft tie in
  // the realtime path, Q1 hexahedra of 2 mm, 20 ms steps and a stiff tie in the accurate
  for (const std::string model : {"realtime", "accurate"})
    {
      dealii::ParameterHandler prm;
      scene::Simulation::declare_parameters(prm);
      ParameterFile::from_file(prm, test_support::source_path("parameters/stitch_interrupted.prm"),
                                      {"Model=" + model});
      prm.enter_subsection("Mesh");
      const std::string geo = prm.get("Geo parameters");
      prm.leave_subsection();
      prm.enter_subsection("Pierce points");
      const double tie = prm.get_double("Transverse stiffness");
      prm.leave_subsection();
      if (model == "realtime")
        {
          EXPECT_EQ(geo, "h: 0.0015, hexahedra: 0, Wg: 0.0004");
          EXPECT_EQ(tie, 500.0);
        }
      else
        {
          EXPECT_EQ(geo, "h: 0.002, hexahedra: 1, Wg: 0.0004");
          EXPECT_EQ(tie, 5e4);
        }
    }
}
