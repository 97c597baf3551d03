#include <suturesim/scene/suture_newton_trace.h>

#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace suturesim::scene
{
  SutureNewtonTrace::SutureNewtonTrace(std::vector<std::pair<std::string, const rod::NodalTerms *>> terms,
                                       std::string file_name, PointStates points)
    : names{"elastic", "self_contact", "applied", "ties"}
    , nodal(std::move(terms))
    , file(std::move(file_name))
    , point_states(std::move(points))
  {
    for (const auto &[name, term] : nodal)
      names.push_back(name);
  }

  void
  SutureNewtonTrace::record(rod::RodModel &suture, const rod::NewtonIterate &iterate)
  {
    if (iterate.iteration == 0)
      rows.clear();
    std::vector<const rod::NodalTerms *> terms;
    for (const auto &[name, term] : nodal)
      terms.push_back(term);
    rod::ResidualParts split = suture.residual_parts(terms);
    std::vector<Eigen::VectorXd *> parts{&split.elastic, &split.self_contact, &split.applied, &split.element_terms};
    for (auto &p : split.nodal)
      parts.push_back(&p);
    // the supports' reactions are not residuals
    const std::size_t n = suture.n_nodes();
    Eigen::VectorXd   total = Eigen::VectorXd::Zero(6 * n);
    for (Eigen::VectorXd *p : parts)
      {
        for (std::size_t i = 0; i < n; ++i)
          for (unsigned c = 0; c < 6; ++c)
            if (suture.is_constrained(i, c))
              (*p)[6 * i + c] = 0;
        total += *p;
      }
    Row row;
    row.iteration = iterate.iteration;
    row.residual  = iterate.residual;
    row.step      = iterate.step;
    for (std::size_t i = 0; i < n; ++i)
      {
        if (total.segment<6>(6 * i).norm() > total.segment<6>(6 * row.worst).norm())
          row.worst = i;
        if (iterate.delta)
          {
            row.moved  = std::max(row.moved, iterate.step * iterate.delta->segment<3>(6 * i).norm());
            row.turned = std::max(row.turned, iterate.step * iterate.delta->segment<3>(6 * i + 3).norm());
          }
      }
    for (const Eigen::VectorXd *p : parts)
      {
        row.norms.push_back(p->norm());
        row.worst_norms.push_back(p->segment<6>(6 * row.worst).norm());
      }
    if (point_states)
      row.points = point_states();
    rows.push_back(std::move(row));
  }

  std::string
  trace_points_file(const std::string &file)
  {
    std::filesystem::path p(file);
    return (p.parent_path() / (p.stem().string() + "_points" + p.extension().string())).string();
  }

  void
  write_point_state(std::ostream &out, const coupling::TissueNeedle::ThreadPointState &p)
  {
    out << ',' << p.point << ',' << p.element << ',' << p.u << ',' << p.slip << ',' << p.slipping << ','
        << p.normal << ',' << p.friction << ',' << p.across;
  }

  void
  append_trace_rows(const std::string &path, const bool first, const std::string &header,
                    const std::function<void(std::ostream &)> &rows, const std::string &what)
  {
    std::ofstream out(path, first ? std::ios::trunc : std::ios::app);
    if (first)
      out << header << '\n';
    out << std::setprecision(9);
    rows(out);
    out.flush();
    if (!out)
      throw std::runtime_error(path + ": cannot write " + what);
  }

  void
  SutureNewtonTrace::write(const double t, const double dt)
  {
    std::ostringstream header;
    header << "time [s],dt [s],solve,iteration,residual [N|N m],step [1],largest move [m],largest turn [rad]";
    for (const auto &name : names)
      header << ',' << name << " [N|N m]";
    header << ",worst node";
    for (const auto &name : names)
      header << ",worst node " << name << " [N|N m]";
    const bool first = solves++ == 0;
    append_trace_rows(
      file, first, header.str(),
      [&](std::ostream &out) {
        for (const Row &r : rows)
          {
            out << t << ',' << dt << ',' << solves << ',' << r.iteration << ',' << r.residual << ',' << r.step
                << ',' << r.moved << ',' << r.turned;
            for (const double v : r.norms)
              out << ',' << v;
            out << ',' << r.worst;
            for (const double v : r.worst_norms)
              out << ',' << v;
            out << '\n';
          }
      },
      "the suture's Newton trace");
    if (!point_states)
      return;
    append_trace_rows(
      trace_points_file(file), first, std::string("time [s],dt [s],solve,iteration,") + point_state_columns,
      [&](std::ostream &out) {
        for (const Row &r : rows)
          for (const auto &p : r.points)
            {
              out << t << ',' << dt << ',' << solves << ',' << r.iteration;
              write_point_state(out, p);
              out << '\n';
            }
      },
      "the suture's Newton trace");
  }
} // namespace suturesim::scene
