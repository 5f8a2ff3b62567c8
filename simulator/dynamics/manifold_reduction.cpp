#include "simulator/dynamics/manifold_reduction.hpp"

#include <algorithm>
#include <cmath>

namespace arphys::dynamics {
namespace {
// Resting contacts sit at the contact gap (1 um); points this close to a group's
// closest touch as it does.
constexpr double kTouching_m = 1e-5;
}  // namespace

std::vector<collision::ManifoldPoint> reduce_manifold(std::vector<collision::ManifoldPoint> points, int limit) {
  if (static_cast<int>(points.size()) <= limit) return points;
  const double same_direction = std::cos(20.0 * M_PI / 180.0);
  std::vector<std::vector<int>> clusters;
  std::vector<Eigen::Vector3d> directions;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    int found = -1;
    for (std::size_t c = 0; c < clusters.size() && found < 0; ++c)
      if (points[i].normal_W.dot(directions[c]) > same_direction) found = static_cast<int>(c);
    if (found < 0) {
      clusters.push_back({i});
      directions.push_back(points[i].normal_W);
    } else {
      clusters[found].push_back(i);
    }
  }
  // Each cluster's closest point leads it; clusters in the order of their closest points.
  for (auto& cluster : clusters)
    std::iter_swap(cluster.begin(), std::min_element(cluster.begin(), cluster.end(), [&](int a, int b) {
                     return points[a].distance_m < points[b].distance_m;
                   }));
  std::stable_sort(clusters.begin(), clusters.end(), [&](const auto& a, const auto& b) {
    return points[a.front()].distance_m < points[b.front()].distance_m;
  });
  std::vector<char> taken(points.size(), 0);
  std::vector<collision::ManifoldPoint> kept;
  const auto keep = [&](int index) {
    if (static_cast<int>(kept.size()) >= limit || taken[index]) return;
    taken[index] = 1;
    kept.push_back(points[index]);
  };
  for (const auto& cluster : clusters) keep(cluster.front());
  // Each group's extremes along four directions across its normal: first among the
  // points that touch as its closest does (within kTouching_m of it), the support polygon
  // the body rests on, then among all of them. (Extremes of all alone kept a resting
  // bunny's footprint, its points 0.5-1 mm above the table, and dropped the vertices it
  // stood on but the closest: every step its solve tipped it about that one, the CCD met
  // the dropped ones at once, and two rounds of re-solves held it where it was.)
  const auto keep_extremes = [&](const std::vector<int>& group) {
    if (group.empty()) return;
    const Eigen::Vector3d n = points[group.front()].normal_W;
    const Eigen::Vector3d t1 = (std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(n).normalized();
    const Eigen::Vector3d t2 = n.cross(t1);
    for (const Eigen::Vector3d& axis : {t1, t2, Eigen::Vector3d((t1 + t2).normalized()), Eigen::Vector3d((t1 - t2).normalized())}) {
      int lo = group.front(), hi = group.front();
      for (int i : group) {
        if (points[i].point_B_W.dot(axis) < points[lo].point_B_W.dot(axis)) lo = i;
        if (points[i].point_B_W.dot(axis) > points[hi].point_B_W.dot(axis)) hi = i;
      }
      keep(lo);
      keep(hi);
    }
  };
  for (const auto& cluster : clusters) {
    std::vector<int> touching;
    for (int i : cluster)
      if (points[i].distance_m <= points[cluster.front()].distance_m + kTouching_m) touching.push_back(i);
    keep_extremes(touching);
  }
  for (const auto& cluster : clusters) keep_extremes(cluster);
  return kept;
}

}  // namespace arphys::dynamics
