#include "simulator/collision/convex_advancement.hpp"

#include <algorithm>
#include <cmath>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/collision/convex_distance.hpp"

namespace arphys::collision {
namespace {

using geometry::ScrewMotion;

// Steps of advancement per piece pair before the rest of the motion is swept, and the
// smallest step (a fraction of the motion) worth taking: a pair closing slowly from a
// touch would take thousands.
constexpr int kMaxSteps = 8;
constexpr double kSmallestStep = 0.02;
// A distance bound that proves two pieces apart whatever the rounding of its computation.
constexpr double kApart_m = 1e-12;

// A bound on the speed (metres per unit of t) of every point of the piece on its body's
// screw: the speed of its centre, which stays the same along the motion, and the turn of
// the farthest point about it.
double point_speed_bound(const ConvexPiece& piece, const ScrewMotion& motion) {
  const Eigen::Vector3d centre_W = motion.start() * piece.centroid_m();
  return (motion.velocity_of_point(centre_W).norm() + motion.angle_rad() * piece.radius_m()) * (1 + 1e-12);
}

// The motion from t to 1 of a screw: the same path, its parameter stretched.
ScrewMotion rest_of(const ScrewMotion& motion, double t) { return ScrewMotion(motion.pose_at(t), motion.end()); }

// Advances one piece pair from t = 0 while a step of at least kSmallestStep is proven
// safe; returns how far the pair is proven apart (1: the whole motion) and whether it is
// proven apart (not just not touching) there.
double advance(const ConvexPiece& a, const ScrewMotion& motion_A, const ConvexPiece& b, const ScrewMotion& motion_B,
               bool* apart_there) {
  const double speed = point_speed_bound(a, motion_A) + point_speed_bound(b, motion_B);
  double t = 0;
  *apart_there = false;
  for (int step = 0; step < kMaxSteps; ++step) {
    const double reach = speed * (1 - t);
    const ConvexDistance d = convex_distance(a, motion_A.pose_at(t), b, motion_B.pose_at(t), reach);
    *apart_there = d.lower_m > kApart_m;
    if (d.lower_m > reach) return 1.0;
    if (!(d.lower_m > kSmallestStep * speed)) return t;
    t += d.lower_m / speed;
  }
  return t;
}

}  // namespace

ContinuousResult convex_sets_time_of_impact(const ConvexSet& A, const ScrewMotion& motion_A, const ConvexSet& B,
                                            const ScrewMotion& motion_B, const ContinuousOptions& options) {
  double free_until = 1;
  bool apart_there = true;  // every pair left at free_until is proven apart there
  for (const ConvexPiece& a : A.pieces)
    for (const ConvexPiece& b : B.pieces) {
      const double speed = point_speed_bound(a, motion_A) + point_speed_bound(b, motion_B);
      const double ball_gap = (motion_B.start() * b.centroid_m() - motion_A.start() * a.centroid_m()).norm() -
                              a.radius_m() - b.radius_m();
      if (ball_gap > speed + kApart_m) continue;  // their balls cannot meet
      bool apart = false;
      const double t = advance(a, motion_A, b, motion_B, &apart);
      if (t < free_until) {
        free_until = t;
        apart_there = apart;
      } else if (t == free_until) {
        apart_there = apart_there && apart;
      }
    }
  if (free_until >= 1) return {};
  ContinuousOptions rest = options;
  rest.apart_at_start = options.apart_at_start || apart_there;
  if (free_until == 0) return time_of_impact(*A.hulls, motion_A, *B.hulls, motion_B, rest);
  // (The rest's tolerance, in its own parameter, is the same fraction of a shorter motion.)
  ContinuousResult r = time_of_impact(*A.hulls, rest_of(motion_A, free_until), *B.hulls, rest_of(motion_B, free_until), rest);
  if (r.collides) r.time_of_impact = free_until + (1 - free_until) * r.time_of_impact;
  return r;
}

}  // namespace arphys::collision
