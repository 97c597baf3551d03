#include <suturesim/realtime/system.h>

#include <stdexcept>

namespace suturesim::realtime
{
  std::uint32_t
  Nodes::add(const Vector3d &X, const double m, const double b)
  {
    if (!(m > 0))
      throw std::invalid_argument("realtime node with mass " + std::to_string(m) + " kg");
    const Eigen::Index n = x.cols();
    for (Matrix3Xd *a : {&x, &v, &reference, &previous, &force, &external, &target})
      a->conservativeResize(3, n + 1);
    x.col(n) = reference.col(n) = previous.col(n) = target.col(n) = X;
    v.col(n).setZero();
    force.col(n).setZero();
    external.col(n).setZero();
    for (VectorXd *a : {&mass, &damping, &inverse_mass})
      a->conservativeResize(n + 1);
    mass[n]         = m;
    damping[n]      = b;
    inverse_mass[n] = 1 / m;
    held.push_back(0);
    return static_cast<std::uint32_t>(n);
  }

  void
  Nodes::set_held(const std::uint32_t i, const Hold why, const bool hold)
  {
    held[i]         = hold ? (held[i] | why) : (held[i] & ~why);
    inverse_mass[i] = held[i] ? 0.0 : 1.0 / mass[i];
  }

  void
  System::finalize()
  {
    const Eigen::Index n = nodes.size();
    work_a.resize(3, n);
    work_b.resize(3, n);
    work_x.resize(3, n);
    if (n > 0)
      scale = (nodes.reference.rowwise().maxCoeff() - nodes.reference.rowwise().minCoeff()).norm();
    if (!(scale > 0))
      scale = 1;
  }

  void
  System::internal_forces(const Matrix3Xd &x, Matrix3Xd &f, const std::size_t first) const
  {
    f.setZero();
    for (std::size_t k = first; k < interactions.size(); ++k)
      interactions[k]->add_forces(x, f);
  }

  void
  System::total_forces(const Matrix3Xd &x)
  {
    Matrix3Xd &f = nodes.force;
    // detection first: a contact set may change an interaction for this state (the node
    // access leaves out the suture link it moves onto, node_access.h)
    detect_contacts(x, Contacts::all);
    internal_forces(x, f);
    for (const auto &c : contacts)
      c->add_forces(x, f);
    f += nodes.external;
    if (!gravity.isZero())
      f.noalias() += gravity * nodes.mass.transpose();
  }

  void
  System::detect_contacts(const Matrix3Xd &x, const Contacts which)
  {
    const auto start = std::chrono::steady_clock::now();
    for (const auto &c : contacts)
      if (which == Contacts::all || c->has_projection() == (which == Contacts::projected))
        c->detect(x);
    detection_time += std::chrono::steady_clock::now() - start;
  }

  double
  System::elastic_energy(const Matrix3Xd &x) const
  {
    double e = 0;
    for (const auto &i : interactions)
      e += i->energy(x);
    return e;
  }

  double
  System::kinetic_energy() const
  {
    return 0.5 * (nodes.v.colwise().squaredNorm().transpose().cwiseProduct(nodes.mass)).sum();
  }

  void
  System::stiffness_product(const Matrix3Xd &x, const Matrix3Xd &u, Matrix3Xd &Ku) const
  {
    const double norm = u.cwiseAbs().maxCoeff();
    if (norm == 0)
      {
        Ku.setZero(3, x.cols());
        return;
      }
    const double eps = 1e-6 * scale / norm;
    work_x           = x + eps * u;
    internal_forces(work_x, work_a);
    work_x = x - eps * u;
    internal_forces(work_x, work_b);
    Ku = (work_b - work_a) / (2 * eps);
  }
} // namespace suturesim::realtime
