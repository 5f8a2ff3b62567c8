#pragma once
// Exact elementary continuous tests between two moving triangles: the three
// vertex/face pairs each way and the nine edge/edge pairs (METHOD.md section 1.4).
//
// Each pair's coplanarity function (one or two frequencies of sines plus the screw's
// linear axial term: not a polynomial in general) and its in-face / in-edge conditions
// are enclosed over a time interval with the interval arithmetic of the culling; the
// interval is halved, earliest half first, until it is `time_tolerance` wide while
// some pair's conditions still hold. All fifteen pairs share one bisection, so the
// screw terms are evaluated once per interval.
//
// Certified: the returned time is never later than the true first contact of the two
// triangles and at most `time_tolerance` earlier; no contact is missed. A near miss
// closer than the motion over `time_tolerance` may be reported as a contact.
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
};
const char* to_string(FeaturePair kind);

struct FeatureContact {
  double time = kNoContact;
  FeaturePair kind = FeaturePair::kNone;
  int corner_A = -1, corner_B = -1;  // 0..2 within the triangle
};

// Triangle a (corners in A's body frame) and triangle b (in B's body frame); rel_AB
// moves B's points into A's frame, rel_BA the reverse. Searches `window` only.
FeatureContact triangle_pair_toi(const RelativeMotion& rel_AB, const RelativeMotion& rel_BA, const Eigen::Vector3d a[3],
                                 const Eigen::Vector3d b[3], const Interval& window, double time_tolerance);

}  // namespace arphys::collision
