// The suture presets (`Suture/Preset`, rod/cross_section.h preset_table()): each sets the
// section's radius, Young's modulus, Poisson's ratio and density to the values its
// sources give, documented in --help; a value set next to a preset that contradicts it
// is a one-line input error naming the key.
// Sources (references.md, "Suture"): USP diameters 2-0 0.250–0.299, 3-0 0.200–0.249,
// 4-0 0.150–0.199, 5-0 0.100–0.149, 6-0 0.070–0.079 mm, the preset takes the middle of
// the range; monofilament nylon/polypropylene moduli of order 1–5 GPa (3 GPa taken);
// silk 8.7 GPa initial modulus (Naleway et al. 2015, J Biomed Mater Res B 103:735).
// Densities (nylon 6 1140, silk fibroin 1300 kg/m³) and ν = 0.4 are handbook values
// cross_section.cc states.
#include "run_scene.h"

#include <suturesim/core/error.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/rod/cross_section.h>
#include <suturesim/rod/rod_parameters.h>

#include <deal.II/base/parameter_handler.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

using namespace suturesim;

namespace
{
  /// USP diameter range per size, m (references.md).
  const std::map<std::string, std::pair<double, double>> usp{{"2-0", {0.250e-3, 0.299e-3}},
                                                             {"3-0", {0.200e-3, 0.249e-3}},
                                                             {"4-0", {0.150e-3, 0.199e-3}},
                                                             {"5-0", {0.100e-3, 0.149e-3}},
                                                             {"6-0", {0.070e-3, 0.079e-3}}};

  /// The Suture section parsed from @p body (the inside of "subsection Suture"), with the
  /// values the handler holds afterwards (what parameters.prm records).
  rod::RodParameters
  parse(const std::string &body, std::map<std::string, double> *recorded = nullptr,
        const std::vector<std::string> &command_line = {})
  {
    dealii::ParameterHandler prm;
    prm.enter_subsection("Suture");
    rod::RodParameters::declare(prm);
    prm.leave_subsection();
    const ParameterFile  file(prm, "subsection Suture\n" + body + "end\n", "preset.prm", ".", command_line);
    const ParameterScope root(file, "");
    rod::RodParameters   rp;
    prm.enter_subsection("Suture");
    rp.parse(prm, root.subsection("Suture"));
    prm.enter_subsection("Cross section");
    if (recorded)
      for (const char *key : {"Radius", "Young's modulus", "Poisson's ratio", "Density"})
        (*recorded)[key] = prm.get_double(key);
    prm.leave_subsection();
    prm.leave_subsection();
    return rp;
  }
} // namespace

TEST(SuturePreset, EveryPresetTakesItsSourcesValues)
{
  const auto &table = rod::preset_table();
  EXPECT_EQ(table.size(), 10u); // five USP sizes, monofilament and silk each
  unsigned checked = 0;
  for (const auto &p : table)
    {
      const std::string size = p.name.substr(0, p.name.find(' ')), kind = p.name.substr(p.name.find(' ') + 1);
      ASSERT_TRUE(usp.count(size)) << p.name;
      ASSERT_TRUE(kind == "monofilament" || kind == "silk") << p.name;
      const auto [low, high] = usp.at(size);
      EXPECT_NEAR(p.diameter, 0.5 * (low + high), 1e-12) << p.name;
      EXPECT_EQ(p.E, kind == "silk" ? 8.7e9 : 3e9) << p.name;
      EXPECT_EQ(p.density, kind == "silk" ? 1300.0 : 1140.0) << p.name;
      EXPECT_EQ(p.nu, 0.4) << p.name;
      EXPECT_FALSE(p.source.empty()) << p.name;

      // parsed, the section takes them, and the handler records them
      std::map<std::string, double> recorded;
      const auto rp = parse(" set Preset = " + p.name + "\n", &recorded);
      EXPECT_EQ(rp.section.radius, p.diameter / 2) << p.name;
      EXPECT_EQ(rp.section.E, p.E) << p.name;
      EXPECT_EQ(rp.section.nu, p.nu) << p.name;
      EXPECT_EQ(rp.section.density, p.density) << p.name;
      EXPECT_EQ(recorded["Radius"], p.diameter / 2) << p.name;
      EXPECT_EQ(recorded["Young's modulus"], p.E) << p.name;
      EXPECT_EQ(recorded["Density"], p.density) << p.name;
      // and the preset's own value given again is no contradiction (parameters.prm reads back)
      std::ostringstream radius;
      radius << std::setprecision(17) << p.diameter / 2;
      EXPECT_NO_THROW(parse(" set Preset = " + p.name + "\n subsection Cross section\n  set Radius = " + radius.str() +
                            "\n end\n"))
        << p.name;
      ++checked;
    }
  EXPECT_EQ(checked, table.size());
}

TEST(SuturePreset, HelpListsEveryPresetWithItsValues)
{
  const auto r = test_support::run_suturesim("preset_help", {"--help"});
  ASSERT_EQ(r.exit_code, 0);
  // the help text is wrapped into comment lines: compare without the comment marks,
  // white space collapsed
  std::string help = r.output;
  std::replace(help.begin(), help.end(), '#', ' ');
  help = one_line(help);
  unsigned listed = 0;
  for (const auto &p : rod::preset_table())
    {
      std::ostringstream entry;
      entry << p.name << ": d = " << p.diameter * 1e3 << " mm, E = " << p.E / 1e9 << " GPa, nu = " << p.nu
            << ", density = " << p.density << " kg/m^3 (" << p.source << ")";
      EXPECT_NE(help.find(entry.str()), std::string::npos) << entry.str();
      ++listed;
    }
  EXPECT_EQ(listed, 10u);
  EXPECT_NE(help.find("2-0 monofilament: d = 0.2745 mm, E = 3 GPa"), std::string::npos); // as a reader gives it
  EXPECT_NE(help.find("Naleway et al. 2015"), std::string::npos);
}

TEST(SuturePreset, AValueThatContradictsThePresetIsAOneLineError)
{
  unsigned refused = 0;
  for (const auto &[key, value] : std::vector<std::pair<std::string, std::string>>{
         {"Radius", "0.0002"}, {"Young's modulus", "2e9"}, {"Poisson's ratio", "0.3"}, {"Density", "1000"}})
    {
      std::string message;
      try
        {
          parse(" set Preset = 4-0 silk\n subsection Cross section\n  set " + key + " = " + value + "\n end\n");
        }
      catch (const InputError &e)
        {
          message = e.what();
        }
      EXPECT_NE(message.find("preset.prm:4: Suture/Cross section/" + key + ": is set by 'Preset = 4-0 silk'"),
                std::string::npos)
        << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      ++refused;
    }
  EXPECT_EQ(refused, 4u);
}

TEST(SuturePreset, ACommandLineValueThatContradictsThePresetIsAnErrorToo)
{
  // a study's axis over the modulus is a --set: the preset must not win silently
  std::string message;
  try
    {
      parse(" set Preset = 3-0 monofilament\n", nullptr, {"Suture/Cross section/Young's modulus=1e9"});
    }
  catch (const InputError &e)
    {
      message = e.what();
    }
  EXPECT_NE(message.find("--set Suture/Cross section/Young's modulus: is set by 'Preset = 3-0 monofilament'"),
            std::string::npos)
    << message;
  // with the preset's own value it is no contradiction
  EXPECT_NO_THROW(parse(" set Preset = 3-0 monofilament\n", nullptr, {"Suture/Cross section/Young's modulus=3e9"}));
}
