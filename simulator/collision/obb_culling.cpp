#include "simulator/collision/obb_culling.hpp"

namespace arphys::collision {
namespace {

// Sums of at most six non-negative products, each rounded once, and the additions:
// the relative error is below 12 * 2^-53 < 2e-15, so scaling by (1 + 1e-14) gives a
// proven upper bound of the exact value.
inline double round_up_sum(double s) { return s * (1 + 1e-14) + 1e-300; }

}  // namespace

namespace {
// Every quantity below is a sum of at most a dozen products of doubles, each within a
// few ulps; a relative slack of 1e-13 on both sides of a comparison covers them.
constexpr double kSlack = 1e-13;
// |x| >= lower and the bound r: separated when lower certainly exceeds r.
inline bool exceeds(double mid_abs, double rad, double r) {
  return mid_abs - rad > r * (1 + kSlack) + (mid_abs + rad) * kSlack + 1e-300;
}
}  // namespace

bool obbs_separated(const Obb& a, const Obb& b, const Eigen::Matrix3d& R_AB, const MovingPoint& center,
                    double angular_speed) {
  const double h = center.half_width;
  // Sweep per unit |L| from turning and from the velocity's change, plus rounding of mid.
  const double isotropic = h * (center.velocity_rad + angular_speed * b.radius_m) + center.rounding;
  // Bounding spheres first: cheap, and they settle most far-apart pairs.
  const double reach = a.radius_m + b.radius_m + h * center.velocity.norm() + isotropic;
  if ((center.mid - a.center).squaredNorm() > reach * reach * (1 + kSlack)) return true;
  // Everything in A's box frame: d = center offset and v = its velocity at tm, C = B's box axes.
  const Eigen::Matrix3d Ea_T = a.axes.transpose();
  const Eigen::Matrix3d C = Ea_T * (R_AB * b.axes);
  const Eigen::Vector3d d = Ea_T * (center.mid - a.center);
  const Eigen::Vector3d v = Ea_T * center.velocity;
  const Eigen::Matrix3d absC = C.cwiseAbs();
  const Eigen::Vector3d& ha = a.half_extents_m;
  const Eigen::Vector3d& hb = b.half_extents_m;

  for (int i = 0; i < 3; ++i) {  // A's axes
    const double r = ha[i] + absC.row(i).dot(hb) + h * std::abs(v[i]) + isotropic;
    if (exceeds(std::abs(d[i]), 0.0, r)) return true;
  }
  for (int j = 0; j < 3; ++j) {  // B's axes at tm
    const double r = absC.col(j).dot(ha) + hb[j] + h * std::abs(C.col(j).dot(v)) + isotropic;
    if (exceeds(std::abs(C.col(j).dot(d)), 0.0, r)) return true;
  }
  for (int i = 0; i < 3; ++i) {  // a_i x b_j, with |L| <= 1 bounding the isotropic sweep
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double proj = d[i2] * C(i1, j) - d[i1] * C(i2, j);
      const double speed = std::abs(v[i2] * C(i1, j) - v[i1] * C(i2, j));
      const double r = ha[i1] * absC(i2, j) + ha[i2] * absC(i1, j) + hb[j1] * absC(i, j2) + hb[j2] * absC(i, j1) +
                       h * speed + isotropic;
      if (exceeds(std::abs(proj), 0.0, r)) return true;
    }
  }
  return false;
}

double obb_sweep_m(const Obb& b, const MovingPoint& center, double angular_speed) {
  return center.half_width * (center.velocity.norm() + center.velocity_rad + angular_speed * b.radius_m);
}

bool obbs_separated(const Obb& a, const Obb& b, const Eigen::Matrix3d& R_AB, const Eigen::Vector3d& p_AB,
                    double margin_m) {
  const Eigen::Matrix3d C = a.axes.transpose() * R_AB * b.axes;
  const Eigen::Vector3d d = a.axes.transpose() * (R_AB * b.center + p_AB - a.center);
  const Eigen::Matrix3d absC = C.cwiseAbs().array() + 1e-14;  // covers rounding and near-parallel axes
  const Eigen::Vector3d ha = a.half_extents_m.array() + 0.5 * margin_m;
  const Eigen::Vector3d hb = b.half_extents_m.array() + 0.5 * margin_m;
  for (int i = 0; i < 3; ++i)
    if (std::abs(d[i]) > round_up_sum(ha[i] + absC.row(i).dot(hb))) return true;
  for (int j = 0; j < 3; ++j)
    if (std::abs(C.col(j).dot(d)) > round_up_sum(absC.col(j).dot(ha) + hb[j])) return true;
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double proj = d[i2] * C(i1, j) - d[i1] * C(i2, j);
      const double r = ha[i1] * absC(i2, j) + ha[i2] * absC(i1, j) + hb[j1] * absC(i, j2) + hb[j2] * absC(i, j1);
      if (std::abs(proj) > round_up_sum(r)) return true;
    }
  }
  return false;
}

}  // namespace arphys::collision
