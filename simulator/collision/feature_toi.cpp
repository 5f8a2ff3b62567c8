#include "simulator/collision/feature_toi.hpp"

#include <algorithm>
#include <optional>

#include "simulator/collision/triangle_distance.hpp"

namespace arphys::collision {

const char* to_string(FeaturePair kind) {
  switch (kind) {
    case FeaturePair::kNone: return "none";
    case FeaturePair::kOverlapAtStart: return "overlap-at-start";
    case FeaturePair::kVertexFace: return "vertex(B)-face(A)";
    case FeaturePair::kFaceVertex: return "face(B)-vertex(A)";
    case FeaturePair::kEdgeEdge: return "edge-edge";
    case FeaturePair::kPrimitive: return "primitive";
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
  double edge_length[3];
  double size = 0;  // longest edge

  explicit FixedTriangle(const Eigen::Vector3d c[3]) {
    for (int i = 0; i < 3; ++i) corner[i] = c[i];
    for (int i = 0; i < 3; ++i) edge[i] = corner[(i + 1) % 3] - corner[i];
    for (int i = 0; i < 3; ++i) edge_length[i] = edge[i].norm();
    size = std::max({edge_length[0], edge_length[1], edge_length[2]});
    normal = edge[0].cross(corner[2] - corner[0]);
    for (int i = 0; i < 3; ++i) inward[i] = normal.cross(edge[i]);
    lo = corner[0].cwiseMin(corner[1]).cwiseMin(corner[2]);
    hi = corner[0].cwiseMax(corner[1]).cwiseMax(corner[2]);
  }

  // Does the straight path P0 -> P1 (a point's exact positions at a leaf's ends) cross
  // the plane within the closed triangle, to `slack` metres (which must cover how far
  // the true path strays from that chord)?
  bool crossed_by(const Eigen::Vector3d& P0, const Eigen::Vector3d& P1, double slack) const {
    const double f0 = normal.dot(P0 - corner[0]), f1 = normal.dot(P1 - corner[0]);
    if ((f0 > 0 && f1 > 0) || (f0 < 0 && f1 < 0)) return false;
    const double lambda = f0 == f1 ? 0.0 : f0 / (f0 - f1);
    const Eigen::Vector3d x = P0 + lambda * (P1 - P0);
    const double reach = slack;
    for (int i = 0; i < 3; ++i)
      if (inward[i].dot(x - corner[i]) < -reach * inward[i].norm()) return false;
    return true;
  }

  // Can the moving point be on this triangle during its interval? P is its box.
  bool may_touch(const MovingPoint& p, const IVec3& P) const {
    if (boxes_disjoint(P, lo, hi)) return false;
    // A vertex sliding within the face's plane (two coplanar faces, a box pressed
    // onto another) has a coplanarity function that is zero at every time: its
    // contact with the face is at the face's boundary, found by the edge/edge pairs
    // and by the neighbouring face's vertex/face pair. Bisecting it would go on to the
    // limit of the tolerance everywhere the vertex is over the face's boundary.
    const double normal_norm = normal.norm();
    if (std::abs(normal.dot(p.velocity)) <= 1e-9 * normal_norm * p.velocity.norm() &&
        p.velocity_rad <= 1e-9 * p.velocity.norm() &&
        std::abs(normal.dot(p.mid - corner[0])) <= 1e-9 * normal_norm * size)
      return false;
    if (!p.project(normal, normal.dot(corner[0])).contains_zero()) return false;
    for (int i = 0; i < 3; ++i)
      if (p.project(inward[i], inward[i].dot(corner[i])).hi < 0) return false;
    return true;
  }
};

// A candidate leaf of the bisection: a time interval at the tolerance and the feature
// pairs whose conditions its enclosures could not rule out.
struct Leaf {
  Interval T;
  uint32_t alive = 0;
};

class TrianglePairSearch {
 public:
  TrianglePairSearch(const RelativeMotion& rel_AB, const RelativeMotion& rel_BA, const Eigen::Vector3d a[3],
                     const Eigen::Vector3d b[3], const Interval& window)
      : rel_AB_(rel_AB), rel_BA_(rel_BA), A_(a), B_(b) {
    // Below the enclosures' own rounding allowance they cannot tell touching triangles
    // from triangles a hair apart: that distance (ten times over) counts as touching.
    const RelativeMotion::Snapshot s_AB = rel_AB.snapshot(window), s_BA = rel_BA.snapshot(window);
    double fuzz = 0;
    for (int k = 0; k < 3; ++k)
      fuzz = std::max({fuzz, rel_AB.moving_point(b[k], s_AB).rounding, rel_BA.moving_point(a[k], s_BA).rounding});
    touch_distance_ = 10 * fuzz + 1e-300;
  }

  // Earliest leaf in T (depth first, earliest half first), or none (alive == 0). When
  // the pair's node budget runs out, the node being searched is returned as a leaf:
  // every time before it is proven contact-free, so its start is never late.
  Leaf search(const Interval& T, uint32_t alive, double tolerance) const {
    if (++nodes_ > kNodeBudget) {
      exhausted_ = true;
      return {T, alive};
    }
    const RelativeMotion::Snapshot snapshot_AB = rel_AB_.snapshot(T);
    IVec3 PB[3];  // boxes of B's corners in A's frame
    MovingPoint MB[3];
    for (int k = 0; k < 3; ++k) {
      const MovingPoint& p = MB[k] = rel_AB_.moving_point(B_.corner[k], snapshot_AB);
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
          if (!(alive >> bit & 1)) continue;
          if (coplanar_sliding(i, snapshot_AB.R_AB.mid * B_.edge[j], MB[j], MB[(j + 1) % 3]) ||
              !coplanarity_may_vanish(i, MB[j], MB[(j + 1) % 3]) ||
              !edges_may_touch(i, j, PB[j], PB[(j + 1) % 3], R_AB * B_.edge[j]))
            alive &= ~(1u << bit);
        }
    }
    if (alive == 0) return {};
    if (T.width() <= tolerance) return {T, alive};
    const double mid = T.mid();
    const Leaf left = search({T.lo, mid}, alive, tolerance);
    return left.alive ? left : search({mid, T.hi}, alive, tolerance);
  }

  // A contact certainly inside the leaf: a feature pair whose coplanarity function
  // changes sign over it (exact end-point evaluations) and whose in-face / in-edge
  // condition holds where it does.
  std::optional<FeatureContact> verify(const Leaf& leaf) const {
    const double lo = leaf.T.lo, hi = leaf.T.hi;
    // How far a corner's path can stray from its chord over the leaf: with |p''| <=
    // velocity_rad / h, the sagitta is at most (2h)^2 / 8 |p''| = h velocity_rad / 2.
    auto sagitta = [&](const RelativeMotion& rel, const Eigen::Vector3d corners[3]) {
      const RelativeMotion::Snapshot s = rel.snapshot(leaf.T);
      double most = 0;
      for (int k = 0; k < 3; ++k) most = std::max(most, rel.moving_point(corners[k], s).velocity_rad);
      return 0.5 * s.h * most * (1 + 1e-12) + touch_distance_;
    };
    const double stray_B = sagitta(rel_AB_, B_.corner);
    Eigen::Vector3d B_lo[3], B_hi[3];  // B's corners in A's frame at the leaf's ends
    for (int k = 0; k < 3; ++k) {
      B_lo[k] = rel_AB_.point_at(B_.corner[k], lo);
      B_hi[k] = rel_AB_.point_at(B_.corner[k], hi);
    }
    for (int k = 0; k < 3; ++k)
      if ((leaf.alive >> k & 1) && A_.crossed_by(B_lo[k], B_hi[k], stray_B)) return feature(k, lo);
    if (leaf.alive & kFaceVertexBits) {
      const double stray_A = sagitta(rel_BA_, A_.corner);
      for (int k = 0; k < 3; ++k)
        if ((leaf.alive >> (3 + k) & 1) &&
            B_.crossed_by(rel_BA_.point_at(A_.corner[k], lo), rel_BA_.point_at(A_.corner[k], hi), stray_A))
          return feature(3 + k, lo);
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int bit = 6 + 3 * i + j, j1 = (j + 1) % 3;
        if (!(leaf.alive >> bit & 1)) continue;
        const Eigen::Vector3d& p0 = A_.corner[i];
        const Eigen::Vector3d& ea = A_.edge[i];
        const double g0 = ea.cross(B_lo[j1] - B_lo[j]).dot(B_lo[j] - p0);
        const double g1 = ea.cross(B_hi[j1] - B_hi[j]).dot(B_hi[j] - p0);
        if ((g0 > 0 && g1 > 0) || (g0 < 0 && g1 < 0)) continue;
        const double lambda = g0 == g1 ? 0.0 : g0 / (g0 - g1);
        const Eigen::Vector3d q0 = B_lo[j] + lambda * (B_hi[j] - B_lo[j]);
        const Eigen::Vector3d q1 = B_lo[j1] + lambda * (B_hi[j1] - B_lo[j1]);
        // The interpolated edge is within the sagitta of the true one where the
        // coplanarity changes sign: the segments must meet there, to that distance.
        if (segment_segment_distance(p0, p0 + ea, q0, q1) <= stray_B) return feature(bit, lo);
      }
    return std::nullopt;
  }

  // Exact distance of the triangles at t, and a bound on how fast it can shrink over W
  // (the largest speed of B's corners in A's frame: speeds are convex over a triangle).
  double distance_at(double t) const {
    Eigen::Vector3d b[3];
    for (int k = 0; k < 3; ++k) b[k] = rel_AB_.point_at(B_.corner[k], t);
    return triangle_triangle_distance(A_.corner, b);
  }
  double closing_speed_bound(const Interval& W) const {
    const RelativeMotion::Snapshot s = rel_AB_.snapshot(W);
    double v = 0;
    for (int k = 0; k < 3; ++k) {
      const MovingPoint p = rel_AB_.moving_point(B_.corner[k], s);
      v = std::max(v, p.velocity.norm() + p.velocity_rad);
    }
    return interval_detail::up(v * (1 + 1e-12));
  }
  // The feature pair (of the allowed ones, or else of all) closest at t: the one to
  // report for triangles that touch there. (The first allowed bit could be two edges
  // far from each other, whose cross product then became the contact normal.)
  int closest_feature(double t, uint32_t allowed) const {
    Eigen::Vector3d b[3], a_in_B[3];
    for (int k = 0; k < 3; ++k) {
      b[k] = rel_AB_.point_at(B_.corner[k], t);
      a_in_B[k] = rel_BA_.point_at(A_.corner[k], t);
    }
    double best = std::numeric_limits<double>::infinity();
    int best_bit = 0;
    for (const uint32_t mask : {allowed, kAllPairs}) {
      for (int bit = 0; bit < 15; ++bit) {
        if (!(mask >> bit & 1)) continue;
        double d;
        if (bit < 3) {
          d = (b[bit] - closest_point_on_triangle(b[bit], A_.corner[0], A_.corner[1], A_.corner[2])).norm();
        } else if (bit < 6) {
          const Eigen::Vector3d& p = a_in_B[bit - 3];
          d = (p - closest_point_on_triangle(p, B_.corner[0], B_.corner[1], B_.corner[2])).norm();
        } else {
          const int i = (bit - 6) / 3, j = (bit - 6) % 3;
          d = segment_segment_distance(A_.corner[i], A_.corner[(i + 1) % 3], b[j], b[(j + 1) % 3]);
        }
        if (d < best) {
          best = d;
          best_bit = bit;
        }
      }
      if (best <= touch_distance_) break;  // an allowed pair touches: report it
    }
    return best_bit;
  }
  double touch_distance() const { return touch_distance_; }
  bool exhausted() const { return exhausted_; }
  long nodes() const { return nodes_; }

  // The feature pair of a bit, as a contact at time t.
  static FeatureContact feature(int bit, double t) {
    if (bit < 3) return {t, FeaturePair::kVertexFace, -1, bit};
    if (bit < 6) return {t, FeaturePair::kFaceVertex, bit - 3, -1};
    return {t, FeaturePair::kEdgeEdge, (bit - 6) / 3, (bit - 6) % 3};
  }

 private:
  // Edge j of B moving within the plane of edge i of A (both edges in one plane, the
  // motion along it): the coplanarity function is zero at every time, and the edges
  // can only first meet at an end of one of them, a vertex/face contact of a
  // neighbouring face.
  bool coplanar_sliding(int i, const Eigen::Vector3d& eb, const MovingPoint& q0, const MovingPoint& q1) const {
    Eigen::Vector3d n = A_.edge[i].cross(eb);
    const double norm = n.norm();
    if (!(norm > 1e-12 * A_.edge_length[i] * eb.norm())) return false;  // parallel: handled elsewhere
    n /= norm;
    const double size = A_.edge_length[i] + eb.norm();
    for (const MovingPoint* q : {&q0, &q1}) {
      const double speed = q->velocity.norm();
      if (std::abs(n.dot(q->mid - A_.corner[i])) > 1e-9 * size || std::abs(n.dot(q->velocity)) > 1e-9 * speed ||
          q->velocity_rad > 1e-9 * speed)
        return false;
    }
    return true;
  }

  // Can the coplanarity f(t) = (ea x (q1(t) - q0(t))) . (q0(t) - p0) of A's edge i and B's
  // moving edge q0 q1 vanish over the node? A first-order Taylor enclosure: f at the
  // node's middle, its slope there, and bounds on the rest. The interval test below
  // encloses q0 and q1 by boxes, which a motion along the face (one box sliding on
  // another) inflates in every direction, the normal too: a resting pair 1 um apart
  // sliding 1 mm per step was bisected into about 1,000 nodes per triangle pair. The
  // motion along the face barely changes f, and this enclosure says so.
  bool coplanarity_may_vanish(int i, const MovingPoint& q0, const MovingPoint& q1) const {
    const Eigen::Vector3d& ea = A_.edge[i];
    const double h = q0.half_width;
    const Eigen::Vector3d e_mid = q1.mid - q0.mid, e_velocity = q1.velocity - q0.velocity;
    const double e_rad = q0.velocity_rad + q1.velocity_rad, e_rounding = q0.rounding + q1.rounding;
    const Eigen::Vector3d r_mid = q0.mid - A_.corner[i];
    const Eigen::Vector3d n_mid = ea.cross(e_mid);
    const double value = n_mid.dot(r_mid);
    const double slope = ea.cross(e_velocity).dot(r_mid) + n_mid.dot(q0.velocity);
    const double ea_norm = A_.edge_length[i], r_norm = r_mid.norm(), n_norm = n_mid.norm();
    const double e_reach = h * (e_velocity.norm() + e_rad) + e_rounding;      // |e(t) - e_mid|
    const double q_reach = h * (q0.velocity.norm() + q0.velocity_rad) + q0.rounding;  // |q0(t) - q0.mid|
    // f(t) - value = (ea x de).r_mid + n_mid.dq + (ea x de).dq, with de, dq the changes
    // of e and q0: each linear in (t - tm) up to velocity_rad |t - tm| and the rounding.
    const double radius = std::abs(slope) * h + ea_norm * (e_rad * h + e_rounding) * r_norm +
                          n_norm * (q0.velocity_rad * h + q0.rounding) + ea_norm * e_reach * q_reach;
    // Rounding of the products above, generously.
    const double slack = 1e-13 * ea_norm * (e_mid.norm() + e_reach) * (r_norm + q_reach);
    const double r = interval_detail::up(radius * (1 + 1e-12) + slack);
    return value - r <= 0 && value + r >= 0;
  }

  // Edge i of A (fixed) against the moving edge j of B, Q0 Q1, with direction enclosure eb.
  bool edges_may_touch(int i, int j, const IVec3& Q0, const IVec3& Q1, const IVec3& eb) const {
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
    if (std::max({n[0].mag(), n[1].mag(), n[2].mag()}) <= 1e-12 * ea.norm() * B_.edge_length[j]) return false;
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

  const RelativeMotion& rel_AB_;
  const RelativeMotion& rel_BA_;
  FixedTriangle A_, B_;  // each in its own body frame
  double touch_distance_ = 0;
  // Nearly coplanar triangles that tilt as they move (a box turning over another) keep
  // the interval tests from excluding anything until the intervals are tiny, and the
  // bisection then visits a huge tree. A budget bounds it; typical pairs need < 200 nodes.
  static constexpr long kNodeBudget = 4000;
  mutable long nodes_ = 0;
  mutable bool exhausted_ = false;
};

}  // namespace

namespace {

// The first verified contact in W. A leaf is accepted only when it holds a verified
// contact, or the triangles touch at its start. Otherwise the enclosures were too
// coarse there (the triangles pass within about the motion over a leaf): the leaf is
// searched again at a 1024 times finer tolerance, which either finds a verified
// contact inside it or proves it contact-free, and at the finest level the search
// resumes d / (closing speed) later, d the triangles' distance (a proven contact-free
// step, conservative-advancement style).
FeatureContact resolve(const TrianglePairSearch& search, Interval W, double tolerance, int zoom_levels, uint32_t features) {
  constexpr int kMaxSteps = 16;
  for (int step = 0; step < kMaxSteps; ++step) {
    const Leaf leaf = search.search(W, features, tolerance);
    if (!leaf.alive) return {};
    // Out of budget: the start of the unresolved node, conservative (possibly early).
    if (search.exhausted()) return TrianglePairSearch::feature(search.closest_feature(leaf.T.lo, leaf.alive), leaf.T.lo);
    if (const auto contact = search.verify(leaf)) return *contact;
    const double d = search.distance_at(leaf.T.lo);
    if (d <= search.touch_distance()) return TrianglePairSearch::feature(search.closest_feature(leaf.T.lo, leaf.alive), leaf.T.lo);
    if (zoom_levels > 0) {
      const FeatureContact inner = resolve(search, leaf.T, tolerance / 1024, zoom_levels - 1, features);
      if (inner.time != kNoContact) return inner;
      if (!(leaf.T.hi < W.hi)) return {};
      W.lo = leaf.T.hi;  // the whole leaf is contact-free
      continue;
    }
    const double speed = search.closing_speed_bound({leaf.T.lo, W.hi});
    if (!(speed > 0)) return {};
    const double next = interval_detail::down(leaf.T.lo + d / speed);
    if (next > W.hi) return {};
    W.lo = std::max(next, W.lo);
  }
  // Still unresolved after many steps: report the end of the proven contact-free
  // prefix (never late; the only case where the TOI may be more than the tolerance early).
  return TrianglePairSearch::feature(search.closest_feature(W.lo, features), W.lo);
}

}  // namespace

FeatureContact triangle_pair_toi(const RelativeMotion& rel_AB, const RelativeMotion& rel_BA, const Eigen::Vector3d a[3],
                                 const Eigen::Vector3d b[3], const Interval& window, double time_tolerance,
                                 long* nodes_used, uint32_t features) {
  features &= kAllPairs;
  if (!(window.lo <= window.hi) || features == 0) return {};
  const TrianglePairSearch search(rel_AB, rel_BA, a, b, window);
  const FeatureContact contact = resolve(search, window, time_tolerance, 1, features);
  if (nodes_used) *nodes_used = search.nodes();
  return contact;
}

uint32_t feature_pairs(uint8_t owned_a, uint8_t owned_b) {
  uint32_t bits = (owned_b & 7u) | (owned_a & 7u) << 3;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if ((owned_a >> (3 + i) & 1) && (owned_b >> (3 + j) & 1)) bits |= 1u << (6 + 3 * i + j);
  return bits;
}

}  // namespace arphys::collision
