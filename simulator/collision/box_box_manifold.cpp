#include "simulator/collision/box_box_manifold.hpp"

#include <cmath>

#include "simulator/collision/convex_manifold.hpp"
#include "simulator/collision/triangle_distance.hpp"

namespace arphys::collision {
namespace {

struct Box {
  Eigen::Matrix3d axes;         // columns: the box's axes in the world
  Eigen::Vector3d center;
  Eigen::Vector3d half;
  double radius_along(const Eigen::Vector3d& n) const { return (axes.transpose() * n).cwiseAbs().dot(half); }
};

// Face contact: `ref`'s face with outward normal n (pointing at `inc`) against inc's most
// opposed face, appended as manifold points from A to B (`ref_is_A` says which is which).
void face_contact(const Box& ref, const Box& inc, const Eigen::Vector3d& n, bool ref_is_A, double tolerance,
                  std::vector<ManifoldPoint>* points) {
  // Reference face: the axis of ref most aligned with n.
  const Eigen::Vector3d local_n = ref.axes.transpose() * n;
  int r = 0;
  local_n.cwiseAbs().maxCoeff(&r);
  const Eigen::Vector3d face_n = ref.axes.col(r) * (local_n[r] > 0 ? 1.0 : -1.0);
  const Eigen::Vector3d face_center = ref.center + ref.half[r] * face_n;
  // Incident face: inc's face whose outward normal is most against face_n.
  const Eigen::Vector3d inc_n = inc.axes.transpose() * face_n;
  int k = 0;
  inc_n.cwiseAbs().maxCoeff(&k);
  const double side = inc_n[k] > 0 ? -1.0 : 1.0;
  const Eigen::Vector3d inc_center = inc.center + side * inc.half[k] * inc.axes.col(k);
  const int u = (k + 1) % 3, v = (k + 2) % 3;
  const Eigen::Vector3d eu = inc.half[u] * inc.axes.col(u), ev = inc.half[v] * inc.axes.col(v);
  std::vector<Eigen::Vector3d> polygon{inc_center + eu + ev, inc_center - eu + ev, inc_center - eu - ev,
                                       inc_center + eu - ev};
  for (int i = 1; i <= 2; ++i) {
    const int a = (r + i) % 3;
    const Eigen::Vector3d axis = ref.axes.col(a);
    const double c = axis.dot(ref.center);
    polygon = clip_to_half_space(polygon, axis, c + ref.half[a]);
    polygon = clip_to_half_space(polygon, -axis, -c + ref.half[a]);
  }
  for (const Eigen::Vector3d& p : polygon) {
    const double d = face_n.dot(p - face_center);
    if (d > tolerance) continue;
    const Eigen::Vector3d on_face = p - d * face_n;
    if (ref_is_A)
      points->push_back({on_face, p, face_n, d, {-1, -1}});
    else
      points->push_back({p, on_face, -face_n, d, {-1, -1}});
  }
}

}  // namespace

std::vector<ManifoldPoint> box_box_manifold(const Eigen::Vector3d& size_A_m, const geometry::Pose& X_WA,
                                            const Eigen::Vector3d& size_B_m, const geometry::Pose& X_WB,
                                            double tolerance_m) {
  const Box A{X_WA.linear(), X_WA.translation(), 0.5 * size_A_m};
  const Box B{X_WB.linear(), X_WB.translation(), 0.5 * size_B_m};
  const Eigen::Vector3d d = B.center - A.center;
  // Gap along an axis, the axis oriented from A to B.
  auto gap_along = [&](Eigen::Vector3d n) {
    if (n.dot(d) < 0) n = -n;
    return std::make_pair(n.dot(d) - A.radius_along(n) - B.radius_along(n), n);
  };
  double best_face = -std::numeric_limits<double>::infinity();
  Eigen::Vector3d face_normal;
  bool face_of_A = true;
  for (int i = 0; i < 6; ++i) {
    const auto [gap, n] = gap_along(i < 3 ? A.axes.col(i) : B.axes.col(i - 3));
    if (gap > tolerance_m) return {};
    if (gap > best_face) {
      best_face = gap;
      face_normal = n;
      face_of_A = i < 3;
    }
  }
  double best_edge = -std::numeric_limits<double>::infinity();
  Eigen::Vector3d edge_normal;
  int edge_i = -1, edge_j = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector3d c = A.axes.col(i).cross(B.axes.col(j));
      if (c.norm() < 1e-6) continue;  // parallel edges: the face axes cover them
      // An edge axis within half a degree of a face axis (two boxes stacked with a
      // twist: A's x edge and B's y edge cross in the contact plane) measures the same
      // gap as the face, give or take rounding and tilt, but would reduce a face
      // contact to the one point where two edges cross: the top box then tips over it.
      const Eigen::Vector3d axis = c.normalized();
      if ((A.axes.transpose() * axis).cwiseAbs().maxCoeff() > 0.99996 ||
          (B.axes.transpose() * axis).cwiseAbs().maxCoeff() > 0.99996)
        continue;
      const auto [gap, n] = gap_along(axis);
      if (gap > tolerance_m) return {};
      if (gap > best_edge) {
        best_edge = gap;
        edge_normal = n;
        edge_i = i;
        edge_j = j;
      }
    }
  std::vector<ManifoldPoint> points;
  // Prefer a face: an edge axis must be clearly better (rounding makes near-parallel
  // edges look as good as the face they lie in).
  const double margin = 1e-9 + 1e-6 * std::abs(best_face);
  if (edge_i >= 0 && best_edge > best_face + margin) {
    // The supporting edges: A's edge along axis i furthest along n, B's furthest against it.
    Eigen::Vector3d on_A = A.center, on_B = B.center;
    for (int k = 0; k < 3; ++k) {
      if (k != edge_i) on_A += A.half[k] * (A.axes.col(k).dot(edge_normal) > 0 ? 1.0 : -1.0) * A.axes.col(k);
      if (k != edge_j) on_B -= B.half[k] * (B.axes.col(k).dot(edge_normal) > 0 ? 1.0 : -1.0) * B.axes.col(k);
    }
    const Eigen::Vector3d ea = A.half[edge_i] * A.axes.col(edge_i), eb = B.half[edge_j] * B.axes.col(edge_j);
    Eigen::Vector3d pa, pb;
    segment_segment_distance(on_A - ea, on_A + ea, on_B - eb, on_B + eb, &pa, &pb);
    // Closest points at an end of either edge: the edges do not cross, the nearest
    // features are a vertex and something else; the face axis answers that better.
    const bool crossing = std::abs((pa - on_A).dot(ea)) < (1 - 1e-9) * ea.squaredNorm() &&
                          std::abs((pb - on_B).dot(eb)) < (1 - 1e-9) * eb.squaredNorm();
    if (crossing) {
      const double distance = edge_normal.dot(pb - pa);
      if (distance <= tolerance_m) points.push_back({pa, pb, edge_normal, distance, {-1, -1}});
      return points;
    }
  }
  if (face_of_A)
    face_contact(A, B, face_normal, true, tolerance_m, &points);
  else
    face_contact(B, A, -face_normal, false, tolerance_m, &points);
  return points;
}

}  // namespace arphys::collision
