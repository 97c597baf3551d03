#include <suturesim/core/error.h>
#include <suturesim/scene/parameter_file.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#ifndef SUTURESIM_SOURCE_DIR
#  define SUTURESIM_SOURCE_DIR "."
#endif

namespace suturesim::scene
{
  namespace
  {
    std::string
    trim(const std::string &s)
    {
      const auto b = s.find_first_not_of(" \t\r");
      if (b == std::string::npos)
        return "";
      const auto e = s.find_last_not_of(" \t\r");
      return s.substr(b, e - b + 1);
    }

    /// Maps each "set Key = value" of the text to its line, tracking subsections. This is
    /// a locator for messages, not a parser: deal.II has parsed and validated the text
    /// before it is used.
    std::map<std::string, int>
    locate_keys(const std::string &text)
    {
      std::map<std::string, int> lines;
      std::vector<std::string>   stack;
      std::istringstream         in(text);
      std::string                line;
      int                        number = 0;
      while (std::getline(in, line))
        {
          ++number;
          line = trim(line.substr(0, line.find('#')));
          if (line.rfind("subsection ", 0) == 0)
            stack.push_back(trim(line.substr(11)));
          else if (line == "end" && !stack.empty())
            stack.pop_back();
          else if (line.rfind("set ", 0) == 0)
            {
              const auto  eq  = line.find('=');
              std::string key = trim(line.substr(4, eq == std::string::npos ? eq : eq - 4));
              std::string path;
              for (const auto &s : stack)
                path += s + "/";
              lines[path + key] = number;
            }
        }
      return lines;
    }

    /// deal.II's parse messages span several lines and say "Line <n> of file <f>"; the
    /// user gets "f:n: what is wrong".
    std::string
    reformat(const dealii::ExceptionBase &e, const std::string &file_name)
    {
      std::ostringstream info;
      e.print_info(info);
      std::string       text = one_line(info.str());
      const std::regex  located(R"(^Line <(\d+)> of file <(.*?)>?:\s*(.*)$)");
      std::smatch       m;
      if (std::regex_match(text, m, located))
        {
          std::string rest = m[3];
          // "The entry value X for the entry named K does not match the given pattern: P"
          const std::regex pattern(
            R"(The entry value (.*) for the entry named (.*) does not match the given pattern: (.*))");
          std::smatch p;
          if (std::regex_match(rest, p, pattern))
            rest = std::string(p[2]) + ": value '" + std::string(p[1]) +
                   "' does not match " + std::string(p[3]);
          return file_name + ":" + std::string(m[1]) + ": " + rest;
        }
      return file_name + ": " + text;
    }
  } // namespace

  ParameterFile::ParameterFile(dealii::ParameterHandler &prm,
                               const std::string        &text,
                               const std::string        &name,
                               const std::string        &directory)
    : file_name(name)
    , directory(directory)
    , lines(locate_keys(text))
  {
    try
      {
        prm.parse_input_from_string(text, name);
      }
    catch (const dealii::ExceptionBase &e)
      {
        throw InputError(reformat(e, name));
      }
  }

  ParameterFile
  ParameterFile::from_file(dealii::ParameterHandler &prm, const std::string &file_name)
  {
    std::ifstream in(file_name);
    if (!in)
      throw InputError(file_name + ": cannot open the scene file");
    std::stringstream buffer;
    buffer << in.rdbuf();
    const auto parent = std::filesystem::path(file_name).parent_path().string();
    return ParameterFile(prm, buffer.str(), file_name, parent.empty() ? "." : parent);
  }

  void
  ParameterFile::apply_override(dealii::ParameterHandler &prm, const std::string &assignment)
  {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos)
      throw InputError("--set \"" + assignment + "\": expected \"Subsection/Key=value\"");
    const std::string path  = trim(assignment.substr(0, eq));
    const std::string value = trim(assignment.substr(eq + 1));

    std::vector<std::string> parts;
    std::stringstream        ss(path);
    for (std::string part; std::getline(ss, part, '/');)
      parts.push_back(trim(part));

    if (parts.empty() || std::any_of(parts.begin(), parts.end(),
                                     [](const std::string &part) { return part.empty(); }))
      throw InputError("--set \"" + assignment + "\": expected \"Subsection/Key=value\"");
    unsigned int entered = 0;
    try
      {
        for (std::size_t i = 0; i + 1 < parts.size(); ++i, ++entered)
          {
            // enter_subsection() would create an undeclared subsection silently.
            if (!prm.subsection_path_exists({parts[i]}))
              throw InputError("--set \"" + assignment + "\": no subsection '" +
                               parts[i] + "'");
            prm.enter_subsection(parts[i]);
          }
        prm.set(parts.back(), value);
      }
    catch (const dealii::ExceptionBase &e)
      {
        for (; entered > 0; --entered)
          prm.leave_subsection();
        std::ostringstream info;
        e.print_info(info);
        throw InputError("--set \"" + assignment + "\": " + one_line(info.str()));
      }
    catch (...)
      {
        for (; entered > 0; --entered)
          prm.leave_subsection();
        throw;
      }
    for (; entered > 0; --entered)
      prm.leave_subsection();
    overrides.push_back(path);
  }

  int
  ParameterFile::line_of(const std::string &path) const
  {
    const auto it = lines.find(path);
    return it == lines.end() ? 0 : it->second;
  }

  void
  ParameterFile::fail(const std::string &path, const std::string &problem) const
  {
    for (const auto &o : overrides)
      if (o == path)
        throw InputError("--set " + path + ": " + problem);
    const int line = line_of(path);
    throw InputError(file_name + (line > 0 ? ":" + std::to_string(line) : "") + ": " + path +
                     (line > 0 ? "" : " (default)") + ": " + problem);
  }

  std::string
  ParameterFile::resolve(const std::string &path) const
  {
    namespace fs = std::filesystem;
    if (fs::path(path).is_absolute())
      return path;
    const fs::path local = fs::path(directory) / path;
    if (fs::exists(local))
      return local.lexically_normal().string();
    const fs::path project = fs::path(SUTURESIM_SOURCE_DIR) / path;
    if (fs::exists(project))
      return project.lexically_normal().string();
    return local.lexically_normal().string();
  }

  const dealii::Patterns::List &
  vector_pattern()
  {
    static const dealii::Patterns::List pattern(dealii::Patterns::Double(), 3, 3, ",");
    return pattern;
  }

  Eigen::Vector3d
  get_vector(const dealii::ParameterHandler &prm, const std::string &key)
  {
    const auto v = dealii::Utilities::string_to_double(dealii::Utilities::split_string_list(prm.get(key), ','));
    return {v[0], v[1], v[2]};
  }

  std::vector<std::pair<std::string, std::vector<double>>>
  get_named_values(const dealii::ParameterHandler &prm, const std::string &key)
  {
    std::vector<std::pair<std::string, std::vector<double>>> entries;
    for (const auto &item : dealii::Utilities::split_string_list(prm.get(key), ';'))
      {
        const auto colon = item.find(':');
        entries.emplace_back(dealii::Utilities::trim(item.substr(0, colon)),
                             dealii::Utilities::string_to_double(
                               dealii::Utilities::split_string_list(item.substr(colon + 1), ',')));
      }
    return entries;
  }

  std::map<double, std::vector<double>>
  get_keyframes(const dealii::ParameterHandler &prm, const std::string &key, const ParameterScope &scope)
  {
    std::map<double, std::vector<double>> keyframes;
    for (const auto &[time, v] : get_named_values(prm, key))
      scope.require(keyframes.emplace(dealii::Utilities::string_to_double(time), v).second, key,
                    "time " + time + " appears twice");
    return keyframes;
  }
} // namespace suturesim::scene
