#include "simulator/collision/discrete_query.hpp"

#include <limits>
#include <map>
#include <set>

#include "simulator/collision/obb_culling.hpp"
#include "simulator/collision/triangle_distance.hpp"

namespace arphys::collision {
namespace {

// Depth-first over node pairs whose boxes come within `margin()` of each other,
// descending the larger box first; `leaf(node_A, node_B)` sees the surviving leaf pairs
// and returns false to stop. The order of the leaf pairs depends on the trees only,
// not on the pose or the margin (NearbyTrianglePairs relies on it).
template <typename Margin, typename Leaf>
void traverse_close_pairs(const CollisionMesh& A, const CollisionMesh& B, const Eigen::Matrix3d& R_AB,
                          const Eigen::Vector3d& p_AB, Margin margin, Leaf leaf) {
  const auto& na = A.tree().nodes();
  const auto& nb = B.tree().nodes();
  std::vector<std::pair<int, int>> stack{{0, 0}};
  while (!stack.empty()) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    if (obbs_separated(na[a].box, nb[b].box, R_AB, p_AB, margin())) continue;
    if (na[a].is_leaf() && nb[b].is_leaf()) {
      if (!leaf(a, b)) return;
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

// The triangle pairs whose boxes come within margin_m at these poses, to
// `leaf(triangle_A, triangle_B)` (false: stop), through `nearby` when given.
template <typename Leaf>
void close_triangle_pairs(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                          const geometry::Pose& X_WB, double margin_m, NearbyTrianglePairs* nearby, Leaf leaf) {
  const geometry::Pose X_AB = X_WA.inverse() * X_WB;
  const Eigen::Matrix3d R_AB = X_AB.linear();
  const Eigen::Vector3d p_AB = X_AB.translation();
  const auto& na = A.tree().nodes();
  const auto& nb = B.tree().nodes();
  const auto descend = [&](double margin) {
    traverse_close_pairs(A, B, R_AB, p_AB, [margin] { return margin; },
                         [&](int a, int b) { return leaf(na[a].triangle, nb[b].triangle); });
  };
  if (!nearby) return descend(margin_m);
  const bool same_meshes = nearby->mesh_A == &A && nearby->mesh_B == &B;
  // How far a triangle of B can have moved relative to A since X_AB_before: its root box
  // centre's displacement plus the turn's, |R - R0| times the reach about that centre
  // (for a difference of rotations the 2-norm is the Frobenius norm over sqrt 2).
  const auto moved_since = [&](const geometry::Pose& X_AB_before) {
    const Eigen::Vector3d& c = nb[0].box.center;
    return (R_AB * c + p_AB - X_AB_before * c).norm() +
           0.7072 * (R_AB - X_AB_before.linear()).norm() * B.tree().reach_m();
  };
  if (same_meshes && nearby->margin_m >= 0 && margin_m + 1.01 * moved_since(nearby->X_AB) + 1e-12 < nearby->margin_m) {
    ++nearby->reuses;
    for (const auto& [a, b] : nearby->leaves) {
      if (obbs_separated(na[a].box, nb[b].box, R_AB, p_AB, margin_m)) continue;
      if (!leaf(na[a].triangle, nb[b].triangle)) return;
    }
    return;
  }
  const bool keep = same_meshes && nearby->seen && moved_since(nearby->X_AB_seen) < 0.25 * nearby->spare_margin_m;
  nearby->mesh_A = &A;
  nearby->mesh_B = &B;
  nearby->seen = true;
  nearby->X_AB_seen = X_AB;
  nearby->leaves.clear();
  nearby->margin_m = -1;
  ++nearby->descents;
  if (!keep) return descend(margin_m);
  nearby->X_AB = X_AB;
  nearby->margin_m = margin_m + nearby->spare_margin_m;
  bool stopped = false;  // the caller has its answer; the descent goes on to fill `nearby`
  traverse_close_pairs(A, B, R_AB, p_AB, [&] { return nearby->margin_m; }, [&](int a, int b) {
    nearby->leaves.emplace_back(a, b);
    if (!stopped && !obbs_separated(na[a].box, nb[b].box, R_AB, p_AB, margin_m))
      stopped = !leaf(na[a].triangle, nb[b].triangle);
    return true;
  });
}

void corners_in_world(const CollisionMesh& M, int triangle, const geometry::Pose& X_W, Eigen::Vector3d out[3]) {
  M.corners(triangle, out);
  for (int k = 0; k < 3; ++k) out[k] = X_W * out[k];
}

}  // namespace

std::optional<TrianglePair> find_intersection(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                                              const geometry::Pose& X_WB, NearbyTrianglePairs* nearby) {
  std::optional<TrianglePair> found;
  close_triangle_pairs(A, X_WA, B, X_WB, 0.0, nearby, [&](int ta, int tb) {
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
  const geometry::Pose X_AB = X_WA.inverse() * X_WB;
  const auto& na = A.tree().nodes();
  const auto& nb = B.tree().nodes();
  traverse_close_pairs(A, B, X_AB.linear(), X_AB.translation(), [&] { return std::isfinite(bound) ? bound : 1e300; },
                       [&](int node_a, int node_b) {
    const int ta = na[node_a].triangle, tb = nb[node_b].triangle;
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

namespace {

// The normal out of a solid across its edge (direction edge_W) nearest to normal_out:
// itself if it lies between the two faces' normals, else the nearer face's normal.
// faces_sum_W: the sum of the two faces' unit normals (zero: unknown, left as it is).
Eigen::Vector3d within_edge_normals(const Eigen::Vector3d& normal_out, const Eigen::Vector3d& edge_W,
                                    const Eigen::Vector3d& faces_sum_W) {
  const double s = faces_sum_W.norm();
  if (s == 0 || normal_out.dot(faces_sum_W) >= 0.5 * s * s) return normal_out;
  // The faces' normals lie at half their angle either side of their sum, across the edge.
  const Eigen::Vector3d middle = faces_sum_W / s;
  const Eigen::Vector3d side = edge_W.cross(middle).normalized();
  const double c = std::min(1.0, 0.5 * s);
  const double t = std::sqrt(1 - c * c);
  return c * middle + (normal_out.dot(side) >= 0 ? t : -t) * side;
}

// Whether a point at `offset` from a solid's edge lies inside the solid there. edge_W
// runs counter-clockwise on the face with unit normal face_W; faces_sum_W is the sum of
// both faces' normals. Across a convex edge the inside is behind both faces, across a
// concave one behind either.
bool beside_edge_inside(const Eigen::Vector3d& offset, const Eigen::Vector3d& edge_W, const Eigen::Vector3d& face_W,
                        const Eigen::Vector3d& faces_sum_W) {
  const Eigen::Vector3d other_W = faces_sum_W - face_W;
  const bool behind_face = offset.dot(face_W) < 0, behind_other = offset.dot(other_W) < 0;
  // Convex: the other face turns away from this face's side of the edge (face x edge
  // points from the edge into this face).
  const bool convex = other_W.dot(face_W.cross(edge_W)) < 0;
  return convex ? behind_face && behind_other : behind_face || behind_other;
}

// Collects the feature contacts of close triangle pairs without duplicates: a vertex
// over a face (keyed by the vertex and the face's normal, so one vertex on two coplanar
// triangles counts once) or two edges crossing (keyed by their vertex indices).
class ManifoldBuilder {
 public:
  ManifoldBuilder(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                  const geometry::Pose& X_WB, double tolerance)
      : A_(A), B_(B), X_WA_(X_WA), X_WB_(X_WB), tolerance_(tolerance) {}

  void add_pair(int ta, int tb) {
    Eigen::Vector3d a[3], b[3];
    corners_in_world(A_, ta, X_WA_, a);
    corners_in_world(B_, tb, X_WB_, b);
    const Eigen::Vector3i& ia = A_.mesh().triangles[ta];
    const Eigen::Vector3i& ib = B_.mesh().triangles[tb];
    const Eigen::Vector3d nA = (a[1] - a[0]).cross(a[2] - a[0]).normalized();
    const Eigen::Vector3d nB = (b[1] - b[0]).cross(b[2] - b[0]).normalized();
    for (int k = 0; k < 3; ++k) {
      // B's vertex over A's face, and A's vertex over B's face.
      const Eigen::Vector3d out_B = B_.closed() ? Eigen::Vector3d(X_WB_.linear() * B_.vertex_outward(ib[k])) : Eigen::Vector3d::Zero();
      const Eigen::Vector3d out_A = A_.closed() ? Eigen::Vector3d(X_WA_.linear() * A_.vertex_outward(ia[k])) : Eigen::Vector3d::Zero();
      vertex_face(b[k], out_B, a, nA, A_.closed(), +1, ib[k], {ta, tb});
      vertex_face(a[k], out_A, b, nB, B_.closed(), -1, -1 - ia[k], {ta, tb});
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) edge_edge(a, i, nA, b, j, nB, ia, ib, {ta, tb});
  }

  std::vector<ManifoldPoint> take() { return std::move(points_); }

 private:
  // `sign` +1: the vertex is B's, the face A's; -1 the other way round. The normal
  // always points from A to B. Vertex keys: B's vertex v as v, A's as -1 - v.
  // `vertex_out` (zero for an open surface) is the outward direction of the solid the
  // vertex belongs to: a face can only hold the vertex back if it faces that way.
  void vertex_face(const Eigen::Vector3d& v, const Eigen::Vector3d& vertex_out, const Eigen::Vector3d tri[3],
                   Eigen::Vector3d n, bool outward, double sign, int key, TrianglePair pair) {
    const Eigen::Vector3d on_face = closest_point_on_triangle(v, tri[0], tri[1], tri[2]);
    const double d = (v - on_face).norm();
    if (d > tolerance_) return;
    // Only a vertex over the face's interior: over an edge the contact is an edge one.
    const Eigen::Vector3d projected = v - n.dot(v - tri[0]) * n;
    if ((projected - on_face).norm() > 1e-9 * (1 + d + v.norm())) return;
    // A solid's face pushes out along its outward normal even when the vertex is
    // slightly inside; a shell's face pushes to the side the vertex is on.
    if (!outward && n.dot(v - tri[0]) < 0 && d > 1e-12) n = -n;
    // (An open surface's vertex has no outward direction: any face may hold it back. The
    // test below keeps such a vertex: with 0 >= 0 it would drop it, and a scanned bunny with
    // holes in its base would find no contact on its vertices and sink through the table.)
    if (vertex_out.squaredNorm() > 0 && vertex_out.dot(n) >= -1e-9 * vertex_out.norm()) return;  // the face does not oppose the vertex
    for (const int index : vertex_entries_[key])
      if (points_[index].normal_W.dot(sign * n) > 1 - 1e-9) return;  // coplanar neighbour: same contact
    // Two corners meeting (stacked boxes): one vertex/face contact of each body at the
    // same place and normal; keep one.
    const Eigen::Vector3d where = sign > 0 ? v : on_face;
    for (const ManifoldPoint& p : points_)
      if ((p.point_B_W - where).norm() <= 1e-9 * (1 + where.norm()) && p.normal_W.dot(sign * n) > 1 - 1e-9) return;
    vertex_entries_[key].push_back(static_cast<int>(points_.size()));
    const Eigen::Vector3d normal = sign * n;
    const Eigen::Vector3d on_A = sign > 0 ? on_face : v, on_B = sign > 0 ? v : on_face;
    points_.push_back({on_A, on_B, normal, normal.dot(on_B - on_A), pair});
  }

  // nA, nB: the unit normals of the triangles the edges were taken from (counter-clockwise).
  void edge_edge(const Eigen::Vector3d a[3], int i, const Eigen::Vector3d& nA, const Eigen::Vector3d b[3], int j,
                 const Eigen::Vector3d& nB, const Eigen::Vector3i& ia, const Eigen::Vector3i& ib, TrianglePair pair) {
    if (A_.is_flat_edge(ia[i], ia[(i + 1) % 3]) || B_.is_flat_edge(ib[j], ib[(j + 1) % 3])) return;
    const Eigen::Vector3d p0 = a[i], p1 = a[(i + 1) % 3], q0 = b[j], q1 = b[(j + 1) % 3];
    Eigen::Vector3d n = (p1 - p0).cross(q1 - q0);
    if (n.norm() <= 1e-9 * (p1 - p0).norm() * (q1 - q0).norm()) return;  // parallel: the vertex contacts cover it
    Eigen::Vector3d pa, pb;
    const double d = segment_segment_distance(p0, p1, q0, q1, &pa, &pb);
    if (d > tolerance_) return;
    auto interior = [](const Eigen::Vector3d& x, const Eigen::Vector3d& e0, const Eigen::Vector3d& e1) {
      const double s = (x - e0).dot(e1 - e0) / (e1 - e0).squaredNorm();
      return s > 1e-9 && s < 1 - 1e-9;
    };
    if (!interior(pa, p0, p1) || !interior(pb, q0, q1)) return;  // at an end: a vertex contact
    const auto key = std::make_pair(std::minmax(ia[i], ia[(i + 1) % 3]), std::minmax(ib[j], ib[(j + 1) % 3]));
    if (!edge_keys_.insert(key).second) return;
    n.normalize();
    // Orient from A to B. Edges apart (neither closest point inside the other solid
    // beside its edge): along the closest points. Edges crossed or touching: out of A
    // and into B by the outward normals of whichever is a solid (the closest points
    // then point the wrong way: a box edge that a bunny's edge had passed by 0.2 mm got
    // a normal into the box, and with the box's face contacts the bunny's push-out was
    // contradictory at every step); two shells: by the bodies' origins when touching.
    // (Judging "crossed" by the sum of the faces' normals alone called a bunny's edge
    // 0.5 mm above a table's top and 0.8 mm in from its rim crossed: a contact 0.8 mm
    // deep, pushed apart where nothing overlapped, as a bunny slid off the table.)
    const Eigen::Vector3d outward_A = X_WA_.linear() * A_.edge_outward(ia[i], ia[(i + 1) % 3]);
    const Eigen::Vector3d outward_B = X_WB_.linear() * B_.edge_outward(ib[j], ib[(j + 1) % 3]);
    const bool apart = d > 1e-12 && !(A_.closed() && beside_edge_inside(pb - pa, p1 - p0, nA, outward_A)) &&
                       !(B_.closed() && beside_edge_inside(pa - pb, q1 - q0, nB, outward_B));
    Eigen::Vector3d from_A_to_B = Eigen::Vector3d::Zero();
    if (A_.closed()) from_A_to_B += outward_A;
    if (B_.closed()) from_A_to_B -= outward_B;
    if (apart) {
      from_A_to_B = pb - pa;
    } else if (!A_.closed() && !B_.closed()) {
      from_A_to_B = X_WB_.translation() - X_WA_.translation();
    }
    if (n.dot(from_A_to_B) < 0) n = -n;
    // On a solid, a contact across an edge has its normal between its two faces' normals.
    // Two edges crossing at another angle touch one of those faces: the normal is that
    // face's. (Kept as they came, such rows, a box's bottom edge pressing a bunny's rim
    // into the box, contradicted the box's face contacts step after step; dropped, a
    // bunny's base edges resting on a table's rim, tilted a hair outside its normals,
    // left it unsupported there, and it waited on the table at every step.)
    if (A_.closed()) n = within_edge_normals(n, p1 - p0, outward_A);
    if (B_.closed()) n = -within_edge_normals(-n, q1 - q0, outward_B);
    points_.push_back({pa, pb, n, n.dot(pb - pa), pair});
  }

  const CollisionMesh& A_;
  const CollisionMesh& B_;
  const geometry::Pose& X_WA_;
  const geometry::Pose& X_WB_;
  double tolerance_;
  std::vector<ManifoldPoint> points_;
  std::map<int, std::vector<int>> vertex_entries_;
  std::set<std::pair<std::pair<int, int>, std::pair<int, int>>> edge_keys_;
};

}  // namespace

std::vector<ManifoldPoint> contact_manifold(const CollisionMesh& A, const geometry::Pose& X_WA, const CollisionMesh& B,
                                            const geometry::Pose& X_WB, double tolerance_m,
                                            NearbyTrianglePairs* nearby) {
  ManifoldBuilder builder(A, X_WA, B, X_WB, tolerance_m);
  close_triangle_pairs(A, X_WA, B, X_WB, tolerance_m, nearby, [&](int ta, int tb) {
    builder.add_pair(ta, tb);
    return true;
  });
  return builder.take();
}

}  // namespace arphys::collision
