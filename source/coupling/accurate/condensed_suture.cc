#include <suturesim/coupling/accurate/condensed_suture.h>

#include <suturesim/rod/rotation.h>

#include <algorithm>
#include <memory>

namespace suturesim::coupling
{
  using namespace dealii;

  namespace
  {
    /// Central-difference steps of the condensation's blocks, m and rad.
    constexpr double step = 1e-8, turn = 1e-7;
  } // namespace

  CondensedSuture::CondensedSuture(rod::RodModel &rod, const rod::NewtonParameters &parameters,
                                   TissueNeedle &tie, SutureContact *touching, const tissue::PointLoadList &all,
                                   const rod::NodalTerms *nodal)
    : suture(rod)
    , newton(parameters)
    , needle(tie)
    , contact(touching)
    , loads(all)
    , terms(nodal)
  {
    element_terms = [this](const std::size_t e, Eigen::Matrix<double, 12, 1> &r, Eigen::Matrix<double, 12, 12> *J) {
      needle.thread_terms(seen, e, r, J);
    };
    // the carriers also follow within a solve: a thread drawn through its holes by more
    // than an element in one step would otherwise hold each point on its old element's
    // curve extended past the projection's bound (u = 2), where the tie means nothing
    // (seen at the stitch's grasp, docs/interrupted_stitch.md)
    newton.follow = [this] {
      if (!needle.follow_thread(seen))
        return false;
      elements = needle.loaded_elements();
      return true;
    };
  }

  CondensedSuture::Attached::Attached(CondensedSuture &b)
    : body(b)
  {
    body.elements = body.needle.loaded_elements();
    body.suture.set_element_terms(&body.element_terms, &body.elements);
  }

  CondensedSuture::Attached::~Attached()
  {
    body.suture.set_element_terms(nullptr, nullptr);
  }

  Eigen::VectorXd
  CondensedSuture::residual()
  {
    const Attached attached(*this);
    return suture.residual(terms);
  }

  std::vector<std::size_t>
  CondensedSuture::coupled_points() const
  {
    std::vector<std::size_t> points = needle.thread_points();
    if (contact)
      for (std::size_t k = 0; k < contact->points().size(); ++k)
        points.push_back(loads.offset(1) + k);
    return points;
  }

  void
  CondensedSuture::hold(const std::vector<Point<3>> &x)
  {
    // no point loads at all before the needle touches (x is then empty)
    const std::size_t n = std::min(needle.points().size(), x.size());
    seen.assign(x.begin(), x.begin() + n);
    if (contact && !contact->points().empty())
      contact->set_tissue_positions(std::vector<Point<3>>(x.begin() + loads.offset(1), x.end()));
  }

  Eigen::VectorXd
  CondensedSuture::residual_at(const std::vector<Point<3>> &x)
  {
    hold(x);
    return suture.residual(terms);
  }

  bool
  CondensedSuture::equilibrate(const std::vector<Point<3>> &x, Eigen::MatrixXd &G, std::string &failure)
  {
    // The suture's equilibrium, with the points' carrier elements following the thread
    // as it slides (TissueNeedle::follow_thread(); a few rounds at most: at a bend a point
    // may sit where either element could carry it, and the last is kept).
    hold(x);
    rod::NewtonResult result;
    iterations = 0;
    for (unsigned round = 0; round < 5; ++round)
      {
        const Attached attached(*this);
        result = suture.solve(newton, terms);
        iterations += result.iterations;
        if (!result.converged || !needle.follow_thread(seen))
          break;
      }
    peak_iterations = std::max(peak_iterations, iterations);
    const Attached attached(*this);
    if (!result.converged)
      {
        failure = "suture: " + result.reason;
        return false;
      }
    const std::vector<std::size_t> coupled = coupled_points();
    const std::size_t              m = coupled.size(), n = suture.n_nodes();
    G.setZero(3 * m, 3 * m);
    if (m == 0)
      return true;
    suture.linearize(terms);
    // H and F below are differences: each pierce point's friction stays on the branch
    // it takes here (coulomb_friction()), released however this returns
    needle.hold_friction_branches(x);
    const std::unique_ptr<TissueNeedle, void (*)(TissueNeedle *)> release(
      &needle, [](TissueNeedle *n) { n->release_friction_branches(); });

    // H = ∂R/∂y: the suture's residual as each coupled point moves
    Eigen::MatrixXd         H(6 * n, 3 * m);
    std::vector<Point<3>>   y = x;
    for (std::size_t j = 0; j < m; ++j)
      for (unsigned d = 0; d < 3; ++d)
        {
          y[coupled[j]][d] = x[coupled[j]][d] + step;
          const Eigen::VectorXd plus = residual_at(y);
          y[coupled[j]][d]           = x[coupled[j]][d] - step;
          const Eigen::VectorXd minus = residual_at(y);
          y[coupled[j]][d]            = x[coupled[j]][d];
          H.col(3 * j + d)            = (plus - minus) / (2 * step);
        }
    hold(x);

    // F_q = ∂f/∂q: the loads on the tissue as the suture's nodes near them move (the
    // nodes of the elements the points may load, TissueNeedle::loaded_elements(), and
    // the contacts' nodes)
    std::vector<std::size_t> nodes;
    for (const std::size_t e : elements)
      {
        nodes.push_back(e);
        nodes.push_back(e + 1);
      }
    if (contact)
      for (const auto &c : contact->contacts())
        nodes.push_back(c.node);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    Eigen::MatrixXd F = Eigen::MatrixXd::Zero(3 * m, 6 * n);
    const auto      loads_now = [&](Eigen::VectorXd &f) {
      f.resize(3 * m);
      Tensor<1, 3> fk;
      Tensor<2, 3> unused;
      for (std::size_t j = 0; j < m; ++j)
        {
          loads.force(coupled[j], x[coupled[j]], fk, unused);
          for (unsigned d = 0; d < 3; ++d)
            f[3 * j + d] = fk[d];
        }
    };
    Eigen::VectorXd plus, minus;
    for (const std::size_t i : nodes)
      {
        const rod::Vec3 xi = suture.positions()[i];
        const rod::Quat qi = suture.rotations()[i];
        for (unsigned d = 0; d < 3; ++d)
          {
            suture.set_node(i, xi + step * rod::Vec3::Unit(d), qi);
            loads_now(plus);
            suture.set_node(i, xi - step * rod::Vec3::Unit(d), qi);
            loads_now(minus);
            F.col(6 * i + d) = (plus - minus) / (2 * step);
            // the rotations, through the tangents of the pierce points' curve
            suture.set_node(i, xi, rod::quaternion_exp(turn * rod::Vec3::Unit(d)) * qi);
            loads_now(plus);
            suture.set_node(i, xi, rod::quaternion_exp(-turn * rod::Vec3::Unit(d)) * qi);
            loads_now(minus);
            F.col(6 * i + 3 + d) = (plus - minus) / (2 * turn);
          }
        suture.set_node(i, xi, qi);
      }

    // G = F_q D⁻¹ H
    Eigen::MatrixXd DinvH(6 * n, 3 * m);
    for (std::size_t k = 0; k < 3 * m; ++k)
      DinvH.col(k) = suture.solve_linearized(H.col(k));
    G = F * DinvH;
    return true;
  }
} // namespace suturesim::coupling
