#pragma once
// The options a World steps by: tolerances, the solver's and the CCD's settings, limits.
// World's constructor checks them (check_world_options).
#include <Eigen/Core>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/dynamics/contact_solver.hpp"

namespace arphys::dynamics {

struct WorldOptions {
  Eigen::Vector3d gravity_m_s2{0, 0, -9.81};
  // Feature pairs closer than this are constraints of the step.
  double contact_tolerance_m = 1e-3;
  // A resting pair (constraints of the step already) whose points move less than this
  // relative to each other over a step is held by its contacts and checked at the end of
  // its motion instead of swept by the CCD (sweep_motions, step_sweep.hpp). Capped per pair at a
  // quarter of the thinner body's thickness, so nothing passes through anything unswept;
  // pairs with a mesh (whose thinnest part is not known) or with restitution (what the
  // end check finds is held, not bounced) keep to contact_tolerance_m. (The CCD of such
  // pairs, surfaces a gap apart, and the cuts it finds are most of a settling pile's cost.)
  double resting_unswept_motion_m = 10e-3;
  // No pair ends a step deeper inside each other than this, or than it started the
  // step (a tracked body pushed into a virtual one is undone at
  // max_depenetration_speed_m_s, not at once).
  double overlap_tolerance_m = 1e-6;
  // The gap resting contacts keep: surfaces never quite touch at rest, so the CCD of the
  // next step does not see them as impacts (no endless tiny events).
  double contact_gap_m = 1e-6;
  // Speed at which an overlap (a tracked body pushed into a virtual one faster than it
  // could move) is undone; bounded so nothing is launched.
  double max_depenetration_speed_m_s = 0.05;
  // Approach speeds below this do not bounce (resting contact under gravity).
  double restitution_threshold_m_s = 0.05;
  // A bounce that a solve brings about within the step (a struck body striking the next)
  // is met in turn, the step cut there and bounced from the velocities then, when the
  // pair's restitution is at least this. Below it the pair is held together by this step's
  // solve and pushed apart at the next step's start with the speed it missed: momentum and
  // the restitution's share of energy kept, one step late, and no cut, which re-solves and
  // re-sweeps the whole group (in a pile of bunnies, restitution 0.3-0.4, nearly every step).
  double sequential_bounce_restitution = 0.5;
  int max_events_per_step = 16;
  // Points of resting primitive pairs (boxes, spheres, planes) that the step's motion
  // leaves deeper than overlap_tolerance_m, with nothing meeting inside the step, are
  // lifted out by moving the end poses (post-stabilisation, position_projection.hpp)
  // instead of by a velocity constraint and another solve of the step. False: every
  // such point is a constraint of a re-solve (docs/decisions/0004).
  bool project_deep_points = true;
  // Launch guard (guard_launches, step_solve.hpp): speed (of a
  // body's kinetic energy) a solve may add beyond twice the fastest body it couples and
  // the depenetration speed.
  double launch_guard_slack_m_s = 0.5;
  // No body point moves faster than this after a solve (metres per second).
  double max_body_speed_m_s = 60.0;
  // A body pair's contact set is reduced to at most this many points when larger (the
  // closest point per normal direction, then the extremes of each contact patch, which
  // keep its support polygon; see manifold_reduction.hpp).
  int max_contacts_per_pair = 16;
  // Deactivation ("sleeping"): a dynamic body whose points have all moved slower than
  // sleep_speed_m_s for sleep_after_s is stopped and held as if fixed, costing nothing,
  // until a moving body comes within reach of it over a step; that wakes it and, in turn,
  // the sleepers it touched when it fell asleep. 0: never (the default: the
  // benchmark scenes measure every body every step). A woken body starts from rest.
  double sleep_after_s = 0;
  double sleep_speed_m_s = 0.01;
  ContactSolverOptions solver;
  // Threads for the step's per-pair work (contact manifolds, sweeps and end checks of
  // depth-measured pairs: boxes, spheres, planes, convex pieces); mesh pairs, the solves
  // and the stepping stay on the calling thread. The result does not depend on it.
  int threads = 1;
  // CCD settings; its work budget bounds a step's cost when meshes have sunk into each
  // other (the step is then cut where the CCD stopped, never past a contact).
  collision::ContinuousOptions ccd = [] {
    collision::ContinuousOptions o;
    // A time of impact to a millionth of the step (a nanosecond at 1 ms) is never late
    // and early by less than the motion over that time; the CCD library's default (1e-9,
    // for measuring it) costs near-parallel edges of resting boxes many more iterations
    // for no difference a simulation can show.
    o.time_tolerance = 1e-6;
    o.max_triangle_pairs = 2000;
    o.max_search_nodes = 200000;
    return o;
  }();
};

// Throws std::invalid_argument naming the option and its value when one is out of its
// range (a NaN or negative tolerance, a zero event cap).
void check_world_options(const WorldOptions& options);

}  // namespace arphys::dynamics
