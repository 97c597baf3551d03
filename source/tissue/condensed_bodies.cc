#include <suturesim/tissue/condensed_bodies.h>

namespace suturesim::tissue
{
  using namespace dealii;

  std::vector<std::size_t>
  CondensedBodies::coupled_points() const
  {
    std::vector<std::size_t> points;
    for (const auto *b : bodies)
      {
        const auto part = b->coupled_points();
        points.insert(points.end(), part.begin(), part.end());
      }
    return points;
  }

  bool
  CondensedBodies::equilibrate(const std::vector<Point<3>> &x, Eigen::MatrixXd &G, std::string &failure)
  {
    std::vector<Eigen::MatrixXd> parts(bodies.size());
    Eigen::Index                 size = 0;
    for (std::size_t i = 0; i < bodies.size(); ++i)
      {
        if (!bodies[i]->equilibrate(x, parts[i], failure))
          return false;
        size += parts[i].rows();
      }
    G.setZero(size, size);
    Eigen::Index at = 0;
    for (const auto &g : parts)
      {
        G.block(at, at, g.rows(), g.cols()) = g;
        at += g.rows();
      }
    return true;
  }

  void
  CondensedBodies::observe(const Trial &trial)
  {
    for (auto *b : bodies)
      b->observe(trial);
  }
} // namespace suturesim::tissue
