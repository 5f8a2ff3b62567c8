#include "simulator/collision/feature_toi.hpp"

#include <algorithm>

#include "simulator/collision/triangle_distance.hpp"

namespace arphys::collision {

const char* to_string(FeaturePair kind) {
  switch (kind) {
    case FeaturePair::kNone: return "none";
    case FeaturePair::kOverlapAtStart: return "overlap-at-start";
    case FeaturePair::kVertexFace: return "vertex(B)-face(A)";
    case FeaturePair::kFaceVertex: return "face(B)-vertex(A)";
    case FeaturePair::kEdgeEdge: return "edge-edge";
  }
  return "?";
}

namespace {

// Feature-pair bits: 0-2 vertex k of B vs A's face, 3-5 vertex k of A vs B's face,
// 6 + 3 i + j edge i of A vs edge j of B.
constexpr uint32_t kAllPairs = (1u << 15) - 1;
constexpr uint32_t kFaceVertexBits = 0b111000;

bool boxes_disjoint(const IVec3& box, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  for (int i = 0; i < 3; ++i)
    if (box[i].hi < lo[i] || box[i].lo > hi[i]) return true;
  return false;
}

IVec3 hull(const IVec3& a, const IVec3& b) {
  return {{collision::hull(a[0], b[0]), collision::hull(a[1], b[1]), collision::hull(a[2], b[2])}};
}

// A static triangle in its body's frame, with what the vertex/face test needs.
struct FixedTriangle {
  Eigen::Vector3d corner[3], edge[3], normal, inward[3], lo, hi;

  explicit FixedTriangle(const Eigen::Vector3d c[3]) {
    for (int i = 0; i < 3; ++i) corner[i] = c[i];
    for (int i = 0; i < 3; ++i) edge[i] = corner[(i + 1) % 3] - corner[i];
    normal = edge[0].cross(corner[2] - corner[0]);
    for (int i = 0; i < 3; ++i) inward[i] = normal.cross(edge[i]);
    lo = corner[0].cwiseMin(corner[1]).cwiseMin(corner[2]);
    hi = corner[0].cwiseMax(corner[1]).cwiseMax(corner[2]);
  }

  // Can the moving point be on this triangle during its interval? P is its box.
  bool may_touch(const MovingPoint& p, const IVec3& P) const {
    if (boxes_disjoint(P, lo, hi)) return false;
    if (!p.project(normal, normal.dot(corner[0])).contains_zero()) return false;
    for (int i = 0; i < 3; ++i)
      if (p.project(inward[i], inward[i].dot(corner[i])).hi < 0) return false;
    return true;
  }
};

class TrianglePairSearch {
 public:
  TrianglePairSearch(const RelativeMotion& rel_AB, const RelativeMotion& rel_BA, const Eigen::Vector3d a[3],
                     const Eigen::Vector3d b[3], double tolerance)
      : rel_AB_(rel_AB), rel_BA_(rel_BA), A_(a), B_(b), tolerance_(tolerance) {}

  FeatureContact search(const Interval& T, uint32_t alive) const {
    const RelativeMotion::Snapshot snapshot_AB = rel_AB_.snapshot(T);
    IVec3 PB[3];  // boxes of B's corners in A's frame
    for (int k = 0; k < 3; ++k) {
      const MovingPoint p = rel_AB_.moving_point(B_.corner[k], snapshot_AB);
      PB[k] = p.ball().to_interval();
      if ((alive >> k & 1) && !A_.may_touch(p, PB[k])) alive &= ~(1u << k);
    }
    if (alive & kFaceVertexBits) {
      const RelativeMotion::Snapshot snapshot_BA = rel_BA_.snapshot(T);
      for (int k = 0; k < 3; ++k) {
        if (!(alive >> (3 + k) & 1)) continue;
        const MovingPoint p = rel_BA_.moving_point(A_.corner[k], snapshot_BA);
        if (!B_.may_touch(p, p.ball().to_interval())) alive &= ~(1u << (3 + k));
      }
    }
    if (alive >> 6) {
      const IMat3 R_AB = snapshot_AB.R_AB.to_interval();
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const int bit = 6 + 3 * i + j;
          B_edge_norm_ = B_.edge[j].norm();
        if ((alive >> bit & 1) && !edges_may_touch(i, PB[j], PB[(j + 1) % 3], R_AB * B_.edge[j]))
            alive &= ~(1u << bit);
        }
    }
    if (alive == 0) return {};
    if (T.width() <= tolerance_) return accept(T, alive, PB);
    const double mid = T.mid();
    const FeatureContact left = search({T.lo, mid}, alive);
    return left.time != kNoContact ? left : search({mid, T.hi}, alive);
  }

 private:
  // Edge i of A (fixed) against the moving edge Q0 Q1 of B with direction enclosure eb.
  bool edges_may_touch(int i, const IVec3& Q0, const IVec3& Q1, const IVec3& eb) const {
    const Eigen::Vector3d& p0 = A_.corner[i];
    const Eigen::Vector3d& ea = A_.edge[i];
    const IVec3 Q = hull(Q0, Q1);
    for (int c = 0; c < 3; ++c)
      if (Q[c].hi < std::min(p0[c], p0[c] + ea[c]) || Q[c].lo > std::max(p0[c], p0[c] + ea[c])) return false;
    const IVec3 n = cross(ea, eb);
    // Parallel edges (to rounding) have no isolated edge/edge contact: where they touch,
    // an end of one lies on the other, which is a vertex/face contact on the closed
    // triangle and found there. Skipping them avoids bisecting a coplanarity function
    // that is zero at every time.
    if (std::max({n[0].mag(), n[1].mag(), n[2].mag()}) <= 1e-12 * ea.norm() * B_edge_norm_) return false;
    const IVec3 r = Q0 - p0;
    if (!dot(n, r).contains_zero()) return false;
    // The lines meet at s = (r x eb).n / n.n on A's edge and u = (r x ea).n / n.n on B's.
    const Interval den = dot(n, n);
    const Interval s_num = dot(cross(r, eb), n);
    const Interval u_num = dot(cross(ea, r), n);  // = -(r x ea).n
    if (s_num.hi < 0 || (den - s_num).hi < 0) return false;
    if (u_num.lo > 0 || (den + u_num).hi < 0) return false;
    return true;
  }

  // Interval at the tolerance: vertex/face pairs are accepted as they are; edge/edge
  // pairs are verified, because parallel edges satisfy the coplanarity and in-edge
  // enclosures at any distance: a real contact in T leaves the segments at most the
  // motion over T apart at T's midpoint.
  FeatureContact accept(const Interval& T, uint32_t alive, const IVec3 PB[3]) const {
    for (int k = 0; k < 3; ++k)
      if (alive >> k & 1) return {T.lo, FeaturePair::kVertexFace, -1, k};
    for (int k = 0; k < 3; ++k)
      if (alive >> (3 + k) & 1) return {T.lo, FeaturePair::kFaceVertex, k, -1};
    const double t = T.mid();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        if (!(alive >> (6 + 3 * i + j) & 1)) continue;
        const int j1 = (j + 1) % 3;
        const double motion = std::max(PB[j].max_width(), PB[j1].max_width());
        const Eigen::Vector3d& p0 = A_.corner[i];
        const double gap = segment_segment_distance(p0, p0 + A_.edge[i], rel_AB_.point_at(B_.corner[j], t),
                                                    rel_AB_.point_at(B_.corner[j1], t));
        const double scale = 1e-12 * (A_.edge[i].norm() + B_.edge[j].norm() + p0.norm());
        if (gap <= 2 * motion + scale) return {T.lo, FeaturePair::kEdgeEdge, i, j};
      }
    return {};
  }

  const RelativeMotion& rel_AB_;
  const RelativeMotion& rel_BA_;
  FixedTriangle A_, B_;  // each in its own body frame
  mutable double B_edge_norm_ = 0;
  double tolerance_;
};

}  // namespace

FeatureContact triangle_pair_toi(const RelativeMotion& rel_AB, const RelativeMotion& rel_BA, const Eigen::Vector3d a[3],
                                 const Eigen::Vector3d b[3], const Interval& window, double time_tolerance) {
  if (!(window.lo <= window.hi)) return {};
  return TrianglePairSearch(rel_AB, rel_BA, a, b, time_tolerance).search(window, kAllPairs);
}

}  // namespace arphys::collision
