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

// A bound on how fast the two pieces' points can close in on each other from t to the end
// (metres per unit of t): the relative velocity of their centres at t, what it can change by
// until the end (a centre on a screw keeps its speed and turns at the screw's rate), and the
// turn of each piece's farthest point about its centre. Bodies moving together (a pile
// shoved along) close slowly whatever their speed.
double closing_speed_bound(const ConvexPiece& a, const ScrewMotion& motion_A, const ConvexPiece& b,
                           const ScrewMotion& motion_B, double t) {
  const Eigen::Vector3d v_a = motion_A.velocity_of_point(motion_A.pose_at(t) * a.centroid_m());
  const Eigen::Vector3d v_b = motion_B.velocity_of_point(motion_B.pose_at(t) * b.centroid_m());
  const double turn_of_velocity = motion_A.angle_rad() * v_a.norm() + motion_B.angle_rad() * v_b.norm();
  const double spin = motion_A.angle_rad() * a.radius_m() + motion_B.angle_rad() * b.radius_m();
  return ((v_b - v_a).norm() + turn_of_velocity * (1 - t) + spin) * (1 + 1e-12) + 1e-300;
}

// The motion from t to 1 of a screw: the same path, its parameter stretched.
ScrewMotion rest_of(const ScrewMotion& motion, double t) { return ScrewMotion(motion.pose_at(t), motion.end()); }

// Advances one piece pair from t = 0 while a step of at least kSmallestStep is proven
// safe; returns how far the pair is proven apart (1: the whole motion) and whether it is
// proven apart (not just not touching) there.
double advance(const ConvexPiece& a, const ScrewMotion& motion_A, const ConvexPiece& b, const ScrewMotion& motion_B,
               bool* apart_there) {
  double t = 0;
  *apart_there = false;
  for (int step = 0; step < kMaxSteps; ++step) {
    const double speed = closing_speed_bound(a, motion_A, b, motion_B, t);
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
      const double speed = closing_speed_bound(a, motion_A, b, motion_B, 0);
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
