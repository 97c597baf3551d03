#include <suturesim/core/parameter_adapter.h>

#include <algorithm>
#include <limits>
#include <map>
#include <memory>

namespace suturesim
{
  using namespace dealii;

  void
  declare_plain(ParameterHandler &prm, const ParameterDeclarations &declarations)
  {
    for (const auto &s : declarations.specs())
      {
        std::unique_ptr<Patterns::PatternBase> pattern;
        switch (s.kind)
          {
            case ParameterSpec::Kind::real:
              pattern = std::make_unique<Patterns::Double>(s.min, s.max);
              break;
            case ParameterSpec::Kind::integer:
              pattern = std::make_unique<Patterns::Integer>(
                static_cast<int>(std::max<double>(s.min, std::numeric_limits<int>::min())),
                static_cast<int>(std::min<double>(s.max, std::numeric_limits<int>::max())));
              break;
            case ParameterSpec::Kind::boolean:
              pattern = std::make_unique<Patterns::Bool>();
              break;
            case ParameterSpec::Kind::selection:
              pattern = std::make_unique<Patterns::Selection>(s.choices);
              break;
            case ParameterSpec::Kind::text:
              pattern = std::make_unique<Patterns::Anything>();
              break;
          }
        prm.declare_entry(s.name, s.default_value, *pattern, s.help);
      }
  }

  ParameterValues
  read_plain(const ParameterHandler &prm, const ParameterDeclarations &declarations)
  {
    std::map<std::string, std::string> values;
    for (const auto &s : declarations.specs())
      values[s.name] = prm.get(s.name);
    return ParameterValues(values);
  }
} // namespace suturesim
