#pragma once
/**
 * @file
 * Plain parameter declarations (core/model_parameters.h: what the realtime library and
 * the path-independent laws of coupling/ declare without deal.II) as entries of a
 * dealii::ParameterHandler, so that a scene file is checked on parsing against the same
 * ranges and a model's ParameterError becomes an InputError naming file, line and key.
 */

#include <suturesim/core/model_parameters.h>
#include <suturesim/core/parameter_file.h>

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace suturesim
{
  /// Declares @p declarations as entries of the handler's current subsection.
  void
  declare_plain(dealii::ParameterHandler &prm, const ParameterDeclarations &declarations);

  /// The values of @p declarations from the handler's current subsection.
  ParameterValues
  read_plain(const dealii::ParameterHandler &prm, const ParameterDeclarations &declarations);

  /// Parses the handler's current subsection into a value by @p parse, a function of
  /// ParameterValues that checks them (ParameterError); @p declare names the entries.
  /// A ParameterError fails through @p scope (file, line, key).
  template <typename Declare, typename Parse>
  auto
  parse_plain(const dealii::ParameterHandler &prm, const ParameterScope &scope, const Declare &declare,
              const Parse &parse)
  {
    ParameterDeclarations declarations;
    declare(declarations);
    const ParameterValues values = read_plain(prm, declarations);
    try
      {
        return parse(values);
      }
    catch (const ParameterError &e)
      {
        scope.fail(e.key, e.problem);
      }
  }

  /// "Key" selecting one model of @p Registry (a BasicRegistry over
  /// ParameterDeclarations), and a subsection per model with its parameters.
  /// @p extra_choices are names the caller handles itself ("off|").
  template <typename Registry>
  void
  declare_models(dealii::ParameterHandler &prm, const std::string &key, const std::string &default_name,
                 const std::string &help, const std::string &extra_choices = "")
  {
    const auto &registry = Registry::instance();
    std::string doc      = help + " Choices:";
    for (const auto &[name, entry] : registry.all())
      doc += " '" + name + "': " + entry.description;
    prm.declare_entry(key, default_name, dealii::Patterns::Selection(extra_choices + registry.selection_pattern()),
                      doc);
    for (const auto &[name, entry] : registry.all())
      if (entry.declare_parameters)
        {
          ParameterDeclarations declarations;
          entry.declare_parameters(declarations);
          prm.enter_subsection(name);
          declare_plain(prm, declarations);
          prm.leave_subsection();
        }
  }

  /// The parameters of model @p name of @p Registry, from its subsection of the
  /// handler's current one.
  template <typename Registry>
  ParameterValues
  read_model_values(dealii::ParameterHandler &prm, const std::string &name)
  {
    const auto &entry = Registry::instance().get(name);
    if (!entry.declare_parameters)
      return ParameterValues();
    ParameterDeclarations declarations;
    entry.declare_parameters(declarations);
    prm.enter_subsection(name);
    ParameterValues values = read_plain(prm, declarations);
    prm.leave_subsection();
    return values;
  }

  /// Model @p name of @p Registry built from its subsection; a ParameterError of the
  /// model fails through @p scope's subsection of that name.
  template <typename Registry>
  auto
  create_model(dealii::ParameterHandler &prm, const ParameterScope &scope, const std::string &name)
  {
    const auto values = read_model_values<Registry>(prm, name);
    try
      {
        return Registry::instance().get(name).create(values);
      }
    catch (const ParameterError &e)
      {
        scope.subsection(name).fail(e.key, e.problem);
      }
  }
} // namespace suturesim
