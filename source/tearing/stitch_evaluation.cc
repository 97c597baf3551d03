#include <suturesim/collision/proximity.h>
#include <suturesim/tearing/stitch_evaluation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace suturesim::tearing
{
  namespace
  {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  }

  void
  StitchLimits::declare(ParameterDeclarations &d)
  {
    const StitchLimits defaults;
    d.add_text("Wound faces", defaults.wound_faces,
               "The boundaries (names or ids, 'a, b') that are the wound's faces, from which the entry's and "
               "exit's distance to the wound is measured and through which a stitch crosses it; empty: "
               "Closure/Face contact's. Unit: none.");
    d.add_real("Minimum edge distance", defaults.edge_distance, 0, 1,
               "A stitch whose entry or exit is nearer the wound than this is too close to the edge (seed 003); "
               "0: the stitch's own bite depth (the rule of thumb: entry about as far from the edge as the "
               "tissue sutured is deep). Unit: m. Range: [0, 1].");
    d.add_real("Minimum spacing", defaults.spacing, 0, 1,
               "A stitch nearer its neighbour than this (midpoints of the entry-exit chords) is too close to it "
               "(seed 003); 0: twice the edge limit. Unit: m. Range: [0, 1].");
  }

  StitchLimits
  StitchLimits::parse(const ParameterValues &v)
  {
    StitchLimits l;
    l.wound_faces   = v.text("Wound faces");
    l.edge_distance = v.real("Minimum edge distance");
    l.spacing       = v.real("Minimum spacing");
    return l;
  }

  Wound::Wound(const Eigen::Matrix3Xd &vertices, const std::vector<std::array<std::uint32_t, 3>> &triangles,
               const std::vector<char> &on_face)
  {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (std::size_t t = 0; t < triangles.size(); ++t)
      if (on_face[t])
        {
          const auto &tri = triangles[t];
          faces.push_back({vertices.col(tri[0]), vertices.col(tri[1]), vertices.col(tri[2])});
          const auto &f = faces.back();
          normals.push_back((f[1] - f[0]).cross(f[2] - f[0]).normalized());
          boxes.emplace_back(faces.back()[0]);
          for (const auto &v : faces.back())
            {
              boxes.back().extend(v);
              lo = lo.cwiseMin(v);
              hi = hi.cwiseMax(v);
            }
        }
    if (present())
      tolerance = 1e-9 * (hi - lo).norm();
  }

  double
  Wound::distance(const Eigen::Vector3d &X) const
  {
    double nearest = present() ? std::numeric_limits<double>::max() : nan;
    for (const auto &f : faces)
      {
        Eigen::Vector3d bary;
        nearest = std::min(nearest, (collision::closest_point_on_triangle(X, f[0], f[1], f[2], bary) - X).norm());
      }
    return nearest;
  }

  bool
  Wound::on_face(const Eigen::Vector3d &X) const
  {
    return present() && distance(X) <= tolerance;
  }

  double
  Wound::ray(const Eigen::Vector3d &X, const Eigen::Vector3d &d) const
  {
    // as a segment long enough to reach every face
    double reach = 0;
    for (const auto &f : faces)
      for (const auto &v : f)
        reach = std::max(reach, (v - X).norm());
    double          nearest = std::numeric_limits<double>::infinity(), s = 0;
    Eigen::Vector3d bary;
    for (const auto &f : faces)
      if (collision::segment_crosses_triangle(X, X + 2 * reach * d, f[0], f[1], f[2], s, bary))
        nearest = std::min(nearest, 2 * reach * s);
    return nearest;
  }

  bool
  Wound::separates(const Eigen::Vector3d &a, const Eigen::Vector3d &b) const
  {
    // strictly between the ends: a point on a face (a tract's exit) is on its lip's side;
    // only the faces whose box meets the segment's are tested (a spread point asks this
    // of every quadrature point within its radius)
    Eigen::AlignedBox3d segment(a);
    segment.extend(b);
    double          s = 0;
    Eigen::Vector3d bary;
    for (std::size_t i = 0; i < faces.size(); ++i)
      if (boxes[i].intersects(segment))
        {
          const auto &f = faces[i];
          if (collision::segment_crosses_triangle(a, b, f[0], f[1], f[2], s, bary) && s > 1e-9 && s < 1 - 1e-9)
            return true;
        }
    return false;
  }

  bool
  Wound::hides(const Eigen::Vector3d &a, const Eigen::Vector3d &b) const
  {
    return separates(a, b) || looks_out(a, b - a) || looks_out(b, a - b);
  }

  bool
  Wound::looks_out(const Eigen::Vector3d &p, const Eigen::Vector3d &d) const
  {
    // a direction within 1e-9 rad of a face's plane runs along it (round-off of points
    // on one flat face)
    const double along = 1e-9 * d.norm();
    bool         on    = false;
    for (std::size_t i = 0; i < faces.size(); ++i)
      if (boxes[i].exteriorDistance(p) <= tolerance)
        {
          const auto     &f = faces[i];
          Eigen::Vector3d bary;
          if ((collision::closest_point_on_triangle(p, f[0], f[1], f[2], bary) - p).norm() > tolerance)
            continue;
          if (d.dot(normals[i]) <= along)
            return false;
          on = true;
        }
    return on;
  }

  namespace
  {
    /// Angle between the needle's direction and the surface at a puncture, rad.
    double
    surface_angle(const coupling::PunctureEvent &e)
    {
      return std::asin(std::min(1.0, std::abs(e.direction.dot(e.normal))));
    }

    void
    measure(StitchEvaluation &s, const Wound &wound, const double R)
    {
      s.entry_angle         = surface_angle(s.entry);
      s.entry_edge_distance = wound.distance(s.entry.reference);
      s.bite_width = s.bite_depth = s.exit_edge_distance = s.exit_angle = nan;
      if (!s.exit)
        return;
      s.bite_width         = (s.exit->reference - s.entry.reference).norm();
      s.bite_depth         = s.bite_width <= 2 * R ? R - std::sqrt(R * R - s.bite_width * s.bite_width / 4) : nan;
      s.exit_edge_distance = wound.distance(s.exit->reference);
      s.exit_angle         = surface_angle(*s.exit);
    }

    Eigen::Vector3d
    midpoint(const StitchEvaluation &s)
    {
      return s.exit ? Eigen::Vector3d((s.entry.reference + s.exit->reference) / 2) : s.entry.reference;
    }

    /// Spacing and flags, once every stitch is measured.
    void
    judge(std::vector<StitchEvaluation> &stitches, const StitchLimits &limits)
    {
      for (auto &s : stitches)
        {
          s.spacing = nan;
          for (const auto &other : stitches)
            if (&other != &s)
              {
                const double d = (midpoint(other) - midpoint(s)).norm();
                s.spacing      = std::isnan(s.spacing) ? d : std::min(s.spacing, d);
              }
          s.edge_limit    = limits.edge_distance > 0 ? limits.edge_distance : s.bite_depth;
          s.spacing_limit = limits.spacing > 0 ? limits.spacing : 2 * s.edge_limit;
          // a comparison with NaN is false: no wound, no exit or no neighbour raises no flag
          s.too_close_to_edge      = s.entry_edge_distance < s.edge_limit || s.exit_edge_distance < s.edge_limit;
          s.too_close_to_neighbour = s.spacing < s.spacing_limit;
        }
    }
  } // namespace

  std::vector<StitchEvaluation>
  evaluate_stitches(const std::vector<coupling::PunctureEvent> &events, const Wound &wound, const double needle_radius,
                    const StitchLimits &limits)
  {
    std::vector<StitchEvaluation> stitches;
    bool                          open = false;
    for (const auto &e : events)
      {
        const bool entry = e.kind == "puncture_entry", exit = e.kind == "puncture_exit";
        if (!entry && !exit)
          continue;
        const bool face = wound.on_face(e.reference);
        if (!open && entry)
          {
            stitches.push_back({});
            stitches.back().entry = e;
            open                  = true;
          }
        else if (open && exit && !face)
          {
            stitches.back().exit = e;
            open                 = false;
          }
        else if (open)
          stitches.back().between.push_back(e);
        // an exit with no stitch open cannot follow an entry: nothing to add it to
      }
    for (auto &s : stitches)
      measure(s, wound, needle_radius);
    judge(stitches, limits);
    return stitches;
  }

  namespace
  {
    /// Entry, the punctures through the wound's faces, and the exit if there is one.
    std::size_t
    punctures(const StitchEvaluation &s)
    {
      return 1 + s.between.size() + (s.exit ? 1 : 0);
    }

    nlohmann::json
    number(const double v)
    {
      return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
    }

    nlohmann::json
    point(const Eigen::Vector3d &X)
    {
      return {X[0], X[1], X[2]};
    }
  } // namespace

  nlohmann::json
  stitches_json(const std::vector<StitchEvaluation> &stitches)
  {
    nlohmann::json list = nlohmann::json::array();
    int            edge = 0, neighbour = 0;
    for (const auto &s : stitches)
      {
        edge += s.too_close_to_edge;
        neighbour += s.too_close_to_neighbour;
        list.push_back({{"entry", point(s.entry.reference)},
                        {"exit", s.exit ? point(s.exit->reference) : nlohmann::json(nullptr)},
                        {"entry_time", s.entry.time},
                        {"exit_time", s.exit ? nlohmann::json(s.exit->time) : nlohmann::json(nullptr)},
                        {"punctures", punctures(s)},
                        {"crosses_wound", s.crosses_wound()},
                        {"bite_width", number(s.bite_width)},
                        {"bite_depth", number(s.bite_depth)},
                        {"entry_edge_distance", number(s.entry_edge_distance)},
                        {"exit_edge_distance", number(s.exit_edge_distance)},
                        {"spacing", number(s.spacing)},
                        {"entry_angle", number(s.entry_angle)},
                        {"exit_angle", number(s.exit_angle)},
                        {"edge_limit", number(s.edge_limit)},
                        {"spacing_limit", number(s.spacing_limit)},
                        {"too_close_to_edge", s.too_close_to_edge},
                        {"too_close_to_neighbour", s.too_close_to_neighbour}});
      }
    return {{"stitches", list},
            {"count", stitches.size()},
            {"too_close_to_edge", edge},
            {"too_close_to_neighbour", neighbour}};
  }

  std::string
  stitches_csv(const std::vector<StitchEvaluation> &stitches)
  {
    std::ostringstream out;
    out.precision(9);
    out << "stitch,entry_time [s],exit_time [s],entry_x [m],entry_y [m],entry_z [m],exit_x [m],exit_y [m],"
           "exit_z [m],punctures,crosses_wound,bite_width [m],bite_depth [m],entry_edge_distance [m],"
           "exit_edge_distance [m],spacing [m],entry_angle [rad],exit_angle [rad],edge_limit [m],"
           "spacing_limit [m],too_close_to_edge,too_close_to_neighbour\n";
    const auto cell = [&out](const double v) {
      out << ',';
      if (std::isfinite(v))
        out << v;
    };
    for (std::size_t k = 0; k < stitches.size(); ++k)
      {
        const auto           &s    = stitches[k];
        const Eigen::Vector3d none = Eigen::Vector3d::Constant(nan);
        const Eigen::Vector3d X    = s.exit ? s.exit->reference : none;
        out << k + 1;
        cell(s.entry.time);
        cell(s.exit ? s.exit->time : nan);
        for (int d = 0; d < 3; ++d)
          cell(s.entry.reference[d]);
        for (int d = 0; d < 3; ++d)
          cell(X[d]);
        out << ',' << punctures(s) << ',' << int(s.crosses_wound());
        for (const double v : {s.bite_width, s.bite_depth, s.entry_edge_distance, s.exit_edge_distance, s.spacing,
                               s.entry_angle, s.exit_angle, s.edge_limit, s.spacing_limit})
          cell(v);
        out << ',' << int(s.too_close_to_edge) << ',' << int(s.too_close_to_neighbour) << '\n';
      }
    return out.str();
  }
} // namespace suturesim::tearing
