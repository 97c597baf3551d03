#include <suturesim/knot/diagram.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace suturesim::knot
{
  namespace
  {
    double
    cross(const Eigen::Vector2d &a, const Eigen::Vector2d &b)
    {
      return a.x() * b.y() - a.y() * b.x();
    }

    /// Labels 1, 2, … by first occurrence.
    std::vector<GaussEntry>
    relabelled(std::vector<GaussEntry> entries)
    {
      std::map<unsigned, unsigned> label;
      for (auto &e : entries)
        e.label = label.emplace(e.label, static_cast<unsigned>(label.size() + 1)).first->second;
      return entries;
    }

    /// The position of @p label's occurrence other than @p p.
    std::size_t
    other(const std::vector<GaussEntry> &e, const std::size_t p)
    {
      for (std::size_t q = 0; q < e.size(); ++q)
        if (q != p && e[q].label == e[p].label)
          return q;
      throw std::logic_error("Gauss code: a crossing occurs once");
    }

    /// One Reidemeister I or II move on @p e; false if none applies.
    bool
    reduce_once(std::vector<GaussEntry> &e)
    {
      for (std::size_t p = 0; p + 1 < e.size(); ++p)
        if (e[p].label == e[p + 1].label) // I: a twist loop
          {
            e.erase(e.begin() + static_cast<long>(p), e.begin() + static_cast<long>(p) + 2);
            return true;
          }
      if (e.size() >= 2 && e.front().label == e.back().label) // I through the closing arc
        {
          e.pop_back();
          e.erase(e.begin());
          return true;
        }
      for (std::size_t p = 0; p + 1 < e.size(); ++p)
        {
          if (e[p].over != e[p + 1].over)
            continue;
          // II: the strand at p, p + 1 passes over (or under) both crossings, and the
          // other strand meets them next to each other too
          const std::size_t qx = other(e, p), qy = other(e, p + 1);
          if (qx + 1 != qy && qy + 1 != qx)
            continue;
          const unsigned x = e[p].label, y = e[p + 1].label;
          e.erase(std::remove_if(e.begin(), e.end(), [&](const GaussEntry &g) { return g.label == x || g.label == y; }),
                  e.end());
          return true;
        }
      return false;
    }
  } // namespace

  GaussCode::GaussCode(std::vector<GaussEntry> entries)
    : entries_(relabelled(std::move(entries)))
  {
    std::map<unsigned, int> balance; // +1 per over, +2 per under: 3 when once each
    for (const auto &e : entries_)
      balance[e.label] += e.over ? 1 : 2;
    for (const auto &[label, b] : balance)
      if (b != 3)
        throw std::invalid_argument("Gauss code: crossing " + std::to_string(label) +
                                    " must occur exactly twice, once over and once under");
  }

  GaussCode
  GaussCode::parse(const std::string &text)
  {
    std::istringstream      in(text);
    std::vector<GaussEntry> entries;
    for (std::string token; in >> token;)
      {
        if (token.size() < 2 || (token[0] != 'O' && token[0] != 'U') ||
            token.find_first_not_of("0123456789", 1) != std::string::npos || token.size() > 6)
          throw std::invalid_argument("Gauss code: '" + token + "' is not O or U followed by a label");
        entries.push_back({static_cast<unsigned>(std::stoul(token.substr(1))), token[0] == 'O'});
      }
    return GaussCode(std::move(entries));
  }

  GaussCode
  GaussCode::reduced() const
  {
    std::vector<GaussEntry> e = entries_;
    while (reduce_once(e))
      {
      }
    return GaussCode(std::move(e));
  }

  GaussCode
  GaussCode::mirrored() const
  {
    std::vector<GaussEntry> e = entries_;
    for (auto &entry : e)
      entry.over = !entry.over;
    return GaussCode(std::move(e));
  }

  bool
  GaussCode::is_cut_of(const GaussCode &closed) const
  {
    for (const GaussCode &c : {closed, closed.mirrored()})
      {
        const auto &e = c.entries();
        for (std::size_t k = 0; k < e.size(); ++k)
          {
            std::vector<GaussEntry> rotated(e.begin() + static_cast<long>(k), e.end());
            rotated.insert(rotated.end(), e.begin(), e.begin() + static_cast<long>(k));
            if (GaussCode(std::move(rotated)) == *this)
              return true;
          }
      }
    return entries_.empty() && closed.entries().empty();
  }

  long
  GaussCode::determinant() const
  {
    const std::size_t n = crossings();
    if (n <= 1) // a diagram of one crossing is a twist of the unknot (and its minor empty)
      return 1;
    // arc k begins after the k-th under-pass along the rope and ends at the next one,
    // the last wrapping through the closing arc to the first
    std::vector<std::size_t> arc(entries_.size());
    std::size_t              unders = 0;
    for (std::size_t p = 0; p < entries_.size(); ++p)
      {
        if (!entries_[p].over)
          ++unders;
        arc[p] = unders % n; // an over-pass lies on the arc after the last under-pass
      }
    Eigen::MatrixXd colouring = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    for (std::size_t p = 0; p < entries_.size(); ++p)
      {
        const auto row = static_cast<Eigen::Index>(entries_[p].label - 1);
        if (entries_[p].over)
          colouring(row, static_cast<Eigen::Index>(arc[p])) += 2;
        else // the arc that ends here and the one that begins
          {
            colouring(row, static_cast<Eigen::Index>((arc[p] + n - 1) % n)) -= 1;
            colouring(row, static_cast<Eigen::Index>(arc[p])) -= 1;
          }
      }
    const Eigen::Index m = static_cast<Eigen::Index>(n) - 1;
    return std::lround(std::abs(colouring.topLeftCorner(m, m).fullPivLu().determinant()));
  }

  int
  GaussCode::writhe() const
  {
    int sum = 0;
    for (const auto &e : entries_)
      sum += e.over ? e.sign : 0; // once per crossing: at its over-pass
    return sum;
  }

  std::string
  GaussCode::text() const
  {
    std::string s;
    for (const auto &e : entries_)
      s += (s.empty() ? "" : " ") + std::string(e.over ? "O" : "U") + std::to_string(e.label);
    return s;
  }

  Projection::Projection(const Eigen::Vector3d &normal)
  {
    if (!(normal.norm() > 0) || !normal.allFinite())
      throw std::invalid_argument("the projection plane's normal must be a non-zero vector");
    n = normal.normalized();
    // u along the coordinate axis least aligned with n, made orthogonal to it
    Eigen::Index least;
    n.cwiseAbs().minCoeff(&least);
    u = (Eigen::Vector3d::Unit(least) - n[least] * n).normalized();
    v = n.cross(u);
  }

  KnotDiagram::KnotDiagram(const Eigen::Matrix3Xd &nodes, const Projection &projection)
    : x(nodes)
  {
    const Eigen::Index segments = nodes.cols() - 1;
    if (segments < 1)
      throw std::invalid_argument("a knot diagram needs a rope of at least two nodes");
    std::vector<Eigen::Vector2d> p(static_cast<std::size_t>(nodes.cols()));
    for (Eigen::Index k = 0; k < nodes.cols(); ++k)
      p[static_cast<std::size_t>(k)] = projection.in_plane(nodes.col(k));
    for (Eigen::Index i = 0; i < segments; ++i)
      {
        const auto            ui = static_cast<std::size_t>(i);
        const Eigen::Vector2d di = p[ui + 1] - p[ui];
        for (Eigen::Index j = i + 2; j < segments; ++j)
          {
            const auto            uj = static_cast<std::size_t>(j);
            const Eigen::Vector2d dj = p[uj + 1] - p[uj], w = p[uj] - p[ui];
            const double          denominator = cross(di, dj);
            // parallel projections meet in no single point: a crossing needs a transversal
            if (std::abs(denominator) <= 1e-12 * di.norm() * dj.norm())
              continue;
            const double s = cross(w, dj) / denominator, t = cross(w, di) / denominator;
            // half-open, so a crossing through a node counts once; the last node closes
            const bool in_s = s >= 0 && s < 1, in_t = t >= 0 && (t < 1 || (j + 1 == segments && t <= 1));
            if (!in_s || !in_t)
              continue;
            const double ha = projection.height(point(static_cast<double>(i) + s)),
                         hb = projection.height(point(static_cast<double>(j) + t));
            // (t_over × t_under) · n: the plane's cross product of the projections
            const double handed = ha > hb ? cross(di, dj) : cross(dj, di);
            crossings_.push_back(
              {static_cast<double>(i) + s, static_cast<double>(j) + t, ha > hb, handed > 0 ? 1 : -1});
          }
      }
    std::sort(crossings_.begin(), crossings_.end(), [](const Crossing &l, const Crossing &r) { return l.a < r.a; });
    bounds.push_back(0);
    for (const auto &c : crossings_)
      bounds.insert(bounds.end(), {c.a, c.b});
    std::sort(bounds.begin() + 1, bounds.end());
    bounds.push_back(static_cast<double>(segments));
  }

  GaussCode
  KnotDiagram::gauss_code() const
  {
    std::vector<std::pair<double, GaussEntry>> occurrences;
    for (std::size_t k = 0; k < crossings_.size(); ++k)
      {
        const auto label = static_cast<unsigned>(k + 1);
        occurrences.push_back({crossings_[k].a, {label, crossings_[k].a_over, crossings_[k].sign}});
        occurrences.push_back({crossings_[k].b, {label, !crossings_[k].a_over, crossings_[k].sign}});
      }
    std::sort(occurrences.begin(), occurrences.end(),
              [](const auto &l, const auto &r) { return l.first < r.first; });
    std::vector<GaussEntry> entries;
    for (const auto &o : occurrences)
      entries.push_back(o.second);
    return GaussCode(std::move(entries));
  }

  std::size_t
  KnotDiagram::span_of(const double a) const
  {
    const auto above = std::upper_bound(bounds.begin() + 1, bounds.end() - 1, a);
    return static_cast<std::size_t>(above - bounds.begin()) - 1;
  }

  Eigen::Vector3d
  KnotDiagram::point(const double a) const
  {
    const Eigen::Index last = x.cols() - 1;
    const double       clamped = std::clamp(a, 0.0, static_cast<double>(last));
    const Eigen::Index i       = std::min<Eigen::Index>(static_cast<Eigen::Index>(clamped), last - 1);
    const double       s       = clamped - static_cast<double>(i);
    return (1 - s) * x.col(i) + s * x.col(i + 1);
  }
} // namespace suturesim::knot
