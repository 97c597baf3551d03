#include <suturesim/realtime/free_needle.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <stdexcept>

namespace suturesim::realtime
{
  FreeNeedle::FreeNeedle(const tools::CurvedNeedle &needle, const double density, const double drag)
    : R(needle.radius())
    , B(drag)
  {
    if (!(density > 0) || !(drag > 0))
      throw std::invalid_argument("a free needle needs a positive density and drag");
    if (needle.straight()) // its centroid and turning drag below are an arc's
      throw std::invalid_argument("a double-pointed needle is always held by one of the Endo Stitch's jaws");
    const double d   = needle.wire_diameter();
    const double phi = needle.arc_angle();
    m                = density * M_PI * d * d / 4 * needle.length();
    body_centroid    = R * Eigen::Vector3d(std::sin(phi), 1 - std::cos(phi), 0) / phi;
  }

  void
  add_point_stiffness(Matrix6d &K, const Eigen::Vector3d &r, const double k)
  {
    Eigen::Matrix<double, 3, 6> J;
    J.leftCols<3>().setIdentity();
    J.rightCols<3>() << 0, r[2], -r[1], -r[2], 0, r[0], r[1], -r[0], 0; // −[r]×
    K.noalias() += k * J.transpose() * J;
  }

  void
  FreeNeedle::release(const tools::Pose &pose)
  {
    current     = pose;
    last_force = Eigen::Vector3d::Zero();
  }

  void
  FreeNeedle::step(const Eigen::Vector3d &force, const Eigen::Vector3d &moment, const Eigen::Vector3d &gravity,
                   const Matrix6d &K, const double dt)
  {
    const Eigen::Vector3d c = centroid();
    last_force              = force + m * gravity;
    // the moment about the centroid (the weight acts there)
    const Eigen::Vector3d moment_c = moment - (c - current.position).cross(force);

    Matrix6d A = K;
    A.diagonal().head<3>().array() += B / dt;
    A.diagonal().tail<3>().array() += B * R * R / dt;
    Eigen::Matrix<double, 6, 1> load;
    load << last_force, moment_c;
    const Eigen::Matrix<double, 6, 1> delta = A.ldlt().solve(load);
    const Eigen::Vector3d c_new = c + delta.head<3>();
    const Eigen::Vector3d theta = delta.tail<3>();
    const double   angle = theta.norm();
    if (angle > 0)
      current.orientation = (Eigen::Quaterniond(Eigen::AngleAxisd(angle, theta / angle)) * current.orientation).normalized();
    current.position = c_new - current.orientation * body_centroid;
  }
} // namespace suturesim::realtime
