#include "simulator/collision/shape_query.hpp"

#include "simulator/collision/separation_certificate.hpp"

#include <stdexcept>

#include "simulator/collision/box_box_manifold.hpp"
#include "simulator/collision/convex_advancement.hpp"
#include "simulator/collision/convex_manifold.hpp"
#include "simulator/collision/feature_toi.hpp"
#include "simulator/collision/screw_enclosure.hpp"
#include "simulator/collision/separation_certificate.hpp"
#include "simulator/collision/triangle_distance.hpp"

namespace arphys::collision {
namespace {

using geometry::ScrewMotion;

// Radius of the ball every point of a moving point's enclosure lies in.
double sweep_radius(const MovingPoint& p) {
  return (p.half_width * (p.velocity.norm() + p.velocity_rad) + p.rounding) * (1 + 1e-12);
}

// A hit at t (kNoContact: none), point and normal for the caller to fill. The kind
// says the point and normal are a meeting's (a caller tells them from a work budget's
// stop, which has none: a simulation made no constraint of a plane's or a sphere's
// meetings and cut its step at each instead).
ContinuousResult hit_at(double t) {
  ContinuousResult result;
  if (t == kNoContact) return result;
  result.collides = true;
  result.time_of_impact = t;
  result.features.kind = FeaturePair::kPrimitive;
  return result;
}

// Shared driver of the tree traversals against a plane or a sphere: depth first over
// (node, time interval), earliest first, splitting time when the motion over the
// interval (`node_may_touch` reports it through its last argument) dominates the
// node's size.
template <typename NodeMayTouch, typename Leaf>
void traverse_in_time(const ObbTree& tree, const RelativeMotion& rel, const ContinuousOptions& options,
                      const double& best, NodeMayTouch node_may_touch, Leaf leaf) {
  struct Task {
    int node;
    double t0, t1;
  };
  std::vector<Task> stack{{0, 0.0, 1.0}};
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    if (task.t0 > best) continue;
    const Interval T{task.t0, std::min(task.t1, best)};
    const RelativeMotion::Snapshot snapshot = rel.snapshot(T);
    const ObbNode& node = tree.nodes()[task.node];
    double sweep = 0;
    if (!node_may_touch(node.box, snapshot, sweep)) continue;
    if (node.is_leaf()) {
      leaf(node.triangle, T);
      continue;
    }
    const double size = node.box.half_extents_m.maxCoeff();
    if (sweep > size && T.width() > options.min_culling_interval) {
      const double mid = T.mid();
      stack.push_back({task.node, mid, T.hi});  // later half below: popped second
      stack.push_back({task.node, T.lo, mid});
    } else {
      stack.push_back({node.first_child + 1, T.lo, T.hi});
      stack.push_back({node.first_child, T.lo, T.hi});
    }
  }
}

// Mesh B against the half-space z <= 0 of A (the plane).
ContinuousResult plane_vs_mesh(const ScrewMotion& plane, const CollisionMesh& mesh, const ScrewMotion& motion,
                               const ContinuousOptions& options) {
  const RelativeMotion rel(plane, motion);  // mesh points in the plane's frame
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double best = kNoContact;
  int best_vertex = -1;
  const double angular_speed = rel.angular_speed();
  auto node_may_touch = [&](const Obb& box, const RelativeMotion::Snapshot& s, double& sweep) {
    const MovingPoint center = rel.moving_point(box.center, s);
    const double box_sweep = s.h * angular_speed * box.half_extents_m.norm();
    sweep = sweep_radius(center) + box_sweep;
    const double extent = (s.X_AB.linear() * box.axes).row(2).cwiseAbs().dot(box.half_extents_m) + box_sweep;
    return center.project(up, 0.0).lo - extent * (1 + 1e-12) <= 0;
  };
  auto leaf = [&](int triangle, const Interval& T) {
    for (int k = 0; k < 3; ++k) {
      const int vertex = mesh.mesh().triangles[triangle][k];
      const Eigen::Vector3d& p = mesh.mesh().vertices_m[vertex];
      const double t = first_candidate_time({T.lo, std::min(T.hi, best)}, options.time_tolerance,
                                            [&](const Interval& W) { return rel.moving_point(p, W).project(up, 0.0).lo <= 0; });
      if (t < best) best = t, best_vertex = vertex;
    }
  };
  traverse_in_time(mesh.tree(), rel, options, best, node_may_touch, leaf);
  ContinuousResult result = hit_at(best);
  if (!result.collides) return result;
  result.point_W = motion.pose_at(best) * mesh.mesh().vertices_m[best_vertex];
  result.normal_W = plane.pose_at(best).linear() * up;
  return result;
}

// Sphere B (centre at its body origin) against the half-space z <= 0 of A.
ContinuousResult plane_vs_sphere(const ScrewMotion& plane, double radius, const ScrewMotion& motion,
                                 const ContinuousOptions& options) {
  const RelativeMotion rel(plane, motion);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const double t = first_candidate_time({0.0, 1.0}, options.time_tolerance, [&](const Interval& T) {
    return rel.moving_point(Eigen::Vector3d::Zero(), T).project(up, radius).lo <= 0;
  });
  ContinuousResult result = hit_at(t);
  if (!result.collides) return result;
  result.normal_W = plane.pose_at(t).linear() * up;
  result.point_W = motion.pose_at(t).translation() - radius * result.normal_W;
  return result;
}

// Sphere B against mesh A: the centre comes within the radius of a triangle.
ContinuousResult mesh_vs_sphere(const CollisionMesh& mesh, const ScrewMotion& motion_mesh, double radius,
                                const ScrewMotion& motion_sphere, const ContinuousOptions& options) {
  const RelativeMotion rel(motion_mesh, motion_sphere);  // sphere centre in the mesh's frame
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double best = kNoContact;
  int best_triangle = -1;
  auto node_may_touch = [&](const Obb& box, const RelativeMotion::Snapshot& s, double& sweep) {
    // The centre against the (fixed) box grown by the radius, on the box's axes.
    const MovingPoint c = rel.moving_point(origin, s);
    sweep = sweep_radius(c);
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d axis = box.axes.col(i);
      if (c.project(axis, axis.dot(box.center)).mig() > (box.half_extents_m[i] + radius) * (1 + 1e-12)) return false;
    }
    return true;
  };
  auto leaf = [&](int triangle, const Interval& T) {
    Eigen::Vector3d a[3];
    mesh.corners(triangle, a);
    const double t = first_candidate_time({T.lo, std::min(T.hi, best)}, options.time_tolerance, [&](const Interval& W) {
      const MovingPoint c = rel.moving_point(origin, W);
      return point_triangle_distance(c.mid, a[0], a[1], a[2]) * (1 - 1e-12) - sweep_radius(c) <= radius;
    });
    if (t < best) best = t, best_triangle = triangle;
  };
  traverse_in_time(mesh.tree(), rel, options, best, node_may_touch, leaf);
  ContinuousResult result = hit_at(best);
  if (!result.collides) return result;
  Eigen::Vector3d a[3];
  mesh.corners(best_triangle, a);
  const geometry::Pose X_W_mesh = motion_mesh.pose_at(best);
  const Eigen::Vector3d centre_W = motion_sphere.pose_at(best).translation();
  for (auto& p : a) p = X_W_mesh * p;
  result.point_W = closest_point_on_triangle(centre_W, a[0], a[1], a[2]);
  const Eigen::Vector3d n = centre_W - result.point_W;
  result.normal_W = n.norm() > 0 ? n.normalized() : ((a[1] - a[0]).cross(a[2] - a[0])).normalized();
  return result;
}

ContinuousResult sphere_vs_sphere(double radius_A, const ScrewMotion& motion_A, double radius_B,
                                  const ScrewMotion& motion_B, const ContinuousOptions& options) {
  const RelativeMotion rel(motion_A, motion_B);
  const double reach = radius_A + radius_B;
  const double t = first_candidate_time({0.0, 1.0}, options.time_tolerance, [&](const Interval& T) {
    const MovingPoint c = rel.moving_point(Eigen::Vector3d::Zero(), T);
    return c.mid.norm() * (1 - 1e-12) - sweep_radius(c) <= reach;
  });
  ContinuousResult result = hit_at(t);
  if (!result.collides) return result;
  const Eigen::Vector3d a = motion_A.pose_at(t).translation(), b = motion_B.pose_at(t).translation();
  result.normal_W = (b - a).norm() > 0 ? (b - a).normalized() : Eigen::Vector3d::UnitZ();
  result.point_W = a + radius_A * result.normal_W;
  return result;
}

int rank(Shape::Type type) {
  switch (type) {
    case Shape::Type::kPlane: return 0;
    case Shape::Type::kBox:
    case Shape::Type::kMesh:
    case Shape::Type::kConvexSet: return 1;
    case Shape::Type::kSphere: return 2;
  }
  return 3;
}

// Mesh vertices of B within tolerance of (or below) the plane z = 0 of A.
std::vector<ManifoldPoint> plane_mesh_manifold(const geometry::Pose& X_WA, const CollisionMesh& mesh,
                                               const geometry::Pose& X_WB, double tolerance) {
  const geometry::Pose X_AB = X_WA.inverse() * X_WB;
  const Eigen::Vector3d normal_W = X_WA.linear().col(2);
  std::vector<ManifoldPoint> points;
  std::vector<char> seen(mesh.mesh().num_vertices(), 0);
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const ObbNode& node = mesh.tree().nodes()[stack.back()];
    stack.pop_back();
    const double centre_z = (X_AB * node.box.center).z();
    const double extent = (X_AB.linear() * node.box.axes).row(2).cwiseAbs().dot(node.box.half_extents_m);
    if (centre_z - extent > tolerance) continue;
    if (!node.is_leaf()) {
      stack.push_back(node.first_child);
      stack.push_back(node.first_child + 1);
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.mesh().triangles[node.triangle][k];
      if (seen[v]) continue;
      seen[v] = 1;
      const Eigen::Vector3d p_A = X_AB * mesh.mesh().vertices_m[v];
      if (p_A.z() > tolerance) continue;
      const Eigen::Vector3d on_plane(p_A.x(), p_A.y(), 0.0);
      points.push_back({X_WA * on_plane, X_WA * p_A, normal_W, p_A.z(), {-1, node.triangle}});
    }
  }
  return points;
}

std::vector<ManifoldPoint> mesh_sphere_manifold(const CollisionMesh& mesh, const geometry::Pose& X_WA, double radius,
                                                const geometry::Pose& X_WB, double tolerance) {
  const Eigen::Vector3d centre_A = X_WA.inverse() * X_WB.translation();
  const double reach = radius + tolerance;
  std::vector<ManifoldPoint> points;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const ObbNode& node = mesh.tree().nodes()[stack.back()];
    stack.pop_back();
    const Eigen::Vector3d local = node.box.axes.transpose() * (centre_A - node.box.center);
    if (((local.cwiseAbs() - node.box.half_extents_m).array() > reach).any()) continue;
    if (!node.is_leaf()) {
      stack.push_back(node.first_child);
      stack.push_back(node.first_child + 1);
      continue;
    }
    Eigen::Vector3d a[3];
    mesh.corners(node.triangle, a);
    const Eigen::Vector3d on_triangle = closest_point_on_triangle(centre_A, a[0], a[1], a[2]);
    const double d = (centre_A - on_triangle).norm();
    if (d > reach) continue;
    Eigen::Vector3d n = d > 0 ? Eigen::Vector3d((centre_A - on_triangle) / d) : (a[1] - a[0]).cross(a[2] - a[0]).normalized();
    n = X_WA.linear() * n;
    points.push_back({X_WA * on_triangle, X_WB.translation() - radius * n, n, d - radius, {node.triangle, -1}});
  }
  return points;
}

}  // namespace

std::vector<ManifoldPoint> contact_manifold(const Shape& A, const geometry::Pose& X_WA, const Shape& B,
                                            const geometry::Pose& X_WB, double tolerance_m,
                                            NearbyTrianglePairs* nearby) {
  if (rank(A.type()) > rank(B.type())) {
    std::vector<ManifoldPoint> points = contact_manifold(B, X_WB, A, X_WA, tolerance_m, nearby);
    for (auto& p : points) {
      std::swap(p.point_A_W, p.point_B_W);
      std::swap(p.triangles.triangle_A, p.triangles.triangle_B);
      p.normal_W = -p.normal_W;
    }
    return points;
  }
  switch (A.type()) {
    case Shape::Type::kPlane: {
      if (B.type() == Shape::Type::kPlane)
        throw std::invalid_argument("contact_manifold: plane against plane is not supported (model one as a box)");
      if (B.type() == Shape::Type::kConvexSet) return plane_convex_set_manifold(X_WA, *B.convex(), X_WB, tolerance_m);
      if (B.type() != Shape::Type::kSphere) return plane_mesh_manifold(X_WA, *B.triangles(), X_WB, tolerance_m);
      const Eigen::Vector3d n = X_WA.linear().col(2);
      const double height = n.dot(X_WB.translation() - X_WA.translation()) - B.radius_m();
      if (height > tolerance_m) return {};
      const Eigen::Vector3d on_sphere = X_WB.translation() - B.radius_m() * n;
      return {{on_sphere - height * n, on_sphere, n, height, {-1, -1}}};
    }
    case Shape::Type::kBox:
    case Shape::Type::kConvexSet:
      if (A.type() == Shape::Type::kBox && B.type() == Shape::Type::kBox)
        return box_box_manifold(A.size_m(), X_WA, B.size_m(), X_WB, tolerance_m);
      // Convex pieces meet boxes and pieces by separating axes, spheres by signed
      // distances, and meshes as their hulls' triangles.
      if (A.convex() && B.convex()) return convex_set_manifold(*A.convex(), X_WA, *B.convex(), X_WB, tolerance_m);
      if (A.type() == Shape::Type::kConvexSet && B.type() == Shape::Type::kSphere)
        return convex_set_sphere_manifold(*A.convex(), X_WA, B.radius_m(), X_WB, tolerance_m);
      [[fallthrough]];
    case Shape::Type::kMesh:
      return B.type() == Shape::Type::kSphere
                 ? mesh_sphere_manifold(*A.triangles(), X_WA, B.radius_m(), X_WB, tolerance_m)
                 : contact_manifold(*A.triangles(), X_WA, *B.triangles(), X_WB, tolerance_m, nearby);
    case Shape::Type::kSphere: {
      const Eigen::Vector3d between = X_WB.translation() - X_WA.translation();
      const double gap = between.norm() - A.radius_m() - B.radius_m();
      if (gap > tolerance_m) return {};
      const Eigen::Vector3d n = between.norm() > 0 ? Eigen::Vector3d(between.normalized()) : Eigen::Vector3d::UnitZ();
      return {{X_WA.translation() + A.radius_m() * n, X_WB.translation() - B.radius_m() * n, n, gap, {-1, -1}}};
    }
  }
  return {};
}

ContinuousResult time_of_impact(const Shape& A, const ScrewMotion& motion_A, const Shape& B, const ScrewMotion& motion_B,
                                const ContinuousOptions& options) {
  if (rank(A.type()) > rank(B.type())) {
    // Solve the mirrored pair; the normal then points from B to A.
    ContinuousResult r = time_of_impact(B, motion_B, A, motion_A, options);
    r.normal_W = -r.normal_W;
    std::swap(r.features.triangle_A, r.features.triangle_B);
    std::swap(r.features.corner_A, r.features.corner_B);
    if (r.features.kind == FeaturePair::kVertexFace) {
      r.features.kind = FeaturePair::kFaceVertex;
    } else if (r.features.kind == FeaturePair::kFaceVertex) {
      r.features.kind = FeaturePair::kVertexFace;
    }
    return r;
  }
  ContinuousResult result;
  switch (A.type()) {
    case Shape::Type::kPlane:
      if (B.type() == Shape::Type::kPlane)
        throw std::invalid_argument("time_of_impact: plane against plane is not supported (model one of them as a box)");
      result = B.type() == Shape::Type::kSphere ? plane_vs_sphere(motion_A, B.radius_m(), motion_B, options)
                                                : plane_vs_mesh(motion_A, *B.triangles(), motion_B, options);
      break;
    case Shape::Type::kBox:
      // Resting boxes: most pairs are proven apart without the search.
      if (B.type() == Shape::Type::kBox && boxes_stay_apart(0.5 * A.size_m(), motion_A, 0.5 * B.size_m(), motion_B)) break;
      [[fallthrough]];
    case Shape::Type::kMesh:
    case Shape::Type::kConvexSet:
      // Pieces against pieces (or a box) advance conservatively, then sweep their hulls;
      // against anything else a set is its hulls' mesh: their first touch is the set's.
      if (A.convex() && B.convex() && !(A.type() == Shape::Type::kBox && B.type() == Shape::Type::kBox)) {
        result = convex_sets_time_of_impact(*A.convex(), motion_A, *B.convex(), motion_B, options);
        break;
      }
      result = B.type() == Shape::Type::kSphere
                   ? mesh_vs_sphere(*A.triangles(), motion_A, B.radius_m(), motion_B, options)
                   : time_of_impact(*A.triangles(), motion_A, *B.triangles(), motion_B, options);
      break;
    case Shape::Type::kSphere:
      result = sphere_vs_sphere(A.radius_m(), motion_A, B.radius_m(), motion_B, options);
      break;
  }
  result.time_of_impact = std::clamp(result.time_of_impact, 0.0, 1.0);
  return result;
}

}  // namespace arphys::collision
