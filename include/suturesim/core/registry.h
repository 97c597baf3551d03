#pragma once
/**
 * @file
 * Self-registration of pluggable models (materials, volumetric energies, integrators,
 * suture models, tear criteria), in the manner of ASPECT's ASPECT_REGISTER_* macros and
 * FEBio's REGISTER_FECORE_CLASS: a model's source file registers its name, description,
 * parameter declaration and factory; the selection pattern offered in scene files is
 * built from what is registered, so adding a model touches one new file.
 *
 * No deal.II header is needed here. The accurate path's models declare their parameters
 * into a dealii::ParameterHandler (Registry); the realtime library, which must build
 * without deal.II, declares them into its own plain list (BasicRegistry with
 * ParameterDeclarations), and the scene layer turns that list into deal.II
 * entries.
 */

#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace suturesim
{
  /// A registry of models derived from @p Base whose parameters are declared into a
  /// @p Declarations object and which are built from @p CreateArgs.
  template <typename Base, typename Declarations, typename... CreateArgs>
  class BasicRegistry
  {
  public:
    struct Entry
    {
      std::string name;
      /// One paragraph with the model's equation and its source.
      std::string description;
      /// Declares the model's own parameters in the current subsection of the handler.
      std::function<void(Declarations &)> declare_parameters;
      /// Builds the model; the handler's current subsection is the one declared into.
      std::function<std::unique_ptr<Base>(CreateArgs...)> create;
    };

    static BasicRegistry &
    instance()
    {
      static BasicRegistry registry;
      return registry;
    }

    /// Returns true so that a namespace-scope `const bool` can call it at load time.
    bool
    add(Entry entry)
    {
      const std::string name = entry.name;
      if (!entries.emplace(name, std::move(entry)).second)
        throw std::logic_error("model registered twice: " + name);
      return true;
    }

    const Entry &
    get(const std::string &name) const
    {
      const auto it = entries.find(name);
      if (it == entries.end())
        throw std::invalid_argument("no model named '" + name + "'; known: " +
                                    selection_pattern());
      return it->second;
    }

    std::vector<std::string>
    names() const
    {
      std::vector<std::string> result;
      for (const auto &[name, entry] : entries)
        result.push_back(name);
      return result;
    }

    /// "a|b|c", for dealii::Patterns::Selection.
    std::string
    selection_pattern() const
    {
      std::string pattern;
      for (const auto &[name, entry] : entries)
        pattern += (pattern.empty() ? "" : "|") + name;
      return pattern;
    }

    /// Help text listing every model with its description.
    std::string
    documentation() const
    {
      std::string text;
      for (const auto &[name, entry] : entries)
        text += "'" + name + "': " + entry.description + " ";
      return text;
    }

    const std::map<std::string, Entry> &
    all() const
    {
      return entries;
    }

  private:
    BasicRegistry() = default;
    std::map<std::string, Entry> entries;
  };

  /// Models whose parameters live in a deal.II ParameterHandler (the accurate path).
  template <typename Base, typename... CreateArgs>
  using Registry = BasicRegistry<Base, dealii::ParameterHandler, CreateArgs...>;
} // namespace suturesim
