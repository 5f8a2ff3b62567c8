#include "simulator/collision/convex_advancement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/collision/convex_distance.hpp"

namespace arphys::collision {
namespace {

using geometry::ScrewMotion;

// Steps of advancement per piece pair before the rest of the motion is swept, and the
// smallest step (a fraction of the motion) worth taking: a pair closing slowly from a
// touch would take thousands.
constexpr int kMaxSteps = 32;
// Steps of the vertex-wise bound past a stall (apart_along), each the rest of the motion halved
// at most kMaxHalvings times.
constexpr int kMaxVertexSteps = 32;
constexpr int kMaxHalvings = 4;
constexpr double kSmallestStep = 0.02;
// A distance bound that proves two pieces apart whatever the rounding of its computation.
constexpr double kApart_m = 1e-12;

// A piece's centre and its velocity at t along its body's screw motion.
struct PieceMotion {
  Eigen::Vector3d centre_W, v_W;
};
PieceMotion piece_motion_at(const ConvexPiece& piece, const ScrewMotion& motion, double t) {
  const Eigen::Vector3d centre_W = motion.pose_at(t) * piece.centroid_m();
  return {centre_W, motion.velocity_of_point(centre_W)};
}

// Bounds on how fast the two pieces' points can close in on each other from t to the end
// (metres per unit of t): the relative velocity of their centres at t, what it can change by
// until the end (a centre on a screw keeps its speed and turns at the screw's rate), and the
// turn of each piece's farthest point about its centre. `along`: the bound on the closing
// along that fixed unit axis (A towards B) alone, which a pair sliding across its gap hardly
// has; without it, the bound on any closing. Bodies moving together (a pile shoved along)
// close slowly whatever their speed.
double closing_speed_bound(const ConvexPiece& a, const ScrewMotion& motion_A, const PieceMotion& at_A,
                           const ConvexPiece& b, const ScrewMotion& motion_B, const PieceMotion& at_B, double t,
                           const Eigen::Vector3d* along = nullptr) {
  const Eigen::Vector3d& v_a = at_A.v_W;
  const Eigen::Vector3d& v_b = at_B.v_W;
  const double turn_of_velocity = motion_A.angle_rad() * v_a.norm() + motion_B.angle_rad() * v_b.norm();
  const double spin = motion_A.angle_rad() * a.radius_m() + motion_B.angle_rad() * b.radius_m();
  const double centres = along ? along->dot(v_a - v_b) : (v_b - v_a).norm();
  return (centres + turn_of_velocity * (1 - t) + spin) * (1 + 1e-12) + 1e-300;
}

// The motion from t to 1 of a screw: the same path, its parameter stretched.
ScrewMotion rest_of(const ScrewMotion& motion, double t) { return ScrewMotion(motion.pose_at(t), motion.end()); }

// A piece's vertices at t as they move along the fixed unit axis n: each one's height along
// n, its velocity along n and its speed (per unit of the motion's parameter).
struct AxisReach {
  std::vector<Eigen::Vector3d> moving;  // (height, n . v, |v|) per vertex
  double angle_rad = 0;                 // the screw's rate of turn
  AxisReach(const ConvexPiece& piece, const ScrewMotion& motion, double t, const Eigen::Vector3d& n)
      : angle_rad(motion.angle_rad()) {
    const geometry::Pose X = motion.pose_at(t);
    moving.reserve(piece.vertices_m().size());
    for (const Eigen::Vector3d& v : piece.vertices_m()) {
      const Eigen::Vector3d x = X * v;
      const Eigen::Vector3d velocity = motion.velocity_of_point(x);
      moving.emplace_back(n.dot(x), n.dot(velocity), velocity.norm());
    }
  }
  // The highest any vertex gets along sign * n over the next s of the motion. A point of a
  // screw motion moves with a velocity that turns at the screw's rate (the velocity field
  // is constant in the world), so over s it rises by at most s n.v + s^2 angle |v| / 2.
  double highest(double sign, double s) const {
    const double curl = 0.5 * angle_rad * s * s;
    double most = -std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& m : moving)
      most = std::max(most, sign * m[0] + std::max(0.0, sign * s * m[1] + curl * m[2]));
    return most;
  }
};

// Whether the pieces stay apart along n over the next s of the motion: the most A's vertices
// can rise and B's sink. A pair resting on each other and sliding, whose contact points the
// solve holds (n.v about 0), is proven apart here where the closing-speed bounds of advance()
// stall on the turn of its farthest points.
// (margin_m: how far apart they stay, when they do.)
bool apart_along(const AxisReach& a, const AxisReach& b, double s, double* margin_m) {
  const double top_A = a.highest(1, s), bottom_B = -b.highest(-1, s);
  const double rounding = 1e-12 * (std::abs(top_A) + std::abs(bottom_B));
  *margin_m = bottom_B - top_A - rounding;
  return *margin_m > kApart_m;
}

// Advances one piece pair from t = 0 while the gap is at least what kSmallestStep of the
// undirected bound closes; returns how far the pair is proven apart (1: the whole motion)
// and whether it is proven apart (not just not touching) there. Each step is bounded along
// the axis GJK proved the gap on: the supports' separation along a fixed axis is a lower
// bound on the distance, and it shrinks no faster than the points close along that axis.
// (start_A, start_B: the pieces' motions at t = 0, already known to the caller.)
struct Advance {
  double t = 0;            // proven free until here (1: the whole motion)
  bool apart = false;      // proven apart (not just not touching) at t
  double clearance_m = 0;  // where the first bound proves the whole motion apart: how far apart it holds them
  bool touching = false;   // within touching_m at the start (touching_m > 0): not advanced
};
Advance advance(const ConvexPiece& a, const ScrewMotion& motion_A, const PieceMotion& start_A, const ConvexPiece& b,
                const ScrewMotion& motion_B, const PieceMotion& start_B, double touching_m) {
  Advance out;
  double& t = out.t;
  int vertex_steps = 0;
  for (int step = 0; step < kMaxSteps; ++step) {
    const PieceMotion at_A = t == 0 ? start_A : piece_motion_at(a, motion_A, t);
    const PieceMotion at_B = t == 0 ? start_B : piece_motion_at(b, motion_B, t);
    const double speed = closing_speed_bound(a, motion_A, at_A, b, motion_B, at_B, t);
    const double enough = t == 0 ? std::max(speed, touching_m) : speed * (1 - t);
    const ConvexDistance d = convex_distance(a, motion_A.pose_at(t), b, motion_B.pose_at(t), enough);
    if (t == 0 && touching_m > 0 && !(d.lower_m > touching_m)) {
      out.touching = true;
      return out;
    }
    out.apart = d.lower_m > kApart_m;
    if (!out.apart) return out;
    const double along = std::min(speed, closing_speed_bound(a, motion_A, at_A, b, motion_B, at_B, t, &d.axis_W));
    if (along <= 0 || d.lower_m > along * (1 - t)) {
      if (t == 0) out.clearance_m = d.lower_m - std::max(along, 0.0);
      t = 1;
      return out;
    }
    if (d.lower_m > kSmallestStep * speed) {
      t += d.lower_m / along;
      continue;
    }
    // Stalled by the bounds on the farthest points' turn: the vertex-wise bound over the
    // rest of the motion, or over a half, a quarter ... of it, advances a pair that rests
    // and slides (its turn closes the gap at second order only). Failing that, the sweep
    // takes the pair from here.
    if (++vertex_steps > kMaxVertexSteps) return out;
    const AxisReach reach_A(a, motion_A, t, d.axis_W), reach_B(b, motion_B, t, d.axis_W);
    double s = 1 - t, margin_m = 0;
    for (int halving = 0; !apart_along(reach_A, reach_B, s, &margin_m); ++halving) {
      if (halving == kMaxHalvings) return out;
      s *= 0.5;
    }
    if (s == 1 - t) {
      if (t == 0) out.clearance_m = margin_m;
      t = 1;
      return out;
    }
    t += s;
    --step;  // (its own budget)
  }
  return out;
}

}  // namespace

ContinuousResult convex_sets_time_of_impact(const ConvexSet& A, const ScrewMotion& motion_A, const ConvexSet& B,
                                            const ScrewMotion& motion_B, const ContinuousOptions& options) {
  // Each piece pair advances on its own; a pair left short of the end is swept by the
  // certified query over the rest of its motion, its two hulls alone (sweeping every
  // hull of both sets from the earliest stall, most of a pile's time went to pieces that
  // had been proven apart). Pairs are swept earliest stall first and stop once the next
  // stall comes after the earliest time of impact found: none of the rest can be earlier.
  struct Stall {
    double t;
    int a, b;
    bool apart;
  };
  // Each piece's motion at the start and its centre there, once per piece, not per pair.
  const auto starts = [](const ConvexSet& set, const ScrewMotion& motion) {
    std::vector<std::pair<PieceMotion, Eigen::Vector3d>> out;
    out.reserve(set.pieces.size());
    for (const ConvexPiece& piece : set.pieces)
      out.emplace_back(piece_motion_at(piece, motion, 0), motion.start() * piece.centroid_m());
    return out;
  };
  const auto starts_A = starts(A, motion_A), starts_B = starts(B, motion_B);
  const geometry::Pose X_AB = motion_A.start().inverse() * motion_B.start();
  std::vector<Stall> stalls;
  double clearance_m = std::numeric_limits<double>::infinity();
  bool touching_unswept = false;
  for (int a = 0; a < static_cast<int>(A.pieces.size()); ++a)
    for (int b = 0; b < static_cast<int>(B.pieces.size()); ++b) {
      const ConvexPiece& piece_a = A.pieces[a];
      const ConvexPiece& piece_b = B.pieces[b];
      const auto& [start_a, centre_a] = starts_A[a];
      const auto& [start_b, centre_b] = starts_B[b];
      const double speed = closing_speed_bound(piece_a, motion_A, start_a, piece_b, motion_B, start_b, 0);
      const double ball_gap = (centre_b - centre_a).norm() - piece_a.radius_m() - piece_b.radius_m();
      if (ball_gap > speed + kApart_m) {  // their balls cannot meet
        clearance_m = std::min(clearance_m, ball_gap - speed);
        continue;
      }
      // Nor their boxes (most piece pairs of two bunnies in a pile that pass the balls).
      if (const double box_gap = box_gap_lower_bound_m(piece_a.box_m(), piece_b.box_m(), X_AB);
          box_gap > speed + kApart_m) {
        clearance_m = std::min(clearance_m, box_gap - speed);
        continue;
      }
      // Touching pieces that cannot pass through each other: left to the caller.
      const bool may_leave = speed <= 0.5 * std::min(piece_a.half_thickness_m(), piece_b.half_thickness_m());
      const Advance pair =
          advance(piece_a, motion_A, start_a, piece_b, motion_B, start_b, may_leave ? options.touching_unswept_m : 0.0);
      touching_unswept |= pair.touching;
      if (pair.touching) continue;
      clearance_m = std::min(clearance_m, pair.clearance_m);
      if (pair.t < 1) stalls.push_back({pair.t, a, b, pair.apart});
    }
  std::sort(stalls.begin(), stalls.end(), [](const Stall& x, const Stall& y) {
    return x.t != y.t ? x.t < y.t : (x.a != y.a ? x.a < y.a : x.b < y.b);
  });
  ContinuousResult first;
  for (const Stall& stall : stalls) {
    if (first.collides && stall.t >= first.time_of_impact) break;
    ContinuousOptions rest = options;
    rest.apart_at_start = options.apart_at_start || stall.apart;
    const CollisionMesh& hull_a = *A.piece_hulls[stall.a];
    const CollisionMesh& hull_b = *B.piece_hulls[stall.b];
    // (The rest's tolerance, in its own parameter, is the same fraction of a shorter motion.)
    ContinuousResult r = stall.t == 0 ? time_of_impact(hull_a, motion_A, hull_b, motion_B, rest)
                                      : time_of_impact(hull_a, rest_of(motion_A, stall.t), hull_b, rest_of(motion_B, stall.t), rest);
    if (!r.collides) continue;
    r.time_of_impact = stall.t + (1 - stall.t) * r.time_of_impact;
    if (!first.collides || r.time_of_impact < first.time_of_impact) first = r;
  }
  // (A stall's sweep proves no clearance.)
  if (!first.collides && stalls.empty() && !touching_unswept) first.clearance_m = std::max(clearance_m, 0.0);
  first.touching_unswept = touching_unswept;
  return first;
}

}  // namespace arphys::collision
