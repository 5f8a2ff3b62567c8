#include "simulator/collision/convex_manifold.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "simulator/collision/convex_distance.hpp"
#include "simulator/collision/triangle_distance.hpp"

namespace arphys::collision {
namespace {

using Eigen::Vector3d;
constexpr double kInf = std::numeric_limits<double>::infinity();
// The cosine above which an edge pair's axis is taken for a face's normal (half a degree).
constexpr double kFaceInDisguise = 0.99996;

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

// An edge's arc on the Gauss map: its two faces' normals n1, n2 (negated for B, whose
// normals enter the Minkowski difference B - A turned around) and n2 x n1.
struct Arc {
  Vector3d n1, n2, n2xn1;
};
Arc arc_of(const Placed& piece, int edge, double sign) {
  const ConvexPiece::Edge& e = piece.piece.edges()[edge];
  const Vector3d n1 = sign * piece.n[e.face_left], n2 = sign * piece.n[e.face_right];
  return {n1, n2, n2.cross(n1)};
}

// The axis of A's edge i and B's edge j if their Gauss map arcs cross (a face of the
// Minkowski difference, the only edge pairs that can carry the axis of least penetration),
// with the gap along it.
inline bool crossing_edge_axis(const Placed& A, int i, const Arc& arc_A, const Placed& B, int j, const Arc& arc_B,
                               EdgeAxis* out) {
  const double cba = arc_B.n1.dot(arc_A.n2xn1), dba = arc_B.n2.dot(arc_A.n2xn1);
  if (cba * dba >= 0) return false;
  const double adc = arc_A.n1.dot(arc_B.n2xn1), bdc = arc_A.n2.dot(arc_B.n2xn1);
  if (adc * bdc >= 0 || cba * bdc <= 0) return false;
  const ConvexPiece::Edge& ea = A.piece.edges()[i];
  const ConvexPiece::Edge& eb = B.piece.edges()[j];
  const Vector3d pa = A.v[ea.v0], da = A.v[ea.v1] - pa;
  const Vector3d pb = B.v[eb.v0], db = B.v[eb.v1] - pb;
  Vector3d axis = da.cross(db);
  const double length = axis.norm();
  if (length < 1e-9 * da.norm() * db.norm()) return false;  // parallel edges: the faces cover them
  axis /= length;
  if (axis.dot(pa - A.centroid) < 0) axis = -axis;
  *out = {axis.dot(pb - pa), i, j, axis};
  return true;
}

// The edge pair with the largest gap among those whose Gauss map arcs cross.
EdgeAxis best_edge_pair(const Placed& A, const Placed& B, double tolerance) {
  EdgeAxis best;
  // Each edge's arc once, not once per edge pair.
  thread_local std::vector<Arc> arcs_A, arcs_B;
  arcs_A.resize(A.piece.edges().size());
  arcs_B.resize(B.piece.edges().size());
  for (std::size_t i = 0; i < arcs_A.size(); ++i) arcs_A[i] = arc_of(A, static_cast<int>(i), 1);
  for (std::size_t j = 0; j < arcs_B.size(); ++j) arcs_B[j] = arc_of(B, static_cast<int>(j), -1);
  for (int i = 0; i < static_cast<int>(arcs_A.size()); ++i)
    for (int j = 0; j < static_cast<int>(arcs_B.size()); ++j) {
      EdgeAxis edge;
      if (!crossing_edge_axis(A, i, arcs_A[i], B, j, arcs_B[j], &edge)) continue;
      if (edge.gap > best.gap) best = edge;
      if (edge.gap > tolerance) return best;
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

// The point of an edge-edge contact: false, and nothing added, when the closest points lie
// at an end of either edge (the nearest features are then a vertex and something else,
// which a face axis answers better).
bool edge_contact(const Placed& a, const Placed& b, const EdgeAxis& edge, const geometry::Pose& X_WA,
                  double tolerance_m, const std::pair<int, int>& pieces, std::vector<ManifoldPoint>* points) {
  const ConvexPiece::Edge& ea = a.piece.edges()[edge.edge_A];
  const ConvexPiece::Edge& eb = b.piece.edges()[edge.edge_B];
  Vector3d pa, pb;
  segment_segment_distance(a.v[ea.v0], a.v[ea.v1], b.v[eb.v0], b.v[eb.v1], &pa, &pb);
  const auto inside = [](const Vector3d& p, const Vector3d& p0, const Vector3d& p1) {
    const double s = (p - p0).dot(p1 - p0) / (p1 - p0).squaredNorm();
    return s > 1e-9 && s < 1 - 1e-9;
  };
  if (!inside(pa, a.v[ea.v0], a.v[ea.v1]) || !inside(pb, b.v[eb.v0], b.v[eb.v1])) return false;
  const double distance = edge.axis.dot(pb - pa);
  if (distance <= tolerance_m)
    points->push_back({X_WA * pa, X_WA * pb, X_WA.linear() * edge.axis, distance, {pieces.first, pieces.second}});
  return true;
}

// Apart, the pieces' largest separation is their distance, along GJK's axis. Where no face
// comes within rounding of it, the closest features are two edges, each through its piece's
// support vertex along that axis: of the edge pairs through those two vertices, the one whose axis
// carries the distance (of all edge pairs, another could be better only by rounding).
// edge_A < 0: none does.
EdgeAxis edge_pair_at_distance(const Placed& a, const Placed& b, const ConvexDistance& distance,
                               const geometry::Pose& X_WA, const geometry::Pose& X_WB) {
  const int vertex_A = a.piece.support(X_WA.linear().transpose() * distance.axis_W);
  const int vertex_B = b.piece.support(-(X_WB.linear().transpose() * distance.axis_W));
  const auto through = [](const ConvexPiece::Edge& e, int vertex) { return e.v0 == vertex || e.v1 == vertex; };
  EdgeAxis best;
  for (int j = 0; j < static_cast<int>(b.piece.edges().size()); ++j) {
    if (!through(b.piece.edges()[j], vertex_B)) continue;
    const Arc arc_B = arc_of(b, j, -1);
    for (int i = 0; i < static_cast<int>(a.piece.edges().size()); ++i) {
      EdgeAxis edge;
      if (through(a.piece.edges()[i], vertex_A) && crossing_edge_axis(a, i, arc_of(a, i, 1), b, j, arc_B, &edge) &&
          edge.gap > best.gap)
        best = edge;
    }
  }
  const double margin = 1e-9 + 1e-6 * std::abs(distance.upper_m) + (distance.upper_m - distance.lower_m);
  return best.gap + margin >= distance.upper_m ? best : EdgeAxis{};
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
  const std::pair<int, int> pieces{index_A, index_B};
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
  EdgeAxis edge;
  if (!face_is_the_distance) {
    // Apart, the closest edges are found through the support vertices (the search over every
    // edge pair was most of this function's time in a tumbling pile); overlapping, searched.
    if (distance.lower_m > 0) edge = edge_pair_at_distance(a, b, distance, X_WA, X_WB);
    if (edge.edge_A < 0) edge = best_edge_pair(a, b, tolerance_m);
  }
  if (edge.gap > tolerance_m) return;
  const Eigen::Vector3d& face_normal = face_of_B ? b.n[face_B] : a.n[face_A];
  if (edge.edge_A >= 0 && edge.gap > best_face_gap + margin && std::abs(face_normal.dot(edge.axis)) < kFaceInDisguise &&
      edge_contact(a, b, edge, X_WA, tolerance_m, pieces, points))
    return;
  const bool overlap = std::max(best_face_gap, edge.gap) < 0;
  if (face_of_B)
    face_contact(b, face_B, a, false, gap_B, overlap, tolerance_m, X_WA, pieces, points);
  else
    face_contact(a, face_A, b, true, gap_A, overlap, tolerance_m, X_WA, pieces, points);
}

std::vector<ManifoldPoint> convex_set_manifold(const ConvexSet& A, const geometry::Pose& X_WA, const ConvexSet& B,
                                               const geometry::Pose& X_WB, double tolerance_m) {
  std::vector<ManifoldPoint> points;
  // The pieces' balls, then their boxes, before GJK: most piece pairs of two bodies in
  // contact are further apart than the tolerance.
  const geometry::Pose X_AB = X_WA.inverse() * X_WB;
  for (int i = 0; i < static_cast<int>(A.pieces.size()); ++i) {
    const ConvexPiece& pa = A.pieces[i];
    for (int j = 0; j < static_cast<int>(B.pieces.size()); ++j) {
      const ConvexPiece& pb = B.pieces[j];
      const Vector3d cb_A = X_AB * pb.centroid_m();
      if ((cb_A - pa.centroid_m()).norm() - pa.radius_m() - pb.radius_m() > tolerance_m) continue;
      if (box_gap_lower_bound_m(pa.box_m(), pb.box_m(), X_AB) > tolerance_m) continue;
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
