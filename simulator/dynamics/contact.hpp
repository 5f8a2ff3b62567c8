#pragma once
// A contact of a step (a feature pair of two bodies and what the solve did with it), a
// meeting the CCD found inside a step, and what a step reports.
#include <Eigen/Core>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "simulator/collision/discrete_query.hpp"

namespace arphys::dynamics {

struct Contact {
  int body_a = -1, body_b = -1;  // indices into World::bodies()
  collision::ManifoldPoint feature;
  double impulse_N_s = 0;  // normal impulse of the last solve
  // A lower bound on the normal velocity beyond what the gap asks (see ImpactPoint).
  double min_normal_velocity_m_s = -std::numeric_limits<double>::infinity();
  // The pair pushed within contact_tolerance_m of this point in the previous step's last
  // solve (a warm-start hint for the solver, see ContactRow::pushed_before).
  bool pushed_before = false;
  // The force (normal and friction, world frame) within contact_tolerance_m of this point in
  // the previous step's first solve: the iterative solver's warm start (ContactRow).
  Eigen::Vector3d warm_force_W_N = Eigen::Vector3d::Zero();
  Eigen::Vector3d impulse_W_N_s = Eigen::Vector3d::Zero();  // the last solve's normal and friction impulse, world frame
};

// A meeting the CCD found inside a step: the point, fixed in each body, and A's normal
// there (body frames), for a constraint of the re-solved step.
struct ImpactPoint {
  Eigen::Vector3d point_A_B, point_B_B, normal_A_B;
  // A point where a pair touching at the start ends the step this deep inside (metres;
  // negative for a CCD meeting), and the normal velocity that lifts it out: the
  // linearised constraint let it in, so the bound is its velocity in the last solve
  // plus the depth (and the resting gap) over the step, a Newton step on the true
  // end-of-step depth.
  double end_depth_m = -1;
  double min_normal_velocity_m_s = -std::numeric_limits<double>::infinity();
};
using ImpactMap = std::map<std::pair<int, int>, std::vector<ImpactPoint>>;

struct StepReport {
  // Rounds of the step that had something to resolve: CCD meetings or end checks found too
  // deep, each re-solved or, for resting primitive pairs, lifted (`projections` of them).
  int impacts_resolved = 0;
  int projections = 0;          // rounds whose too-deep resting points were lifted by moving end poses
  int events = 0;               // times the step was cut at a time of impact (its busiest group's)
  bool events_capped = false;   // a group's step ended at an impact (time kept, motion dropped)
  int contacts = 0;             // constraints in the last solve of the step
  bool infeasible = false;      // a body squeezed between non-dynamic ones
  int iterative_islands = 0;    // contact islands too large for the exact solver (max_exact_rows)
  double kkt_residual_m_s = 0;  // worst over the step's solves
  // Deepest overlap among the step's resting contacts where they were gathered: the step's
  // start and each cut (0: none). A cut can catch a pair checked only at the end of its
  // motion inside mid-step, but no deeper than the rest of the step undoes at half
  // max_depenetration_speed_m_s (unswept_clear_fraction); every step ends within
  // the overlap tolerance (and its allowed creep).
  double max_penetration_m = 0;
  int solver_iterations = 0;
  int launches_prevented = 0;  // bodies the launch guard slowed (a solve that would launch them)
  int non_finite_held = 0;     // bodies a numerical failure would have made non-finite, held at rest
  int ccd_queries = 0;         // pair motions swept by the CCD (resting pairs are checked at the end instead)
  // Mesh pairs within reach tested for crossing at poses they were gathered at (those the
  // last step's end check or CCD proved apart there are not tested again).
  int mesh_crossing_tests = 0;
  int bodies_asleep = 0;  // after the step (WorldOptions::sleep_after_s)
};

}  // namespace arphys::dynamics
