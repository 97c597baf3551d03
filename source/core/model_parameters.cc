#include <suturesim/core/model_parameters.h>

#include <charconv>
#include <sstream>

namespace suturesim
{
  std::string
  shortest_text(const double v)
  {
    char       buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof(buffer), v).ptr;
    return std::string(buffer, end);
  }

  void
  ParameterDeclarations::add_real(const std::string &name, const double default_value,
                                  const double min, const double max, const std::string &help)
  {
    list.push_back({name, ParameterSpec::Kind::real, shortest_text(default_value), min, max, "", help});
  }

  void
  ParameterDeclarations::add_integer(const std::string &name, const long default_value,
                                     const long min, const long max, const std::string &help)
  {
    list.push_back({name, ParameterSpec::Kind::integer, std::to_string(default_value),
                    double(min), double(max), "", help});
  }

  void
  ParameterDeclarations::add_bool(const std::string &name, const bool default_value,
                                  const std::string &help)
  {
    list.push_back({name, ParameterSpec::Kind::boolean, default_value ? "true" : "false", 0, 1,
                    "", help});
  }

  void
  ParameterDeclarations::add_selection(const std::string &name, const std::string &default_value,
                                       const std::string &choices, const std::string &help)
  {
    list.push_back({name, ParameterSpec::Kind::selection, default_value, 0, 0, choices, help});
  }

  void
  ParameterDeclarations::add_text(const std::string &name, const std::string &default_value,
                                  const std::string &help)
  {
    list.push_back({name, ParameterSpec::Kind::text, default_value, 0, 0, "", help});
  }

  ParameterValues
  ParameterValues::defaults(const ParameterDeclarations &declarations)
  {
    std::map<std::string, std::string> v;
    for (const auto &s : declarations.specs())
      v[s.name] = s.default_value;
    return ParameterValues(v);
  }

  const std::string &
  ParameterValues::text(const std::string &name) const
  {
    const auto it = values.find(name);
    if (it == values.end())
      throw std::logic_error("realtime parameter '" + name + "' was not declared");
    return it->second;
  }

  double
  ParameterValues::real(const std::string &name) const
  {
    const std::string &t = text(name);
    try
      {
        std::size_t used = 0;
        const double v    = std::stod(t, &used);
        if (t.find_first_not_of(" \t", used) == std::string::npos)
          return v;
      }
    catch (const std::exception &)
      {}
    fail(name, "'" + t + "' is not a number");
  }

  long
  ParameterValues::integer(const std::string &name) const
  {
    const std::string &t = text(name);
    try
      {
        std::size_t used = 0;
        const long  v    = std::stol(t, &used);
        if (t.find_first_not_of(" \t", used) == std::string::npos)
          return v;
      }
    catch (const std::exception &)
      {}
    fail(name, "'" + t + "' is not an integer");
  }

  bool
  ParameterValues::boolean(const std::string &name) const
  {
    const std::string &t = text(name);
    if (t == "true" || t == "yes" || t == "1")
      return true;
    if (t == "false" || t == "no" || t == "0")
      return false;
    fail(name, "'" + t + "' is not true or false");
  }

  ParameterValues &
  ParameterValues::set(const std::string &name, const std::string &value)
  {
    text(name); // must be declared
    values[name] = value;
    return *this;
  }
} // namespace suturesim
