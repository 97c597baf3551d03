#pragma once
/**
 * @file
 * Several bodies condensed onto the tissue's point loads (tissue/condensed_body.h)
 * solved with it as one: the suture and the incision's face contact, say. Their coupled
 * points are concatenated in order and G is block-diagonal, which holds because no two
 * of them act through the same point load.
 */

#include <suturesim/tissue/condensed_body.h>

#include <vector>

namespace suturesim::tissue
{
  class CondensedBodies : public CondensedBody
  {
  public:
    /// @p parts: kept by the caller, disjoint in their coupled points.
    explicit CondensedBodies(std::vector<CondensedBody *> parts)
      : bodies(std::move(parts))
    {}
    std::vector<std::size_t>
    coupled_points() const override;
    bool
    equilibrate(const std::vector<dealii::Point<3>> &x, Eigen::MatrixXd &G, std::string &failure) override;
    /// Shown to every part.
    void
    observe(const Trial &trial) override;

  private:
    std::vector<CondensedBody *> bodies;
  };
} // namespace suturesim::tissue
