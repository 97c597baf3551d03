#include <suturesim/tearing/tear_criterion.h>

#include <deal.II/base/parameter_handler.h>

namespace suturesim::tearing
{
  std::pair<double, Vector3>
  largest_principal(const SymTensor2 &A)
  {
    // deal.II sorts the eigenpairs by decreasing eigenvalue.
    const auto pairs = dealii::eigenvectors(A, dealii::SymmetricTensorEigenvectorMethod::jacobi);
    return {pairs[0].first, pairs[0].second / pairs[0].second.norm()};
  }

  void
  TearCriteria::declare_parameters(dealii::ParameterHandler &prm)
  {
    const auto &criteria = TearCriterion::Registry::instance();
    prm.declare_entry("Criteria", "", dealii::Patterns::MultipleSelection(criteria.selection_pattern()),
                      "Tear criteria evaluated around each pierce tract (comma-separated; empty for none). "
                          + criteria.documentation());
    prm.declare_entry("Process zone radius", "0.5e-3", dealii::Patterns::Double(0),
                      "Radius l of the zone around each pierce tract (the segment from a pass's entry to its "
                      "exit) over which each criterion's measure is averaged before it is compared with its "
                      "critical value. Unit: m. Range: > 0, and several cells wide for a converged average.");
    for (const auto &[name, entry] : criteria.all())
      entry.declare_parameters(prm);
  }

  TearCriteria
  TearCriteria::parse_parameters(const dealii::ParameterHandler &prm, const ParameterScope &scope)
  {
    TearCriteria result;
    result.process_zone_radius = prm.get_double("Process zone radius");
    scope.require(result.process_zone_radius > 0, "Process zone radius", "must be > 0 m");

    // The registry's factories read the criterion's own subsection, as the materials do.
    auto &entering = const_cast<dealii::ParameterHandler &>(prm);
    for (const auto &name : dealii::Utilities::split_string_list(prm.get("Criteria")))
      {
        for (const auto &[chosen, criterion] : result.criteria)
          scope.require(chosen != name, "Criteria", "names '" + name + "' twice");
        entering.enter_subsection(name);
        try
          {
            result.criteria.emplace_back(
                name, TearCriterion::Registry::instance().get(name).create(prm, scope.subsection(name)));
          }
        catch (...)
          {
            entering.leave_subsection();
            throw;
          }
        entering.leave_subsection();
      }
    return result;
  }
} // namespace suturesim::tearing
