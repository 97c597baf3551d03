#include <suturesim/core/error.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/scene/simulation.h>
#include <suturesim/study/study_definition.h>

#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <cctype>
#include <set>

namespace suturesim::study
{
  using dealii::ParameterHandler;
  using dealii::Patterns::Anything;

  namespace
  {
    std::string
    trim(const std::string &s)
    {
      const auto a = s.find_first_not_of(" \t");
      const auto b = s.find_last_not_of(" \t");
      return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
    }

    /// The non-empty trimmed parts of @p text between @p separator.
    std::vector<std::string>
    split(const std::string &text, const char separator)
    {
      std::vector<std::string> parts;
      std::size_t              start = 0;
      while (start <= text.size())
        {
          const auto end  = std::min(text.find(separator, start), text.size());
          const auto part = trim(text.substr(start, end - start));
          if (!part.empty())
            parts.push_back(part);
          start = end + 1;
        }
      return parts;
    }

    std::string
    file_name_part(const std::string &value)
    {
      std::string name;
      for (const char c : value)
        name += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-') ? c : '_';
      return name;
    }

    void
    declare(ParameterHandler &prm)
    {
      prm.declare_entry("Name", "", Anything(), "The study's name (its output folder by default). Unit: none.");
      prm.declare_entry("Base scene", "", Anything(),
                        "The scene every case starts from; relative to the study file's folder. Unit: none.");
      prm.enter_subsection("Reference");
      prm.declare_entry("Settings", "", Anything(),
                        "Settings of the reference case over the base scene: \"Path/Key=value\", "
                        "separated by commas. Unit: none.");
      prm.leave_subsection();
      prm.enter_subsection("Cases");
      prm.declare_entry("Settings", "", Anything(),
                        "Settings every case shares, as for the reference. Unit: none.");
      prm.declare_entry("Axes", "", Anything(),
                        "Axes whose product gives the cases: \"Path/Key = v1 | v2 | ...\", separated by "
                        "semicolons. Unit: none.");
      prm.declare_entry("List", "", Anything(),
                        "Further cases: \"name: Path/Key=value, ...\", separated by semicolons. Unit: none.");
      prm.leave_subsection();
    }

    /// The product of @p axes (each "Path/Key = v1 | v2"), after @p common.
    std::vector<Case>
    product(const std::vector<std::string> &axes, const std::vector<std::string> &common,
            const ParameterScope &scope)
    {
      std::vector<Case> cases{{"", common}};
      for (const auto &axis : axes)
        {
          const auto equals = axis.find('=');
          scope.require(equals != std::string::npos, "Axes", "'" + axis + "' is not 'Path/Key = v1 | v2'");
          const std::string path   = trim(axis.substr(0, equals));
          const auto        values = split(axis.substr(equals + 1), '|');
          scope.require(!path.empty() && !values.empty(), "Axes", "the axis '" + axis + "' has no values");
          std::vector<Case> next;
          for (const auto &c : cases)
            for (const auto &v : values)
              {
                Case n = c;
                n.name += (n.name.empty() ? "" : "_") + file_name_part(v);
                n.settings.push_back(path + "=" + v);
                next.push_back(n);
              }
          cases = next;
        }
      return axes.empty() ? std::vector<Case>{} : cases;
    }

    std::vector<Case>
    listed(const std::string &text, const std::vector<std::string> &common, const ParameterScope &scope)
    {
      std::vector<Case> cases;
      for (const auto &item : split(text, ';'))
        {
          const auto colon = item.find(':');
          scope.require(colon != std::string::npos && colon > 0, "List", "'" + item + "' is not 'name: settings'");
          Case c{file_name_part(trim(item.substr(0, colon))), common};
          for (const auto &s : split(item.substr(colon + 1), ','))
            c.settings.push_back(s);
          cases.push_back(c);
        }
      return cases;
    }

    /// Applies @p c to the base scene as the run will; a bad setting is an error at
    /// the study file's @p key.
    void
    check(const Case &c, const std::string &scene, const ParameterScope &scope, const std::string &key)
    {
      ParameterHandler prm;
      scene::Simulation::declare_parameters(prm);
      try
        {
          ParameterFile::from_file(prm, scene, c.settings);
        }
      catch (const InputError &e)
        {
          scope.fail(key, "case '" + c.name + "': " + e.what());
        }
    }
  } // namespace

  StudyDefinition
  StudyDefinition::read(const std::string &study_file)
  {
    ParameterHandler prm;
    declare(prm);
    const auto           file = ParameterFile::from_file(prm, study_file);
    const ParameterScope top(file, "");
    StudyDefinition      d;
    d.file = study_file;
    d.name = prm.get("Name");
    top.require(!d.name.empty(), "Name", "a study needs a name");
    const std::string base = prm.get("Base scene");
    top.require(!base.empty(), "Base scene", "a study needs a base scene");
    d.base_scene = file.resolve(base);

    prm.enter_subsection("Reference");
    d.reference = {"reference", split(prm.get("Settings"), ',')};
    prm.leave_subsection();
    check(d.reference, d.base_scene, top.subsection("Reference"), "Settings");

    prm.enter_subsection("Cases");
    const ParameterScope cases = top.subsection("Cases");
    const auto           common = split(prm.get("Settings"), ',');
    d.cases                     = product(split(prm.get("Axes"), ';'), common, cases);
    const std::size_t from_axes = d.cases.size();
    for (auto &c : listed(prm.get("List"), common, cases))
      d.cases.push_back(c);
    prm.leave_subsection();
    cases.require(!d.cases.empty(), "Axes", "the study has no cases (no axes and no list)");

    std::set<std::string> names{"reference"};
    for (std::size_t k = 0; k < d.cases.size(); ++k)
      {
        const std::string key = k < from_axes ? "Axes" : "List";
        cases.require(names.insert(d.cases[k].name).second, key, "two cases are named '" + d.cases[k].name + "'");
        check(d.cases[k], d.base_scene, cases, key);
      }
    return d;
  }
} // namespace suturesim::study
