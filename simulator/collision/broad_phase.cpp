#include "simulator/collision/broad_phase.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "simulator/collision/screw_enclosure.hpp"

namespace arphys::collision {

Eigen::AlignedBox3d swept_bounds(const geometry::ScrewMotion& motion, const Eigen::Vector3d& center_B, double radius_m,
                                 int pieces) {
  if (!std::isfinite(radius_m)) {
    const double inf = std::numeric_limits<double>::infinity();
    return Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-inf), Eigen::Vector3d::Constant(inf));
  }
  // The point's path in the world: relative to a still frame at the identity.
  const geometry::ScrewMotion world(geometry::Pose::Identity(), geometry::Pose::Identity());
  const RelativeMotion rel(world, motion);
  Eigen::AlignedBox3d box;
  for (int k = 0; k < pieces; ++k) {
    const Interval T{static_cast<double>(k) / pieces, static_cast<double>(k + 1) / pieces};
    const MidRadVector ball = rel.moving_point(center_B, T).ball();
    const Eigen::Vector3d reach = ball.rad.array() + radius_m;
    box.extend(ball.mid - reach);
    box.extend(ball.mid + reach);
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
