#include "simulator/collision/discrete_query.hpp"

#include <limits>

#include "simulator/collision/obb_culling.hpp"
#include "simulator/collision/triangle_distance.hpp"

namespace arphys::collision {
namespace {

// Depth-first over node pairs whose boxes come within `margin()` of each other,
// descending the larger box first; `leaf(tA, tB)` sees the surviving triangle pairs
// and returns false to stop.
template <typename Margin, typename Leaf>
void traverse_close_pairs(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                          const geometry::Pose& X_WB, Margin margin, Leaf leaf) {
  const geometry::Pose X_AB = X_WA.inverse() * X_WB;
  const Eigen::Matrix3d R_AB = X_AB.linear();
  const Eigen::Vector3d p_AB = X_AB.translation();
  const auto& na = A.tree().nodes();
  const auto& nb = B.tree().nodes();
  std::vector<std::pair<int, int>> stack{{0, 0}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    if (obbs_separated(na[a].box, nb[b].box, R_AB, p_AB, margin())) continue;
    if (na[a].is_leaf() && nb[b].is_leaf()) {
      if (!leaf(na[a].triangle, nb[b].triangle)) return;
      continue;
    }
    const bool split_a = !na[a].is_leaf() && (nb[b].is_leaf() || na[a].box.half_extents_m.maxCoeff() >=
                                                                      nb[b].box.half_extents_m.maxCoeff());
    if (split_a) {
      stack.push_back({na[a].first_child + 1, b});
      stack.push_back({na[a].first_child, b});
    } else {
      stack.push_back({a, nb[b].first_child + 1});
      stack.push_back({a, nb[b].first_child});
    }
  }
}

void corners_in_world(const CollisionMesh& M, int triangle, const geometry::Pose& X_W, Eigen::Vector3d out[3]) {
  M.corners(triangle, out);
  for (int k = 0; k < 3; ++k) out[k] = X_W * out[k];
}

}  // namespace

std::optional<TrianglePair> find_intersection(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                                              const geometry::Pose& X_WB) {
  std::optional<TrianglePair> found;
  traverse_close_pairs(A, X_WA, B, X_WB, [] { return 0.0; }, [&](int ta, int tb) {
    Eigen::Vector3d a[3], b[3];
    corners_in_world(A, ta, X_WA, a);
    corners_in_world(B, tb, X_WB, b);
    if (triangle_triangle_distance(a, b) == 0.0) {
      found = TrianglePair{ta, tb};
      return false;
    }
    return true;
  });
  return found;
}

SeparationResult separation(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                            const geometry::Pose& X_WB, double max_distance_m) {
  SeparationResult best;
  best.distance_m = std::numeric_limits<double>::infinity();
  double bound = max_distance_m;
  traverse_close_pairs(A, X_WA, B, X_WB, [&] { return std::isfinite(bound) ? bound : 1e300; }, [&](int ta, int tb) {
    Eigen::Vector3d a[3], b[3], pa, pb;
    corners_in_world(A, ta, X_WA, a);
    corners_in_world(B, tb, X_WB, b);
    const double d = triangle_triangle_distance(a, b, &pa, &pb);
    if (d < best.distance_m && d <= max_distance_m) {
      best = {d, pa, pb, {ta, tb}};
      bound = d;
    }
    return d > 0;
  });
  return best;
}

std::vector<ManifoldPoint> contact_manifold(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                                            const geometry::Pose& X_WB, double tolerance_m) {
  std::vector<ManifoldPoint> points;
  traverse_close_pairs(A, X_WA, B, X_WB, [&] { return tolerance_m; }, [&](int ta, int tb) {
    Eigen::Vector3d a[3], b[3], pa, pb;
    corners_in_world(A, ta, X_WA, a);
    corners_in_world(B, tb, X_WB, b);
    const double d = triangle_triangle_distance(a, b, &pa, &pb);
    if (d <= tolerance_m) {
      Eigen::Vector3d n = pb - pa;
      if (n.norm() > 1e-12 * (1 + pa.norm())) {
        n.normalize();
      } else {
        n = (a[1] - a[0]).cross(a[2] - a[0]).normalized();
      }
      points.push_back({pa, pb, n, d, {ta, tb}});
    }
    return true;
  });
  return points;
}

}  // namespace arphys::collision
