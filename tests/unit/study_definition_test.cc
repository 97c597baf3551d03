// Study files (study/study_definition.h): the cases a study expands to, and one-line
// errors naming the study file's line for what a case could not run with.
#include <suturesim/core/error.h>
#include <suturesim/study/study_definition.h>

#include "run_scene.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

using namespace suturesim;
using namespace suturesim::test_support;

namespace
{
  /// Writes @p text as a study file into the scratch folder and returns the error of
  /// reading it (empty if there was none).
  std::string
  error_of(const std::string &name, const std::string &text)
  {
    const auto dir = scratch_path() / "studies";
    std::filesystem::create_directories(dir);
    const std::string file = (dir / (name + ".prm")).string();
    std::ofstream(file) << text;
    try
      {
        study::StudyDefinition::read(file);
      }
    catch (const InputError &e)
      {
        return e.what();
      }
    return "";
  }

  const std::string header = "set Name = bad\nset Base scene = " + source_path("tests/data/cook_coarse.prm") + "\n";
} // namespace

TEST(StudyDefinition, AxesMultiplyAndListedCasesFollow)
{
  const auto d = study::StudyDefinition::read(source_path("tests/data/studies/cook_small.prm"));
  EXPECT_EQ(d.name, "cook_small");
  EXPECT_EQ(d.base_scene, source_path("tests/data/cook_coarse.prm"));
  ASSERT_EQ(d.references.size(), 1u);
  EXPECT_EQ(d.references[0].name, "reference");
  EXPECT_EQ(d.references[0].settings,
            (std::vector<std::string>{"Tissue/Element degree=2", "Mesh/Elements per edge=8"}));
  ASSERT_EQ(d.cases.size(), 5u);
  const std::vector<std::string> names{"1_0.5", "1_0.25", "2_0.5", "2_0.25", "fine_mesh"};
  for (std::size_t k = 0; k < names.size(); ++k)
    EXPECT_EQ(d.cases[k].name, names[k]);
  EXPECT_EQ(d.cases[1].settings,
            (std::vector<std::string>{"Mesh/Elements per edge=2", "Tissue/Element degree=1", "Time/Step size=0.25"}));
  EXPECT_EQ(d.cases[4].settings,
            (std::vector<std::string>{"Mesh/Elements per edge=2", "Mesh/Elements per edge=4"}));
}

TEST(StudyDefinition, APhysicalAxisGivesEachValueItsOwnReference)
{
  const std::string file = (scratch_path() / "studies" / "per_axis.prm").string();
  std::filesystem::create_directories(scratch_path() / "studies");
  std::ofstream(file) << header
                      << "subsection Reference\n  set Settings = Tissue/Element degree=2\n"
                         "  set Per axis = Time/Step size\nend\n"
                         "subsection Cases\n  set Axes = Tissue/Element degree = 1 | 2; Time/Step size = 0.5 | 0.25\n"
                         "  set List = listed: Time/Step size=0.25\nend\n";
  const auto d = study::StudyDefinition::read(file);
  ASSERT_EQ(d.references.size(), 2u);
  EXPECT_EQ(d.references[0].name, "reference_0.5");
  EXPECT_EQ(d.references[1].name, "reference_0.25");
  EXPECT_EQ(d.references[1].settings, (std::vector<std::string>{"Tissue/Element degree=2", "Time/Step size=0.25"}));
  // each case against the reference of its own step size, the listed one too
  const std::vector<std::pair<std::string, std::size_t>> expected{
    {"1_0.5", 0}, {"1_0.25", 1}, {"2_0.5", 0}, {"2_0.25", 1}, {"listed", 1}};
  ASSERT_EQ(d.cases.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k)
    {
      EXPECT_EQ(d.cases[k].name, expected[k].first);
      EXPECT_EQ(d.cases[k].reference, expected[k].second) << d.cases[k].name;
    }
}

TEST(StudyDefinition, SharedSettingsComeFirstInEveryRun)
{
  const std::string file = (scratch_path() / "studies" / "shared.prm").string();
  std::filesystem::create_directories(scratch_path() / "studies");
  std::ofstream(file) << header << "set Settings = Time/End time=2, Time/Step size=0.5\n"
                      << "subsection Reference\n  set Settings = Tissue/Element degree=2\nend\n"
                         "subsection Cases\n  set Settings = Mesh/Elements per edge=2\n"
                         "  set Axes = Tissue/Element degree = 1 | 2\n  set List = listed: Time/Step size=0.25\nend\n";
  const auto d = study::StudyDefinition::read(file);
  ASSERT_EQ(d.references.size(), 1u);
  EXPECT_EQ(d.references[0].settings,
            (std::vector<std::string>{"Time/End time=2", "Time/Step size=0.5", "Tissue/Element degree=2"}));
  ASSERT_EQ(d.cases.size(), 3u);
  EXPECT_EQ(d.cases[1].settings, (std::vector<std::string>{"Time/End time=2", "Time/Step size=0.5",
                                                           "Mesh/Elements per edge=2", "Tissue/Element degree=2"}));
  // a listed case's own settings go over the shared ones
  EXPECT_EQ(d.cases[2].settings, (std::vector<std::string>{"Time/End time=2", "Time/Step size=0.5",
                                                           "Mesh/Elements per edge=2", "Time/Step size=0.25"}));
  const std::string bad = error_of("bad_shared", header + "set Settings = Tissue/Nonsense=1\n");
  EXPECT_NE(bad.find("bad_shared.prm:3: Settings:"), std::string::npos) << bad;
}

TEST(StudyDefinition, BadStudiesAreOneLineErrorsAtTheirLine)
{
  // line 4 holds the axes in each of these
  const std::string axes = "subsection Cases\n  set Axes = ";
  struct Bad
  {
    std::string name, text, expected;
  };
  const std::vector<Bad> cases{
    {"unknown_path", header + axes + "Tissue/Nonsense = 1 | 2\nend\n", "unknown_path.prm:4: Cases/Axes: case '1'"},
    {"bad_value", header + axes + "Tissue/Element degree = 1 | seven\nend\n", "Cases/Axes: case 'seven'"},
    {"empty_axis", header + axes + "Time/Step size = \nend\n", ":4: Cases/Axes: the axis 'Time/Step size =' has no values"},
    {"too_many", header + axes + "Time/Step size = 1|2|3|4|5|6|7|8|9|10; Time/End time = 1|2|3|4|5|6|7|8|9|10; " +
                   "Tissue/Element degree = 1|2|3|4|5|6|7|8|9|10; Mesh/Elements per edge = 1|2|3|4|5|6|7|8|9|10|11\nend\n",
     ":4: Cases/Axes: the axes give more than 10000 cases"},
    {"no_cases", header, "Cases/Axes (default): the study has no cases"},
    {"same_name", header + "subsection Cases\n  set List = a: Time/Step size=0.5; a: Time/Step size=0.25\nend\n",
     ":4: Cases/List: two cases are named 'a'"},
    {"no_base", "set Name = x\n", "Base scene (default): a study needs a base scene"},
    {"bad_reference", header + "subsection Reference\n  set Settings = Model=nonsense\nend\n",
     ":4: Reference/Settings: case 'reference'"},
    // values each valid, refused by the scene together (as suturesim --validate refuses them)
    {"scene_refuses", header + "subsection Reference\n  set Settings = Mesh/Local refinement/Levels=1\nend\n",
     ":4: Reference/Settings: case 'reference': --set Mesh/Local refinement/Levels: refinement needs Near "
     "boundaries or Near needle path"},
    {"unmatched", header + "subsection Reference\n  set Per axis = Time/Step size\nend\n" +
                    "subsection Cases\n  set List = a: Time/Step size=0.5; b: Time/End time=2\nend\n",
     ":4: Reference/Per axis: case 'b' does not set 'Time/Step size', so it has no reference"},
    // a failed reference is reported only where each case has its own
    {"report_one_reference", header + "subsection Reference\n  set On failure = report\nend\n" + axes +
                               "Time/Step size = 0.5 | 0.25\nend\n",
     ":4: Reference/On failure: 'report' needs 'Per axis'"},
    // a map over two axes with at least one metric; a metric entry names a metric on each side
    {"map_not_an_axis", header + axes + "Time/Step size = 0.5 | 0.25\nend\nsubsection Figures\n set Map axes = "
                          "Time/Step size; Time/End time\n set Map metrics = closure_tension\nend\n",
     ":7: Figures/Map axes: 'Time/End time' is not an axis of Cases/Axes"},
    {"map_one_axis", header + axes + "Time/Step size = 0.5 | 0.25\nend\nsubsection Figures\n set Map axes = "
                       "Time/Step size\n set Map metrics = closure_tension\nend\n",
     ":7: Figures/Map axes: needs two axes"},
    {"map_no_metric", header + axes + "Time/Step size = 0.5 | 0.25; Time/End time = 1 | 2\nend\nsubsection Figures\n"
                        " set Map axes = Time/Step size; Time/End time\nend\n",
     "Figures/Map metrics (default): a map needs both its two axes and at least one metric"},
    {"map_half_metric", header + axes + "Time/Step size = 0.5 | 0.25; Time/End time = 1 | 2\nend\nsubsection "
                          "Figures\n set Map axes = Time/Step size; Time/End time\n set Map metrics = a: \nend\n",
     ":8: Figures/Map metrics: 'a:' names no metric"},
    {"flags_without_map", header + axes + "Time/Step size = 0.5 | 0.25\nend\nsubsection Figures\n set Map flags = "
                            "stitch_evaluation.too_close_to_edge\nend\n",
     ":7: Figures/Map flags: flags need a map"},
  };
  for (const auto &c : cases)
    {
      const std::string what = error_of(c.name, c.text);
      std::printf("[ study error ] %s\n", what.c_str());
      EXPECT_NE(what.find(c.expected), std::string::npos) << c.name << ": " << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << c.name << ": " << what;
    }
}
