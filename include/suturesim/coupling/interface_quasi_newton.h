#pragma once
/**
 * @file
 * Interface quasi-Newton acceleration of a partitioned coupling, IQN-ILS (Degroote,
 * Bathe & Vierendeels 2009, Comput. Struct. 87:793–801): the fixed point x = H(x) of
 * "solve one body with the interface held, then the other", here the tissue's points
 * that the suture sees (the pierce points and the contacts, three coordinates each).
 *
 * With r_k = H(x_k) − x_k and x̃_k = H(x_k), the differences of the iterates so far,
 * V = [r_k − r_{k−1}, …] and W = [x̃_k − x̃_{k−1}, …], give a least-squares model of how
 * the residual answers a change of the interface; the next iterate is
 *   x_{k+1} = x̃_k + W c,  c = argmin |V c + r_k|,
 * and the first one x_1 = x_0 + ω r_0. On a linear map of n unknowns it finds the fixed
 * point in at most n + 1 rounds; on the suture–tissue coupling, where one round of
 * Gauss–Seidel contracts by k⊥/(k⊥ + K) per point (a tie stiffer than the tissue at the
 * point), Aitken's scalar Δ² still took 15–20 rounds with four pierce points because the
 * points contract at different rates, which one scalar cannot match.
 *
 * Columns that are nearly dependent (their QR's diagonal below 1e-10 of the largest) are
 * dropped, oldest first.
 */

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace suturesim::coupling
{
  class InterfaceQuasiNewton
  {
  public:
    /// @p omega: the first round's relaxation.
    explicit InterfaceQuasiNewton(double omega = 1.0)
      : omega(omega)
    {}

    /// Moves @p x towards the fixed point given @p target = H(x) (same size, a multiple
    /// of 3); returns the largest |target − x| of a point (three coordinates) before the
    /// move.
    double
    update(Eigen::VectorXd &x, const Eigen::VectorXd &target);

    /// Forgets the history (the interface changed: another point, another step).
    void
    reset()
    {
      residuals.clear();
      targets.clear();
    }

    /// Columns of the model in use (differences kept), for tests.
    std::size_t
    columns() const
    {
      return residuals.empty() ? 0 : residuals.size() - 1;
    }

  private:
    double                       omega;
    std::vector<Eigen::VectorXd> residuals, targets; ///< r_i, x̃_i of this step, oldest first
  };
} // namespace suturesim::coupling
