#include <suturesim/scene/coupled_newton_trace.h>
#include <suturesim/scene/suture_newton_trace.h>

#include <ostream>
#include <string>

namespace suturesim::scene
{
  CoupledNewtonTrace::CoupledNewtonTrace(tissue::CondensedBody &traced, std::string file_name, Sample sampler)
    : body(traced)
    , file(std::move(file_name))
    , sample(std::move(sampler))
  {}

  void
  CoupledNewtonTrace::observe(const Trial &trial)
  {
    if (trial.iteration == 0)
      rows.clear();
    rows.push_back({trial, sample(trial)});
    body.observe(trial);
  }

  void
  CoupledNewtonTrace::write(const double t, const double dt)
  {
    const bool first = solves++ == 0;
    append_trace_rows(
      file, first,
      "time [s],dt [s],solve,iteration,halvings,step [1],largest move [m],residual [N],taken [0|1],"
      "largest entry [N],largest X [m],largest Y [m],largest Z [m],largest component,suture iterations,"
      "suture contacts,pressing,touching face pairs",
      [&](std::ostream &out) {
        for (const Row &r : rows)
          {
            const auto &X = r.state.largest_at;
            out << t << ',' << dt << ',' << solves << ',' << r.trial.iteration << ',' << r.trial.halvings << ','
                << r.trial.step << ',' << r.trial.moved << ',' << r.trial.residual << ',' << r.trial.taken << ','
                << r.state.largest << ',' << X[0] << ',' << X[1] << ',' << X[2] << ','
                << r.state.largest_component << ',' << r.state.suture_iterations << ',' << r.state.contacts << ','
                << r.state.pressing << ',' << r.state.touching << '\n';
          }
      },
      "the coupled Newton trace");
    append_trace_rows(
      trace_points_file(file), first, std::string("time [s],dt [s],solve,iteration,halvings,") + point_state_columns,
      [&](std::ostream &out) {
        for (const Row &r : rows)
          for (const auto &p : r.state.points)
            {
              out << t << ',' << dt << ',' << solves << ',' << r.trial.iteration << ',' << r.trial.halvings;
              write_point_state(out, p);
              out << '\n';
            }
      },
      "the coupled Newton trace");
  }
} // namespace suturesim::scene
