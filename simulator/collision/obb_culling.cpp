#include "simulator/collision/obb_culling.hpp"

namespace arphys::collision {
namespace {

// Sums of at most six non-negative products, each rounded once, and the additions:
// the relative error is below 12 * 2^-53 < 2e-15, so scaling by (1 + 1e-14) gives a
// proven upper bound of the exact value.
inline double round_up_sum(double s) { return s * (1 + 1e-14) + 1e-300; }

}  // namespace

namespace {
constexpr double kSlack = 1e-13;
// |x| >= lower and the bound r: separated when lower certainly exceeds r.
inline bool exceeds(double mid_abs, double rad, double r) {
  return mid_abs - rad > r * (1 + kSlack) + (mid_abs + rad) * kSlack + 1e-300;
}
}  // namespace

bool obbs_separated(const Obb& a, const Obb& b, const MidRadMatrix& R_AB, const MidRadVector& b_center_A) {
  // Everything in A's box frame: d = center offset, C = B's box axes.
  const Eigen::Matrix3d Ea_T = a.axes.transpose();
  const Eigen::Matrix3d C = Ea_T * (R_AB.mid * b.axes);
  const Eigen::Matrix3d C_rad = Ea_T.cwiseAbs() * (R_AB.rad * b.axes.cwiseAbs());
  const Eigen::Vector3d d = Ea_T * (b_center_A.mid - a.center);
  const Eigen::Vector3d d_rad = Ea_T.cwiseAbs() * b_center_A.rad;
  const Eigen::Matrix3d absC = C.cwiseAbs() + C_rad;  // bounds |C(t)|
  const Eigen::Vector3d abs_d = d.cwiseAbs();
  const Eigen::Vector3d& ha = a.half_extents_m;
  const Eigen::Vector3d& hb = b.half_extents_m;

  for (int i = 0; i < 3; ++i)  // A's axes
    if (exceeds(abs_d[i], d_rad[i], ha[i] + absC.row(i).dot(hb))) return true;
  for (int j = 0; j < 3; ++j) {  // B's axes: sum_i C_ij d_i
    const double mid = std::abs(C.col(j).dot(d));
    const double rad = C.col(j).cwiseAbs().dot(d_rad) + C_rad.col(j).dot(abs_d + d_rad);
    if (exceeds(mid, rad, absC.col(j).dot(ha) + hb[j])) return true;
  }
  for (int i = 0; i < 3; ++i) {  // a_i x b_j: pointwise identities of the orthonormal C(t)
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double mid = std::abs(d[i2] * C(i1, j) - d[i1] * C(i2, j));
      const double rad = abs_d[i2] * C_rad(i1, j) + d_rad[i2] * absC(i1, j) + abs_d[i1] * C_rad(i2, j) +
                         d_rad[i1] * absC(i2, j);
      const double r = ha[i1] * absC(i2, j) + ha[i2] * absC(i1, j) + hb[j1] * absC(i, j2) + hb[j2] * absC(i, j1);
      if (exceeds(mid, rad, r)) return true;
    }
  }
  return false;
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
