// Parameters: declare → print → parse round trip of the whole scene tree, and the
// defaults declared through the in-class initialisers parse back to those initialisers
// (conventions.md §2).
#include <suturesim/core/parameter_file.h>
#include <suturesim/scene/simulation.h>
#include <suturesim/tissue/linear_solver.h>
#include <suturesim/tissue/time_integrator.h>
#include <suturesim/tissue/tissue_model.h>

#include <gtest/gtest.h>

#include "run_scene.h"

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
  for (const std::string scene :
       {"parameters/skin_pad_pull.prm", "benchmarks/cook_membrane/cook_membrane.prm",
        "benchmarks/block_patch_load/block_patch_load.prm",
        // with model sections: the printed state is the common text and the chosen
        // section merged, and reads back as itself
        "parameters/stitch_interrupted.prm"})
    {
      dealii::ParameterHandler first;
      scene::Simulation::declare_parameters(first);
      const auto file = ParameterFile::from_file(first, test_support::source_path(scene));
      scene::Simulation parsed(first, file);
      const std::string printed = print(first);

      dealii::ParameterHandler second;
      scene::Simulation::declare_parameters(second);
      ParameterFile again(second, printed, "printed.prm", ".");
      scene::Simulation reparsed(second, again);
      EXPECT_EQ(print(second), printed) << scene;
      EXPECT_EQ(reparsed.name(), parsed.name());
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
  tissue::TimeParameters::declare(prm);
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
  tissue::TimeParameters time, time_default;
  time.end_time = -1;
  time.parse(prm, scope);
  prm.leave_subsection();
  EXPECT_EQ(time.integrator, time_default.integrator);
  EXPECT_EQ(time.end_time, time_default.end_time);
  EXPECT_EQ(time.step_size, time_default.step_size);
  EXPECT_EQ(time.max_cutbacks, time_default.max_cutbacks);
  EXPECT_EQ(time.output_interval, time_default.output_interval);
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
