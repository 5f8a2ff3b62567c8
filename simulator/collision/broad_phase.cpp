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
  std::vector<int> order(boxes.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return boxes[a].min().x() < boxes[b].min().x(); });
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> active;  // boxes whose x range still reaches the sweep line
  for (int i : order) {
    const double x = boxes[i].min().x();
    active.erase(std::remove_if(active.begin(), active.end(), [&](int j) { return boxes[j].max().x() < x; }),
                 active.end());
    for (int j : active) {
      const auto& a = boxes[i];
      const auto& b = boxes[j];
      if (a.min().y() <= b.max().y() && b.min().y() <= a.max().y() && a.min().z() <= b.max().z() &&
          b.min().z() <= a.max().z())
        pairs.emplace_back(std::min(i, j), std::max(i, j));
    }
    active.push_back(i);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace arphys::collision
