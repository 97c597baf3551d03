#pragma once
/**
 * @file
 * Parameters of realtime models without deal.II: a model declares its entries (name,
 * default, range, help text with the unit) into a ParameterDeclarations list; the scene
 * layer turns them into dealii::ParameterHandler entries in the model's own subsection
 * (so range errors name file and line as for every other parameter) and hands the parsed
 * strings back as ParameterValues. Cross-parameter checks in a model throw
 * ParameterError naming the key; the scene layer adds file and line.
 *
 * Realtime models register through BasicRegistry<Base, ParameterDeclarations,
 * const ParameterValues &, ...> (core/registry.h), the same self-registration as the
 * accurate path's models.
 */

#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace suturesim
{
  /// The shortest text that reads back as @p v exactly ("0.2", "1.5707963267948966";
  /// deal.II's Patterns::Tools::to_string keeps six digits).
  std::string
  shortest_text(double v);

  /// A declared default as text, from the in-class initialiser it declares (so that the
  /// two cannot drift: conventions.md §2).
  template <typename T>
  std::string
  default_text(const T v)
  {
    if constexpr (std::is_same_v<T, bool>)
      return v ? "true" : "false";
    else if constexpr (std::is_integral_v<T>)
      return std::to_string(v);
    else
      return shortest_text(v);
  }

  struct ParameterSpec
  {
    enum class Kind
    {
      real,
      integer,
      boolean,
      selection,
      text
    };
    std::string name;
    Kind        kind = Kind::real;
    std::string default_value;
    double      min = -std::numeric_limits<double>::max(); ///< closed range of real/integer
    double      max = std::numeric_limits<double>::max();
    std::string choices; ///< "a|b|c" of a selection
    std::string help;    ///< names the unit and the range
  };

  class ParameterDeclarations
  {
  public:
    void
    add_real(const std::string &name, double default_value, double min, double max,
             const std::string &help);
    void
    add_integer(const std::string &name, long default_value, long min, long max,
                const std::string &help);
    void
    add_bool(const std::string &name, bool default_value, const std::string &help);
    void
    add_selection(const std::string &name, const std::string &default_value,
                  const std::string &choices, const std::string &help);
    /// Free text (lists of points, names); the model parses and checks it.
    void
    add_text(const std::string &name, const std::string &default_value, const std::string &help);

    const std::vector<ParameterSpec> &
    specs() const
    {
      return list;
    }

  private:
    std::vector<ParameterSpec> list;
  };

  /// A bad parameter value found by a model; what() is "key: problem".
  class ParameterError : public std::invalid_argument
  {
  public:
    ParameterError(const std::string &key, const std::string &problem)
      : std::invalid_argument(key + ": " + problem)
      , key(key)
      , problem(problem)
    {}
    std::string key, problem;
  };

  class ParameterValues
  {
  public:
    ParameterValues() = default;
    explicit ParameterValues(std::map<std::string, std::string> values)
      : values(std::move(values))
    {}

    /// The values of @p declarations' defaults (for tests and programmatic use).
    static ParameterValues
    defaults(const ParameterDeclarations &declarations);

    double
    real(const std::string &name) const;
    long
    integer(const std::string &name) const;
    bool
    boolean(const std::string &name) const;
    const std::string &
    text(const std::string &name) const;

    /// Overrides one value (tests, programmatic set-up).
    ParameterValues &
    set(const std::string &name, const std::string &value);

    [[noreturn]] void
    fail(const std::string &name, const std::string &problem) const
    {
      throw ParameterError(name, problem);
    }
    void
    require(const bool condition, const std::string &name, const std::string &problem) const
    {
      if (!condition)
        fail(name, problem);
    }

  private:
    std::map<std::string, std::string> values;
  };
} // namespace suturesim
