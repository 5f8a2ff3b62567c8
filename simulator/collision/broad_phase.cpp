#include "simulator/collision/broad_phase.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace arphys::collision {

Eigen::AlignedBox3d swept_bounds(const geometry::ScrewMotion& motion, const Eigen::Vector3d& center_B, double radius_m) {
  if (!std::isfinite(radius_m)) {
    const double inf = std::numeric_limits<double>::infinity();
    return Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-inf), Eigen::Vector3d::Constant(inf));
  }
  // Seen along the screw axis u the point moves on a circular arc of the screw's angle
  // theta (<= pi) between its end positions, so it stays within the arc's sagitta
  // (c/2) tan(theta/4) of the chord (c: the chord normal to u); along u it moves
  // linearly. The path is thus inside the parallelogram spanned by that chord and the
  // axial travel, widened by the sagitta: its four corners, widened, bound it. (Closed
  // form; enclosing the path piecewise with interval arithmetic was 6 % of a pile's step.)
  // A large turn is split into pieces of at most half a radian (the same screw, at a
  // fraction of the angle), where the bound stays tight.
  const int pieces = std::max(1, static_cast<int>(std::ceil(motion.angle_rad() / 0.5)));
  const Eigen::Vector3d& u = motion.axis();
  const double tan_quarter = std::tan(0.25 * motion.angle_rad() / pieces);
  Eigen::AlignedBox3d box;
  Eigen::Vector3d p0 = motion.start() * center_B;
  for (int k = 1; k <= pieces; ++k) {
    const Eigen::Vector3d p1 = k == pieces ? Eigen::Vector3d(motion.end() * center_B)
                                           : Eigen::Vector3d(motion.pose_at(static_cast<double>(k) / pieces) * center_B);
    const Eigen::Vector3d axial = (p1 - p0).dot(u) * u;
    const double chord_m = (p1 - p0 - axial).norm();
    // Rounding of the poses and of the screw's own parameters: a relative 1e-12 of the
    // coordinates involved keeps the bound certified.
    const double rounding_m = 1e-12 * (p0.cwiseAbs().maxCoeff() + p1.cwiseAbs().maxCoeff() + chord_m + 1.0);
    const double reach = radius_m + 0.5 * chord_m * tan_quarter + rounding_m;
    for (const Eigen::Vector3d& corner : {p0, p1, Eigen::Vector3d(p0 + axial), Eigen::Vector3d(p1 - axial)}) {
      box.extend(Eigen::Vector3d(corner.array() - reach));
      box.extend(Eigen::Vector3d(corner.array() + reach));
    }
    p0 = p1;
  }
  return box;
}

std::vector<std::pair<int, int>> overlapping_pairs(const std::vector<Eigen::AlignedBox3d>& boxes) {
  // A box with a NaN coordinate overlaps nothing; in the sweep it would break the order
  // (and stop a scan early, hiding pairs).
  std::vector<int> order;
  order.reserve(boxes.size());
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i)
    if (!boxes[i].min().array().isNaN().any() && !boxes[i].max().array().isNaN().any()) order.push_back(i);
  const int n = static_cast<int>(order.size());
  std::sort(order.begin(), order.end(), [&](int a, int b) { return boxes[a].min().x() < boxes[b].min().x(); });
  // The boxes in sweep order, contiguous: each box is tested against the ones after it
  // that start before it ends along x (in a pile, a hundred or more: the scan is the
  // broad phase's whole cost, and indirect access through `order` doubled it).
  std::vector<Eigen::AlignedBox3d> sorted(order.size());
  for (int k = 0; k < n; ++k) sorted[k] = boxes[order[k]];
  std::vector<std::pair<int, int>> pairs;
  for (int k = 0; k < n; ++k) {
    const Eigen::AlignedBox3d& a = sorted[k];
    const double end_x = a.max().x();
    for (int l = k + 1; l < n && sorted[l].min().x() <= end_x; ++l) {
      const Eigen::AlignedBox3d& b = sorted[l];
      if (a.min().y() <= b.max().y() && b.min().y() <= a.max().y() && a.min().z() <= b.max().z() &&
          b.min().z() <= a.max().z())
        pairs.emplace_back(std::min(order[k], order[l]), std::max(order[k], order[l]));
    }
  }
  // Sorted by two counting passes (second index, then stably the first): linear in the
  // pairs, where a comparison sort of a pile's thousands of pairs cost as much as the sweep.
  std::vector<std::pair<int, int>> by_second(pairs.size());
  std::vector<int> start(boxes.size() + 1);
  const auto counting_pass = [&](const std::vector<std::pair<int, int>>& in, std::vector<std::pair<int, int>>& out,
                                 int std::pair<int, int>::*key) {
    std::fill(start.begin(), start.end(), 0);
    for (const auto& pair : in) ++start[pair.*key + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    for (const auto& pair : in) out[start[pair.*key]++] = pair;
  };
  counting_pass(pairs, by_second, &std::pair<int, int>::second);
  counting_pass(by_second, pairs, &std::pair<int, int>::first);
  return pairs;
}

}  // namespace arphys::collision
