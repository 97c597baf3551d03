#include <suturesim/collision/proximity.h>
#include <suturesim/tearing/ligament_tear.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace suturesim::tearing
{
  void
  LigamentTearParameters::declare(ParameterDeclarations &d)
  {
    d.add_real("Ligament strength", 0, 0, 1e9,
               "Seed 003's tearing in the realtime path: a pierce point on the skin tears the tissue when its "
               "tension exceeds this times its weakest ligament (the shorter of the distance along its pull to "
               "the wound's faces and the distance to the nearest other insertion on its side; "
               "tearing/ligament_tear.h); 0: no tearing. Unit: N/m. Range: [0, 1e9].");
  }

  LigamentTearParameters
  LigamentTearParameters::parse(const ParameterValues &v)
  {
    LigamentTearParameters p;
    p.strength = v.real("Ligament strength");
    return p;
  }

  std::string
  to_string(const TractEnd end)
  {
    switch (end)
      {
      case TractEnd::top:
        return "top";
      case TractEnd::groove:
        return "groove";
      case TractEnd::bottom:
        return "bottom";
      }
    return "";
  }

  std::string
  tear_kind(const TractEnd far_end)
  {
    return far_end == TractEnd::bottom ? "tear_through" : "tear_into";
  }

  Ligament
  weakest_ligament(const Wound &wound, const Eigen::Vector3d &X, const Eigen::Vector3d &pull,
                   const std::vector<Eigen::Vector3d> &insertions)
  {
    Ligament l;
    l.length = std::numeric_limits<double>::infinity();
    if (wound.present())
      if (const double to_wound = wound.ray(X, pull); std::isfinite(to_wound))
        {
          l.length   = to_wound;
          l.to_wound = true;
          l.end      = X + to_wound * pull;
        }
    double scale = l.to_wound ? l.length : 0;
    for (const auto &Y : insertions)
      scale = std::max(scale, (Y - X).norm());
    for (std::size_t j = 0; j < insertions.size(); ++j)
      {
        const double distance = (insertions[j] - X).norm();
        if (distance <= 1e-12 * scale || distance >= l.length || wound.separates(X, insertions[j]))
          continue;
        l.length    = distance;
        l.to_wound  = false;
        l.insertion = static_cast<std::ptrdiff_t>(j);
        l.end       = insertions[j];
      }
    return l;
  }

  TearSurface::TearSurface(const Eigen::Vector3d &top, const Eigen::Vector3d &far, const Eigen::Vector3d &path,
                           const double margin)
      : origin(top - margin * (far - top)), along_tract((1 + 2 * margin) * (far - top)), along_path((1 + margin) * path)
  {
  }

  bool
  TearSurface::crosses(const Eigen::Vector3d &a, const Eigen::Vector3d &b) const
  {
    // the parallelogram as two triangles; a segment in its plane does not cut across it
    const Eigen::Vector3d corner = origin + along_tract + along_path;
    double                s      = 0;
    Eigen::Vector3d       bary;
    return collision::segment_crosses_triangle(a, b, origin, origin + along_tract, corner, s, bary) ||
           collision::segment_crosses_triangle(a, b, origin, corner, origin + along_path, s, bary);
  }
} // namespace suturesim::tearing
