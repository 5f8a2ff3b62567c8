#include "simulator/collision/convex_manifold.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include "simulator/collision/convex_distance.hpp"
#include "simulator/collision/triangle_distance.hpp"

namespace arphys::collision {
namespace {

using Eigen::Vector3d;
constexpr double kInf = std::numeric_limits<double>::infinity();

// A piece placed in A's frame: its vertices, face planes and centroid there.
struct Placed {
  const ConvexPiece& piece;
  std::vector<Vector3d> v;
  std::vector<Vector3d> n;
  std::vector<double> offset;
  Vector3d centroid;
  Placed(const ConvexPiece& p, const geometry::Pose& X) : piece(p) {
    v.reserve(p.vertices_m().size());
    for (const Vector3d& x : p.vertices_m()) v.push_back(X * x);
    for (const ConvexPiece::Face& f : p.faces()) {
      n.push_back(X.linear() * f.normal);
      offset.push_back(f.offset_m + n.back().dot(X.translation()));
    }
    centroid = X * p.centroid_m();
  }
};

// The face of `ref` with the largest gap to `other` (the least penetration): gap and index.
std::pair<double, int> best_face(const Placed& ref, const Placed& other, double tolerance) {
  std::pair<double, int> best{-kInf, -1};
  for (int f = 0; f < static_cast<int>(ref.n.size()); ++f) {
    double lowest = kInf;
    for (const Vector3d& x : other.v) lowest = std::min(lowest, ref.n[f].dot(x));
    const double gap = lowest - ref.offset[f];
    if (gap > best.first) best = {gap, f};
    if (gap > tolerance) break;  // separated along this face: no contact
  }
  return best;
}

struct EdgeAxis {
  double gap = -kInf;
  int edge_A = -1, edge_B = -1;
  Vector3d axis = Vector3d::Zero();
};

// The edge pair with the largest gap among those whose Gauss map arcs cross (faces of
// the Minkowski difference): only they can carry the axis of least penetration.
EdgeAxis best_edge_pair(const Placed& A, const Placed& B, double tolerance) {
  EdgeAxis best;
  const auto& ea = A.piece.edges();
  const auto& eb = B.piece.edges();
  // B's arcs once (negated normals and their cross product), not once per edge of A.
  struct Arc {
    Vector3d c, d, dxc;
  };
  thread_local std::vector<Arc> arcs;
  arcs.resize(eb.size());
  for (std::size_t j = 0; j < eb.size(); ++j) {
    arcs[j].c = -B.n[eb[j].face_left];
    arcs[j].d = -B.n[eb[j].face_right];
    arcs[j].dxc = arcs[j].d.cross(arcs[j].c);
  }
  for (int i = 0; i < static_cast<int>(ea.size()); ++i) {
    const Vector3d& a = A.n[ea[i].face_left];
    const Vector3d& b = A.n[ea[i].face_right];
    const Vector3d bxa = b.cross(a);
    const Vector3d pa = A.v[ea[i].v0], da = A.v[ea[i].v1] - pa;
    for (int j = 0; j < static_cast<int>(eb.size()); ++j) {
      const Vector3d& c = arcs[j].c;
      const Vector3d& d = arcs[j].d;
      const double cba = c.dot(bxa), dba = d.dot(bxa);
      if (cba * dba >= 0) continue;
      const Vector3d& dxc = arcs[j].dxc;
      const double adc = a.dot(dxc), bdc = b.dot(dxc);
      if (adc * bdc >= 0 || cba * bdc <= 0) continue;
      const Vector3d pb = B.v[eb[j].v0], db = B.v[eb[j].v1] - pb;
      Vector3d axis = da.cross(db);
      const double length = axis.norm();
      if (length < 1e-9 * da.norm() * db.norm()) continue;  // parallel edges: the faces cover them
      axis /= length;
      if (axis.dot(pa - A.centroid) < 0) axis = -axis;
      const double gap = axis.dot(pb - pa);
      if (gap > best.gap) best = {gap, i, j, axis};
      if (gap > tolerance) return best;
    }
  }
  return best;
}

// Points of a face contact in A's frame: `ref`'s face f against `inc`'s most opposed face.
void face_contact(const Placed& ref, int f, const Placed& inc, bool ref_is_A, double gap, bool overlap, double tolerance,
                  const geometry::Pose& X_WA, const std::pair<int, int>& pieces, std::vector<ManifoldPoint>* points) {
  const Vector3d& n = ref.n[f];
  int incident = 0;
  double most_opposed = kInf;
  for (int g = 0; g < static_cast<int>(inc.n.size()); ++g)
    if (const double c = inc.n[g].dot(n); c < most_opposed) {
      most_opposed = c;
      incident = g;
    }
  std::vector<Vector3d> polygon;
  for (int k : inc.piece.faces()[incident].polygon) polygon.push_back(inc.v[k]);
  const std::vector<int>& side = ref.piece.faces()[f].polygon;
  for (std::size_t k = 0; k < side.size() && !polygon.empty(); ++k) {
    const Vector3d& p = ref.v[side[k]];
    const Vector3d out = (ref.v[side[(k + 1) % side.size()]] - p).cross(n);
    if (out.squaredNorm() > 0) polygon = clip_to_half_space(polygon, out.normalized(), out.normalized().dot(p));
  }
  // Overlapping (no axis separates them), the clipped face may miss the deepest point (an edge driven in beside
  // the face, or past its side): it is added, so that the pair's depth is its separation.
  if (overlap) {
    double shallowest_kept = kInf;
    for (const Vector3d& p : polygon) shallowest_kept = std::min(shallowest_kept, n.dot(p) - ref.offset[f]);
    if (shallowest_kept > gap + 1e-9 + 1e-6 * std::abs(gap)) {
      int deepest = 0;
      for (int k = 1; k < static_cast<int>(inc.v.size()); ++k)
        if (n.dot(inc.v[k]) < n.dot(inc.v[deepest])) deepest = k;
      polygon.push_back(inc.v[deepest]);
    }
  }
  for (const Vector3d& p : polygon) {
    const double d = n.dot(p) - ref.offset[f];
    if (d > tolerance) continue;
    const Vector3d on_face = p - d * n;
    const Vector3d n_W = X_WA.linear() * n;
    if (ref_is_A)
      points->push_back({X_WA * on_face, X_WA * p, n_W, d, {pieces.first, pieces.second}});
    else
      points->push_back({X_WA * p, X_WA * on_face, -n_W, d, {pieces.first, pieces.second}});
  }
}

}  // namespace

std::vector<Eigen::Vector3d> clip_to_half_space(const std::vector<Eigen::Vector3d>& polygon, const Eigen::Vector3d& n,
                                                double offset) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector3d& p = polygon[i];
    const Eigen::Vector3d& q = polygon[(i + 1) % polygon.size()];
    const double dp = n.dot(p) - offset, dq = n.dot(q) - offset;
    if (dp <= 0) out.push_back(p);
    if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) out.push_back(p + (dp / (dp - dq)) * (q - p));
  }
  return out;
}

void convex_manifold(const ConvexPiece& A, int index_A, const geometry::Pose& X_WA, const ConvexPiece& B, int index_B,
                     const geometry::Pose& X_WB, double tolerance_m, std::vector<ManifoldPoint>* points) {
  // Most pairs whose balls come within the tolerance are further apart: a few GJK support
  // searches prove it before every face and edge pair is tested.
  const ConvexDistance distance = convex_distance(A, X_WA, B, X_WB, tolerance_m);
  if (distance.lower_m > tolerance_m) return;
  const Placed a(A, geometry::Pose::Identity());
  const Placed b(B, X_WA.inverse() * X_WB);
  const auto [gap_A, face_A] = best_face(a, b, tolerance_m);
  if (gap_A > tolerance_m) return;
  const auto [gap_B, face_B] = best_face(b, a, tolerance_m);
  if (gap_B > tolerance_m) return;
  // Prefer a face, and A's: an edge axis or B's face must be clearly better (rounding
  // makes near-parallel features look as good as the face they lie in). An edge axis
  // within half a degree of that face's normal is the face axis in disguise (two pieces
  // stacked with a twist: their edges cross in the contact plane), and would reduce a
  // face contact to one point.
  const double margin = 1e-9 + 1e-6 * std::abs(std::max(gap_A, gap_B));
  const bool face_of_B = gap_B > gap_A + margin;
  const double best_face_gap = face_of_B ? gap_B : gap_A;
  // Apart, no axis separates the pieces by more than their distance: when a face already
  // comes within the margin of GJK's upper bound on it, no edge pair can be clearly better
  // and the edge pairs (most of this function's time in a resting pile) are not searched.
  const bool face_is_the_distance = best_face_gap >= 0 && best_face_gap + margin >= distance.upper_m;
  const EdgeAxis edge = face_is_the_distance ? EdgeAxis{} : best_edge_pair(a, b, tolerance_m);
  if (edge.gap > tolerance_m) return;
  const std::pair<int, int> pieces{index_A, index_B};
  const Eigen::Vector3d& face_normal = face_of_B ? b.n[face_B] : a.n[face_A];
  if (edge.edge_A >= 0 && edge.gap > best_face_gap + margin && std::abs(face_normal.dot(edge.axis)) < 0.99996) {
    const ConvexPiece::Edge& ea = A.edges()[edge.edge_A];
    const ConvexPiece::Edge& eb = B.edges()[edge.edge_B];
    Vector3d pa, pb;
    segment_segment_distance(a.v[ea.v0], a.v[ea.v1], b.v[eb.v0], b.v[eb.v1], &pa, &pb);
    const auto inside = [](const Vector3d& p, const Vector3d& p0, const Vector3d& p1) {
      const double s = (p - p0).dot(p1 - p0) / (p1 - p0).squaredNorm();
      return s > 1e-9 && s < 1 - 1e-9;
    };
    // Closest points at an end of either edge: the nearest features are a vertex and
    // something else, which the face axis answers better.
    if (inside(pa, a.v[ea.v0], a.v[ea.v1]) && inside(pb, b.v[eb.v0], b.v[eb.v1])) {
      const double distance = edge.axis.dot(pb - pa);
      if (distance <= tolerance_m)
        points->push_back({X_WA * pa, X_WA * pb, X_WA.linear() * edge.axis, distance, {index_A, index_B}});
      return;
    }
  }
  const bool overlap = std::max(best_face_gap, edge.gap) < 0;
  if (face_of_B)
    face_contact(b, face_B, a, false, gap_B, overlap, tolerance_m, X_WA, pieces, points);
  else
    face_contact(a, face_A, b, true, gap_A, overlap, tolerance_m, X_WA, pieces, points);
}

std::vector<ManifoldPoint> convex_set_manifold(const ConvexSet& A, const geometry::Pose& X_WA, const ConvexSet& B,
                                               const geometry::Pose& X_WB, double tolerance_m) {
  std::vector<ManifoldPoint> points;
  for (int i = 0; i < static_cast<int>(A.pieces.size()); ++i) {
    const ConvexPiece& pa = A.pieces[i];
    const Vector3d ca = X_WA * pa.centroid_m();
    for (int j = 0; j < static_cast<int>(B.pieces.size()); ++j) {
      const ConvexPiece& pb = B.pieces[j];
      if ((X_WB * pb.centroid_m() - ca).norm() - pa.radius_m() - pb.radius_m() > tolerance_m) continue;
      convex_manifold(pa, i, X_WA, pb, j, X_WB, tolerance_m, &points);
    }
  }
  return points;
}

std::vector<ManifoldPoint> plane_convex_set_manifold(const geometry::Pose& X_WA, const ConvexSet& B,
                                                     const geometry::Pose& X_WB, double tolerance_m) {
  const geometry::Pose X_AB = X_WA.inverse() * X_WB;
  const Vector3d normal_W = X_WA.linear().col(2);
  std::vector<ManifoldPoint> points;
  for (int j = 0; j < static_cast<int>(B.pieces.size()); ++j) {
    const ConvexPiece& piece = B.pieces[j];
    if ((X_AB * piece.centroid_m()).z() - piece.radius_m() > tolerance_m) continue;
    for (const Vector3d& v : piece.vertices_m()) {
      const Vector3d p_A = X_AB * v;
      if (p_A.z() > tolerance_m) continue;
      const Vector3d on_plane(p_A.x(), p_A.y(), 0.0);
      points.push_back({X_WA * on_plane, X_WA * p_A, normal_W, p_A.z(), {-1, j}});
    }
  }
  return points;
}

double signed_distance(const ConvexPiece& piece, const Eigen::Vector3d& p, Eigen::Vector3d* closest,
                       Eigen::Vector3d* normal) {
  double outside = -kInf;
  int face = 0;
  for (int f = 0; f < static_cast<int>(piece.faces().size()); ++f)
    if (const double s = piece.faces()[f].normal.dot(p) - piece.faces()[f].offset_m; s > outside) {
      outside = s;
      face = f;
    }
  if (outside <= 0) {  // inside (or on): as deep as the nearest face plane
    if (closest) *closest = p - outside * piece.faces()[face].normal;
    if (normal) *normal = piece.faces()[face].normal;
    return outside;
  }
  double best = kInf;
  Vector3d nearest = p;
  for (const Eigen::Vector3i& t : piece.hull().triangles) {
    const Vector3d q = closest_point_on_triangle(p, piece.vertices_m()[t[0]], piece.vertices_m()[t[1]],
                                                 piece.vertices_m()[t[2]]);
    if (const double d = (p - q).norm(); d < best) {
      best = d;
      nearest = q;
    }
  }
  if (closest) *closest = nearest;
  if (normal) *normal = best > 0 ? Vector3d((p - nearest) / best) : piece.faces()[face].normal;
  return best;
}

std::vector<ManifoldPoint> convex_set_sphere_manifold(const ConvexSet& A, const geometry::Pose& X_WA, double radius_m,
                                                      const geometry::Pose& X_WB, double tolerance_m) {
  const Vector3d centre_A = X_WA.inverse() * X_WB.translation();
  std::vector<ManifoldPoint> points;
  for (int i = 0; i < static_cast<int>(A.pieces.size()); ++i) {
    const ConvexPiece& piece = A.pieces[i];
    if ((centre_A - piece.centroid_m()).norm() - piece.radius_m() - radius_m > tolerance_m) continue;
    Vector3d on_piece, n;
    const double d = signed_distance(piece, centre_A, &on_piece, &n) - radius_m;
    if (d > tolerance_m) continue;
    const Vector3d n_W = X_WA.linear() * n;
    points.push_back({X_WA * on_piece, X_WB.translation() - radius_m * n_W, n_W, d, {i, -1}});
  }
  return points;
}

}  // namespace arphys::collision
