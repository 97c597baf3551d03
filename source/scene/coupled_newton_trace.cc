#include <suturesim/scene/coupled_newton_trace.h>
#include <suturesim/scene/suture_newton_trace.h>

#include <fstream>
#include <iomanip>
#include <stdexcept>

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
    std::ofstream out(file, solves == 0 ? std::ios::trunc : std::ios::app);
    if (solves++ == 0)
      out << "time [s],dt [s],solve,iteration,halvings,step [1],largest move [m],residual [N],taken [0|1],"
             "largest entry [N],largest X [m],largest Y [m],largest Z [m],largest component,suture iterations,"
             "suture contacts,pressing,touching face pairs\n";
    out << std::setprecision(9);
    for (const Row &r : rows)
      {
        const auto &X = r.state.largest_at;
        out << t << ',' << dt << ',' << solves << ',' << r.trial.iteration << ',' << r.trial.halvings << ','
            << r.trial.step << ',' << r.trial.moved << ',' << r.trial.residual << ',' << r.trial.taken << ','
            << r.trial.largest << ',' << X[0] << ',' << X[1] << ',' << X[2] << ',' << r.state.largest_component
            << ',' << r.state.suture_iterations << ',' << r.state.contacts << ',' << r.state.pressing << ',' << r.state.touching << '\n';
      }
    out.flush();
    if (!out)
      throw std::runtime_error(file + ": cannot write the coupled Newton trace");

    const std::string points_file = trace_points_file(file);
    std::ofstream     points(points_file, solves == 1 ? std::ios::trunc : std::ios::app);
    if (solves == 1)
      points << "time [s],dt [s],solve,iteration,halvings," << point_state_columns << '\n';
    points << std::setprecision(9);
    for (const Row &r : rows)
      for (const auto &p : r.state.points)
        {
          points << t << ',' << dt << ',' << solves << ',' << r.trial.iteration << ',' << r.trial.halvings;
          write_point_state(points, p);
          points << '\n';
        }
    points.flush();
    if (!points)
      throw std::runtime_error(points_file + ": cannot write the coupled Newton trace");
  }
} // namespace suturesim::scene
