#pragma once
// Exact elementary continuous tests between two moving triangles: the three
// vertex/face pairs each way and the nine edge/edge pairs (docs/method.md section 1.4).
//
// Each pair's coplanarity function and its in-face / in-edge conditions are enclosed
// over a time interval in interval arithmetic (mean-value form for the linear ones);
// the interval is halved, earliest half first, until it is `time_tolerance` wide while
// some pair's conditions still hold. All fifteen pairs share one bisection. The
// function is not a polynomial even when one body is still: the screw's axial
// translation adds a term linear in t = 2 atan(u) / w to the u = tan(wt/2) form, and
// with two rotating bodies it has two frequencies, so the same certified bisection
// serves every case.
//
// A leaf is accepted only when a pair's coplanarity function changes sign across it
// (exact end-point evaluations) with its in-face / in-edge condition holding where it
// does, or when the triangles touch at its start (are closer than ten times the
// enclosures' rounding allowance, about 1e-11 times the coordinates' magnitude; a
// pair that stays that close, two boxes pressed face to face, is a contact whatever
// its time tolerance says). A leaf the enclosures could not
// rule out but that holds no verified contact (the triangles graze past within about
// the motion over a leaf) is searched again at a 1024 times finer tolerance, twice
// over; below that the search resumes d / (closing speed) later, d the triangles'
// distance: a proven contact-free step.
//
// Contract: the returned time is never later than the first contact of the two
// triangles, and at most `time_tolerance` earlier, unless the triangles were already
// touching in the sense above, or 100 such steps left it unresolved (then the proven
// contact-free prefix's end is returned). No contact is missed. A vertex sliding in a
// face's plane, and an edge sliding in the plane of another, are left to the
// neighbouring features that they reach first (their coplanarity is zero throughout).
#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "simulator/collision/interval.hpp"
#include "simulator/collision/screw_enclosure.hpp"

namespace arphys::collision {

constexpr double kNoContact = std::numeric_limits<double>::infinity();

enum class FeaturePair {
  kNone,
  kOverlapAtStart,  // the surfaces already intersect at t = 0
  kVertexFace,      // vertex corner_B of triangle B meets the face of triangle A
  kFaceVertex,      // vertex corner_A of triangle A meets the face of triangle B
  kEdgeEdge,        // edge (corner_A, corner_A + 1) meets edge (corner_B, corner_B + 1)
  kPrimitive,       // a plane's or a sphere's surface meets the other shape: point and normal, no triangles
};
const char* to_string(FeaturePair kind);

struct FeatureContact {
  double time = kNoContact;
  FeaturePair kind = FeaturePair::kNone;
  int corner_A = -1, corner_B = -1;  // 0..2 within the triangle
};

// Earliest time in `window` at which `may_touch(T)` (false only when contact is
// impossible over T) still holds once T is `time_tolerance` wide: depth-first,
// earliest half first. kNoContact when it is ruled out everywhere. The scalar tests of
// the primitives use it; the triangle pairs use a joint version over 15 conditions.
template <typename MayTouch>
double first_candidate_time(const Interval& window, double time_tolerance, const MayTouch& may_touch) {
  if (!(window.lo <= window.hi) || !may_touch(window)) return kNoContact;
  if (window.width() <= time_tolerance) return window.lo;
  const double mid = window.mid();
  const double left = first_candidate_time(Interval{window.lo, mid}, time_tolerance, may_touch);
  return left != kNoContact ? left : first_candidate_time(Interval{mid, window.hi}, time_tolerance, may_touch);
}

// Triangle a (corners in A's body frame) and triangle b (in B's body frame); rel_AB
// moves B's points into A's frame, rel_BA the reverse. Searches `window` only.
// nodes_used (optional) receives the number of search nodes the pair took (at most a
// fixed per-pair budget, beyond which the answer is the start of the unresolved part:
// never late).
// features: the feature pairs to test (bits 0-2 corner k of b against a's face, 3-5
// corner k of a against b's face, 6 + 3 i + j edge i of a against edge j of b; edge i
// runs from corner i to i + 1), e.g. from feature_pairs() below.
FeatureContact triangle_pair_toi(const RelativeMotion& rel_AB, const RelativeMotion& rel_BA, const Eigen::Vector3d a[3],
                                 const Eigen::Vector3d b[3], const Interval& window, double time_tolerance,
                                 long* nodes_used = nullptr, uint32_t features = (1u << 15) - 1);

// The feature pairs of two triangles given the features each stands for
// (CollisionMesh::owned_features): a's corners against b's face only if a owns them, etc.
uint32_t feature_pairs(uint8_t owned_a, uint8_t owned_b);

}  // namespace arphys::collision
