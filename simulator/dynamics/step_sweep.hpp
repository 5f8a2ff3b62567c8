#pragma once
// A step's sweep of the motions a solve gave: the CCD of every pair whose swept boxes meet
// (screw motions from the current poses to the end poses), and the check at the end of the
// motion of pairs that touch at the start or rest and move too little to pass through each
// other. A stage of World::step with its inputs and outputs typed; it reads the bodies,
// never writes them, and records mesh pairs' crossing tests in the memo.
#include <Eigen/Geometry>
#include <map>
#include <vector>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/dynamics/contact.hpp"
#include "simulator/dynamics/step_contacts.hpp"
#include "simulator/dynamics/worker_pool.hpp"
#include "simulator/dynamics/world_model.hpp"

namespace arphys::dynamics {

// A pair's CCD answer for motions from the current poses to next_A, next_B.
struct CachedImpact {
  bool valid = false;
  geometry::Pose next_A, next_B;
  collision::ContinuousResult result;
  std::vector<ImpactPoint> hits;  // the meeting, or the points a touching pair digs in at
  bool deepens = false;           // touching at the start, deeper than allowed at the end
  double allowed_depth_m = 0;     // for a touching pair: the deeper of overlap_tolerance_m and its start depth
  // A touching pair's deepest overlap at the start poses, kept when the pair is asked again
  // from the same start with other end poses (a re-solve moves every body of its island);
  // negative: not measured.
  double start_depth_m = -1;
  bool swept = false;     // the CCD ran and timed the motion (not touching at the start)
  double free_until = 1;  // a touching mesh pair: the fraction of the motion before its surfaces cross
};
using ImpactCache = std::map<BodyPair, CachedImpact>;

// What a sweep reads of the world (every body, indexed as participants name them), the memo
// it records mesh pairs in, its threads.
struct SweepWorld {
  const WorldModel& model;
  const std::vector<BodyState>& state;
  MeshCrossingMemo& memo;
  const WorkerPool& pool;
};

// The sweep's answer: the earliest time of impact inside the motion (a fraction of it; 1:
// none), whether a pair touching at the start ends deeper than it may (its points are in
// `meeting`, with no time of impact), and how many pair motions the CCD swept.
struct Sweep {
  double tau = 1;
  bool deepening = false;
  int ccd_queries = 0;
};
// The participants' (sorted body indices) motions from their current poses to `next` (by
// participant). cache (optional): answers for pairs whose motions it has seen since the
// poses last changed, updated. meeting (optional): the points each pair meets or digs in at.
// resting_pairs: body pairs with contacts at the current poses (sorted); those moving less
// than max_unswept_motion_m relative to each other are checked at the end, not swept.
// swept_pairs: the participants' pairs (by slot) whose swept boxes overlap, if known.
Sweep sweep_motions(const SweepWorld& world, const std::vector<int>& participants,
                    const std::vector<geometry::Pose>& next, const std::vector<BodyPair>* resting_pairs,
                    ImpactCache* cache, ImpactMap* meeting, const std::vector<BodyPair>* swept_pairs = nullptr);

// Box containing a body's bounding ball (radius_m about its origin) along its screw motion
// from X_WB to `next`.
Eigen::AlignedBox3d swept_box(const geometry::Pose& X_WB, double radius_m, const geometry::Pose& next);
// How deep bodies a and b are inside each other at these poses (0: apart).
double deepest_overlap(const BodyModel& a, const geometry::Pose& X_WA, const BodyModel& b, const geometry::Pose& X_WB);
// The relative motion under which a resting pair is checked at the end of its motion
// instead of swept (WorldOptions::resting_unswept_motion_m, capped by the pair's shapes).
double max_unswept_motion_m(const WorldOptions& options, const BodyModel& a, const BodyModel& b);

}  // namespace arphys::dynamics
