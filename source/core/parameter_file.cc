#include <suturesim/core/error.h>
#include <suturesim/core/parameter_file.h>

#include <deal.II/base/utilities.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#ifndef SUTURESIM_SOURCE_DIR
#  define SUTURESIM_SOURCE_DIR "."
#endif

namespace suturesim
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

    /// Whether @p text is valid UTF-8: nlohmann::json refuses to write any other, and
    /// every name of a scene reaches summary.json.
    bool
    valid_utf8(const std::string &text)
    {
      try
        {
          (void)nlohmann::json(text).dump();
          return true;
        }
      catch (const nlohmann::json::type_error &)
        {
          return false;
        }
    }

    /// The longest line a scene may have, in bytes: far above any setting's (a polyline
    /// of a thousand points), far below what would make the parse's memory or the
    /// messages that quote a value unbounded.
    constexpr std::size_t max_line_length = 65536;

    /// Refuses a line of @p text that is not UTF-8 or longer than max_line_length, naming it.
    void
    check_lines(const std::string &text, const std::string &file_name)
    {
      std::istringstream in(text);
      int                number = 0;
      for (std::string line; std::getline(in, line);)
        {
          const std::string here = file_name + ":" + std::to_string(++number) + ": ";
          if (line.size() > max_line_length)
            throw InputError(here + "the line is " + std::to_string(line.size()) + " characters long (at most " +
                             std::to_string(max_line_length) + ")");
          if (!valid_utf8(line))
            throw InputError(here + "the line is not valid UTF-8 text");
        }
    }

    /// Follows the "include <file>" lines of @p text as deal.II will (the file name
    /// relative to the working folder) and refuses a file that includes itself, directly
    /// or through others, or includes nested deeper than 8: deal.II recurses until the
    /// stack overflows.
    void
    check_includes(const std::string &text, const std::string &file_name, std::vector<std::string> &chain)
    {
      std::istringstream in(text);
      int                number = 0;
      for (std::string line; std::getline(in, line);)
        {
          ++number;
          line = trim(line.substr(0, line.find('#')));
          if (line.rfind("include ", 0) != 0 && line.rfind("INCLUDE ", 0) != 0)
            continue;
          const std::string included = trim(line.substr(8));
          const std::string here = file_name + ":" + std::to_string(number) + ": include " + included + ": ";
          std::error_code   error;
          if (std::filesystem::is_directory(included, error))
            throw InputError(here + "is a folder, not a parameter file"); // deal.II read nothing from it
          std::ifstream file(included);
          if (!file)
            continue; // deal.II names the file it cannot open
          const std::string key = std::filesystem::weakly_canonical(included, error).string();
          std::string       path;
          for (const auto &c : chain)
            path += c + " -> ";
          if (std::find(chain.begin(), chain.end(), key) != chain.end())
            throw InputError(here + "the file includes itself (" + path + key + ")");
          if (chain.size() >= 8)
            throw InputError(here + "includes nest deeper than 8 files");
          std::stringstream buffer;
          buffer << file.rdbuf();
          chain.push_back(key);
          check_includes(buffer.str(), included, chain);
          chain.pop_back();
        }
    }

    /// @p text as a number the way deal.II's get_double() and get_integer() read it
    /// (strtod or strtol over the whole text, no range error) and finite; nullopt if it
    /// is not one.
    std::optional<double>
    number(const std::string &text, const bool integer = false)
    {
      const std::string t = trim(text);
      if (t.empty())
        return std::nullopt;
      errno       = 0;
      char *end   = nullptr;
      const double value = integer ? static_cast<double>(std::strtol(t.c_str(), &end, 10)) : std::strtod(t.c_str(), &end);
      if (errno != 0 || end != t.c_str() + t.size() || !std::isfinite(value))
        return std::nullopt;
      return value;
    }

    /// The comma-separated numbers of @p text (the value of @p key), each as number()
    /// reads it; an InputError naming @p key for one that is not.
    std::vector<double>
    get_numbers(const std::string &text, const std::string &key)
    {
      std::vector<double> values;
      for (const auto &item : dealii::Utilities::split_string_list(text, ','))
        {
          const auto x = number(item);
          if (!x)
            throw InputError(key + ": '" + item + "' in '" + text + "' is not a finite number within the machine's range");
          values.push_back(*x);
        }
      return values;
    }

    /// Every entry below @p node (deal.II's JSON print of a ParameterHandler), each paired
    /// with its path: what check_numbers() sorts by pattern.
    void
    numeric_entries(const nlohmann::json &node, const std::string &path,
                    std::vector<std::pair<std::string, const nlohmann::json *>> &out)
    {
      for (const auto &[name, child] : node.items())
        if (child.is_object() && child.contains("value") && child.contains("pattern_description"))
          out.emplace_back(path + name, &child);
        else if (child.is_object())
          numeric_entries(child, path + name + "/", out);
    }

    /// The bounds that the documentation of an entry states ("... Range: (0, 1).",
    /// "Range: >= 0."), where its Pattern cannot: an open bound, or none at all.
    struct DocumentedRange
    {
      double lower = -std::numeric_limits<double>::infinity(), upper = std::numeric_limits<double>::infinity();
      bool   lower_open = false, upper_open = false;
      std::string text; ///< as documented
    };

    /// The range of @p documentation's last "Range: ..." when it is an interval of two
    /// numbers or one comparison with a number; nullopt for any other form (integer
    /// ranges "1-30" are the Pattern's, words such as "pi/2" are not read).
    std::optional<DocumentedRange>
    documented_range(const std::string &documentation)
    {
      const auto at = documentation.rfind("Range: ");
      if (at == std::string::npos)
        return std::nullopt;
      std::string r = trim(documentation.substr(at + 7));
      if (!r.empty() && r.back() == '.')
        r.pop_back();
      DocumentedRange range;
      range.text = r;
      if (!r.empty() && (r[0] == '(' || r[0] == '['))
        {
          const auto comma = r.find(',');
          const char close = r.back();
          if (comma == std::string::npos || (close != ')' && close != ']'))
            return std::nullopt;
          const auto lo = number(r.substr(1, comma - 1)), hi = number(r.substr(comma + 1, r.size() - comma - 2));
          if (!lo || !hi)
            return std::nullopt;
          range.lower      = *lo;
          range.upper      = *hi;
          range.lower_open = r[0] == '(';
          range.upper_open = close == ')';
          return range;
        }
      for (const std::string op : {">=", "<=", ">", "<"})
        if (r.rfind(op, 0) == 0)
          {
            const auto x = number(r.substr(op.size()));
            if (!x)
              return std::nullopt;
            (op[0] == '>' ? range.lower : range.upper)           = *x;
            (op[0] == '>' ? range.lower_open : range.upper_open) = op.size() == 1;
            return range;
          }
      return std::nullopt;
    }

    /// Every Double and Integer entry, and every list of them, read as get_double() and
    /// get_integer() will read it: a pattern accepts texts they refuse (a denormal such as
    /// 4.9e-324 matches Patterns::Double, and strtod reports its underflow), and their
    /// refusal is an exception that names no file, line or entry.
    void
    check_numbers(const dealii::ParameterHandler &prm, const ParameterFile &file)
    {
      std::ostringstream print;
      prm.print_parameters(print, dealii::ParameterHandler::JSON);
      std::vector<std::pair<std::string, const nlohmann::json *>> entries;
      const nlohmann::json tree = nlohmann::json::parse(print.str());
      numeric_entries(tree, "", entries);
      for (const auto &[path, entry] : entries)
        {
          const std::string pattern = entry->at("pattern_description").get<std::string>();
          const std::string value   = entry->at("value").get<std::string>();
          const bool        list    = pattern.rfind("[List of <[", 0) == 0;
          const std::string element = list ? pattern.substr(11) : pattern.substr(1);
          const bool        integer = element.rfind("Integer", 0) == 0;
          if (!integer && element.rfind("Double", 0) != 0)
            continue;
          std::vector<std::string> items{value};
          if (list)
            {
              const auto        by  = pattern.rfind(" separated by <");
              const std::string sep = by == std::string::npos ? "," : pattern.substr(by + 15, pattern.size() - by - 17);
              items = dealii::Utilities::split_string_list(value, sep);
            }
          for (const auto &item : items)
            if (!number(item, integer))
              file.fail(path, "value '" + item + "' is not " + (integer ? "an integer" : "a finite number") +
                                " within the machine's range (" +
                                (integer ? "a 64-bit integer)" : "magnitude 0 or 2.2e-308 to 1.8e308)"));
          // a value the scene gives must lie in the range its documentation states:
          // Patterns::Double(0, 1) accepts 0 and 1 where the range is (0, 1)
          // (a default is not checked: a few mean "off" or "automatic" outside the range)
          const bool default_value = entry->contains("default_value") && entry->at("default_value") == entry->at("value");
          const auto range = list || default_value || !file.given(path) || !entry->contains("documentation")
                               ? std::nullopt
                               : documented_range(entry->at("documentation").get<std::string>());
          if (range)
            {
              const double x = *number(value, integer);
              if (x < range->lower || x > range->upper || (range->lower_open && x == range->lower) ||
                  (range->upper_open && x == range->upper))
                file.fail(path, "value " + value + " is outside its range " + range->text);
            }
        }
    }

    /// Maps each "set Key = value" of the text to its line, tracking subsections. This is
    /// a locator for messages, not a parser: deal.II has parsed and validated the text
    /// before it is used. A key set twice is refused with both lines: deal.II would keep
    /// the last silently, and the reader of the file sees the first.
    std::map<std::string, int>
    locate_keys(const std::string &text, const std::string &file_name)
    {
      std::map<std::string, int> lines;
      std::vector<std::string>   stack;
      std::vector<int>           opened; // the line of each subsection on the stack
      std::istringstream         in(text);
      std::string                line;
      int                        number = 0;
      while (std::getline(in, line))
        {
          ++number;
          line = trim(line.substr(0, line.find('#')));
          if (line.rfind("subsection ", 0) == 0)
            {
              stack.push_back(trim(line.substr(11)));
              opened.push_back(number);
            }
          else if (line == "end" && !stack.empty())
            {
              stack.pop_back();
              opened.pop_back();
            }
          else if (line.rfind("set ", 0) == 0)
            {
              const auto  eq  = line.find('=');
              std::string key = trim(line.substr(4, eq == std::string::npos ? eq : eq - 4));
              std::string path;
              for (const auto &s : stack)
                path += s + "/";
              const auto [first, added] = lines.emplace(path + key, number);
              if (!added)
                throw InputError(file_name + ":" + std::to_string(number) + ": " + path + key +
                                 ": set a second time (first on line " + std::to_string(first->second) +
                                 "); set each key once");
            }
        }
      // deal.II says only that the counts differ, of "<input string>"
      if (!stack.empty())
        throw InputError(file_name + ":" + std::to_string(opened.back()) + ": 'subsection " + stack.back() +
                         "' has no 'end'");
      return lines;
    }

    /// One top-level "subsection Model <name> ... end" of a scene file: settings read
    /// only when Model = <name>. Its text keeps the file's line count (everything
    /// outside its body blank) so that deal.II's messages give the file's line numbers;
    /// keys maps its "Sub/Key" entries to their lines.
    struct ModelSection
    {
      std::string                name;
      int                        line = 0;
      std::string                text;
      std::map<std::string, int> keys;
    };

    /// The lines of @p file_lines for which @p keep holds, the others blank.
    template <typename Keep>
    std::string
    blank_except(const std::vector<std::string> &file_lines, const Keep &keep)
    {
      std::string text;
      for (std::size_t i = 0; i < file_lines.size(); ++i)
        text += (keep(i) ? file_lines[i] : std::string()) + "\n";
      return text;
    }

    /// Cuts the model sections out of @p text: the rest (sections blanked line for
    /// line) is returned, the sections are appended to @p sections.
    std::string
    cut_model_sections(const std::string &text, const std::string &file_name,
                       std::vector<ModelSection> &sections)
    {
      std::vector<std::string> file_lines;
      {
        std::istringstream in(text);
        for (std::string line; std::getline(in, line);)
          file_lines.push_back(line);
      }
      std::vector<bool> in_section(file_lines.size(), false);
      int               depth = 0, open_depth = 0;
      std::size_t       header = 0; // the open section's first line (0-based)
      for (std::size_t i = 0; i < file_lines.size(); ++i)
        {
          const std::string line  = trim(file_lines[i].substr(0, file_lines[i].find('#')));
          const bool        opens = line.rfind("subsection ", 0) == 0;
          const bool        ends  = line == "end";
          const std::string head  = opens ? trim(line.substr(11)) : std::string();
          if (opens && depth == 0 && head.rfind("Model", 0) == 0 &&
              (head.size() == 5 || std::isspace(static_cast<unsigned char>(head[5]))))
            {
              const std::string name = trim(head.substr(5));
              const std::string here = file_name + ":" + std::to_string(i + 1) + ": ";
              if (name.empty())
                throw InputError(here + "'subsection Model' needs a model path, e.g. "
                                        "'subsection Model accurate'");
              for (const auto &s : sections)
                if (s.name == name)
                  throw InputError(here + "a second 'subsection Model " + name +
                                   "' (the first is on line " + std::to_string(s.line) + ")");
              sections.push_back({name, static_cast<int>(i + 1), "", {}});
              header     = i;
              open_depth = 1;
            }
          else if (open_depth > 0 && opens)
            ++open_depth;
          else if (open_depth > 0 && ends && --open_depth == 0)
            {
              // the body, without the section's own "subsection" and "end" lines
              auto &section = sections.back();
              section.text  = blank_except(file_lines, [&](std::size_t j) { return j > header && j < i; });
              section.keys  = locate_keys(section.text, file_name);
              in_section[i] = true;
            }
          if (open_depth > 0)
            in_section[i] = true;
          if (opens)
            ++depth;
          else if (ends && depth > 0)
            --depth;
        }
      if (open_depth > 0)
        throw InputError(file_name + ":" + std::to_string(sections.back().line) +
                         ": 'subsection Model " + sections.back().name + "' has no 'end'");
      return blank_except(file_lines, [&](std::size_t i) { return !in_section[i]; });
    }

    /// deal.II's parse messages span several lines and say "Line <n> of file <f>"; the
    /// user gets "f:n: what is wrong".
    std::string
    reformat(const dealii::ExceptionBase &e, const std::string &file_name)
    {
      std::ostringstream info;
      e.print_info(info);
      // found by plain search, not std::regex, whose recursion overflowed the stack on a
      // 100 kB value
      const std::string text = one_line(info.str());
      const std::string head = "Line <", of = "> of file <";
      const auto        end  = text.find(of);
      const auto        line = text.substr(std::min(head.size(), text.size()), end == std::string::npos ? 0 : end - head.size());
      const auto        colon = end == std::string::npos ? end : text.find(':', end + of.size());
      if (text.rfind(head, 0) != 0 || line.empty() || colon == std::string::npos ||
          line.find_first_not_of("0123456789") != std::string::npos)
        return file_name + ": " + text;
      std::string rest = trim(text.substr(colon + 1));
      // "The entry value X for the entry named K does not match the given pattern: P"
      const std::string value = "The entry value ", named = " for the entry named ",
                        match = " does not match the given pattern: ";
      const auto        m = rest.find(match), n = rest.rfind(named, m);
      if (rest.rfind(value, 0) == 0 && n != std::string::npos && m != std::string::npos && n < m)
        rest = rest.substr(n + named.size(), m - n - named.size()) + ": value '" +
               rest.substr(value.size(), n - value.size()) + "' does not match " + rest.substr(m + match.size());
      return file_name + ":" + line + ": " + rest;
    }
    /// A command-line setting of one model path's section: "Model <path>/Sub/Key=value".
    struct ModelSetting
    {
      std::string model, assignment; ///< the path, "Sub/Key=value"
    };

    /// Splits @p command_line into plain overrides and settings of a model section
    /// ("Model <path>/Sub/Key=value": set as if written in that section, under the plain ones).
    void
    split_command_line(const std::vector<std::string> &command_line, std::vector<std::string> &plain,
                       std::vector<ModelSetting> &scoped)
    {
      for (const auto &o : command_line)
        {
          const auto slash = o.find('/'), eq = o.find('=');
          if (o.rfind("Model ", 0) == 0 && slash != std::string::npos && slash < eq)
            scoped.push_back({trim(o.substr(6, slash - 6)), o.substr(slash + 1)});
          else
            plain.push_back(o);
        }
    }

    /// The scene's Model, after checking that every model section and model-scoped
    /// setting names a model path and that no section sets Model.
    std::string
    chosen_model(dealii::ParameterHandler &prm, const std::string &name, const std::vector<ModelSection> &sections,
                 const std::vector<ModelSetting> &scoped)
    {
      std::string chosen;
      try
        {
          chosen = prm.get("Model");
        }
      catch (const dealii::ExceptionBase &)
        {
          throw InputError(sections.empty() ? "--set \"Model " + scoped.front().model + "/" + scoped.front().assignment +
                                                "\": the scene has no 'Model' entry"
                                            : name + ":" + std::to_string(sections.front().line) +
                                                ": 'subsection Model' sections need a scene with a 'Model' entry");
        }
      const auto check_model = [&](const std::string &model, const std::string &where) {
        try
          {
            prm.set("Model", model);
          }
        catch (const dealii::ExceptionBase &e)
          {
            prm.set("Model", chosen);
            std::ostringstream info;
            e.print_info(info);
            throw InputError(where + ": no such model path (" + one_line(info.str()) + ")");
          }
      };
      for (const auto &section : sections)
        check_model(section.name, name + ":" + std::to_string(section.line) + ": 'subsection Model " + section.name + "'");
      for (const auto &[model, assignment] : scoped)
        {
          const std::string where = "--set \"Model " + model + "/" + assignment + "\"";
          check_model(model, where);
          if (trim(assignment.substr(0, assignment.find('='))) == "Model")
            throw InputError(where + ": Model cannot be set inside a model section");
        }
      prm.set("Model", chosen);
      for (const auto &section : sections)
        if (const auto model = section.keys.find("Model"); model != section.keys.end())
          throw InputError(name + ":" + std::to_string(model->second) +
                           ": Model cannot be set inside 'subsection Model " + section.name + "'");
      return chosen;
    }
  } // namespace

  ParameterFile::ParameterFile(dealii::ParameterHandler       &prm,
                               const std::string              &text,
                               const std::string              &name,
                               const std::string              &directory,
                               const std::vector<std::string> &command_line)
    : file_name(name)
    , directory(directory)
  {
    check_lines(text, name);
    for (const auto &o : command_line)
      if (!valid_utf8(o) || o.size() > max_line_length)
        throw InputError("--set: a setting is not valid UTF-8 text of at most " + std::to_string(max_line_length) +
                         " characters");
    {
      std::vector<std::string> chain{std::filesystem::weakly_canonical(name).string()};
      check_includes(text, name, chain);
    }
    std::vector<ModelSection> sections;
    const std::string         common = cut_model_sections(text, name, sections);
    lines                            = locate_keys(common, name);
    std::vector<std::string>  plain;
    std::vector<ModelSetting> scoped;
    split_command_line(command_line, plain, scoped);
    parse(prm, common);
    for (const auto &o : plain)
      apply_override(prm, o);
    if (sections.empty() && scoped.empty())
      {
        check_numbers(prm, *this);
        return;
      }

    // The path's own settings go over the common ones, and the command line over both:
    // the overrides are set again after the section.
    const std::string chosen = chosen_model(prm, name, sections, scoped);

    // Every section is checked in every run (a misspelt key of the accurate section is
    // reported by a realtime run too): the others are parsed on top, then the state
    // before them is read back from its print.
    std::ostringstream before;
    prm.print_parameters(before, dealii::ParameterHandler::ShortPRM);
    bool others = false;
    for (const auto &section : sections)
      if (section.name != chosen)
        {
          parse(prm, section.text);
          others = true;
        }
    for (const auto &[model, assignment] : scoped)
      if (model != chosen)
        {
          set_path(prm, assignment);
          others = true;
        }
    if (others)
      prm.parse_input_from_string(before.str(), name);

    for (const auto &section : sections)
      if (section.name == chosen)
        {
          parse(prm, section.text);
          for (const auto &[path, line] : section.keys)
            lines[path] = line;
        }
    for (const auto &[model, assignment] : scoped)
      if (model == chosen)
        apply_override(prm, assignment);
    for (const auto &o : plain)
      set_path(prm, o);
    check_numbers(prm, *this);
  }

  void
  ParameterFile::parse(dealii::ParameterHandler &prm, const std::string &text) const
  {
    try
      {
        prm.parse_input_from_string(text, file_name);
      }
    catch (const dealii::ExceptionBase &e)
      {
        throw InputError(reformat(e, file_name));
      }
  }

  ParameterFile
  ParameterFile::from_file(dealii::ParameterHandler       &prm,
                           const std::string              &file_name,
                           const std::vector<std::string> &command_line)
  {
    std::error_code error;
    if (!std::filesystem::is_regular_file(file_name, error) && std::filesystem::exists(file_name, error))
      throw InputError(file_name + ": is not a file (a scene is a parameter file)");
    std::ifstream in(file_name);
    if (!in)
      throw InputError(file_name + ": cannot open the scene file");
    std::stringstream buffer;
    buffer << in.rdbuf();
    // an empty scene would run every default: almost certainly not what was meant
    {
      std::istringstream lines(buffer.str());
      bool               any = false;
      for (std::string line; !any && std::getline(lines, line);)
        any = !trim(line.substr(0, line.find('#'))).empty();
      if (!any)
        throw InputError(file_name + ": the scene file has no settings (empty, or comments only)");
    }
    const auto parent = std::filesystem::path(file_name).parent_path().string();
    return ParameterFile(prm, buffer.str(), file_name, parent.empty() ? "." : parent, command_line);
  }

  void
  ParameterFile::apply_override(dealii::ParameterHandler &prm, const std::string &assignment)
  {
    overrides.push_back(set_path(prm, assignment));
  }

  std::string
  ParameterFile::set_path(dealii::ParameterHandler &prm, const std::string &assignment)
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
    // "Suture / Cross section/E" names the same key as "Suture/Cross section/E" (given())
    std::string normalised;
    for (const auto &part : parts)
      normalised += (normalised.empty() ? "" : "/") + part;
    return normalised;
  }

  int
  ParameterFile::line_of(const std::string &path) const
  {
    const auto it = lines.find(path);
    return it == lines.end() ? 0 : it->second;
  }

  bool
  ParameterFile::given(const std::string &path) const
  {
    return line_of(path) > 0 || std::find(overrides.begin(), overrides.end(), path) != overrides.end();
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
    const fs::path project = project_path(path);
    if (fs::exists(project))
      return project.lexically_normal().string();
    return local.lexically_normal().string();
  }

  std::string
  project_path(const std::string &relative)
  {
    return (std::filesystem::path(SUTURESIM_SOURCE_DIR) / relative).lexically_normal().string();
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
    const auto v = get_numbers(prm.get(key), key);
    if (v.size() != 3)
      throw InputError(key + ": '" + prm.get(key) + "' is not three numbers");
    return {v[0], v[1], v[2]};
  }

  std::vector<std::pair<std::string, std::vector<double>>>
  get_named_values(const dealii::ParameterHandler &prm, const std::string &key)
  {
    std::vector<std::pair<std::string, std::vector<double>>> entries;
    for (const auto &item : dealii::Utilities::split_string_list(prm.get(key), ';'))
      {
        const auto colon = item.find(':');
        if (colon == std::string::npos)
          throw InputError(key + ": '" + item + "' is not 'name: values'");
        entries.emplace_back(dealii::Utilities::trim(item.substr(0, colon)), get_numbers(item.substr(colon + 1), key));
      }
    return entries;
  }

  std::vector<std::pair<std::string, Eigen::Vector3d>>
  get_named_points(const dealii::ParameterHandler &prm, const std::string &key, const ParameterScope &scope,
                   const std::string &noun)
  {
    std::vector<std::pair<std::string, Eigen::Vector3d>> points;
    for (const auto &[name, x] : get_named_values(prm, key))
      {
        scope.require(!name.empty(), key, noun + " without a name: write 'name: x, y, z'");
        scope.require(x.size() == 3, key, noun + " '" + name + "' needs three coordinates");
        for (const auto &[other, point] : points)
          scope.require(other != name, key, noun + " '" + name + "' is named twice");
        points.emplace_back(name, Eigen::Vector3d(x[0], x[1], x[2]));
      }
    return points;
  }

  std::map<double, std::vector<double>>
  get_keyframes(const dealii::ParameterHandler &prm, const std::string &key, const ParameterScope &scope)
  {
    std::map<double, std::vector<double>> keyframes;
    for (const auto &[time, v] : get_named_values(prm, key))
    {
      const auto at = number(time);
      scope.require(at.has_value(), key, "time '" + time + "' is not a finite number");
      scope.require(keyframes.emplace(*at, v).second, key, "time " + time + " appears twice");
    }
    return keyframes;
  }
} // namespace suturesim
