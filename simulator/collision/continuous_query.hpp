#pragma once
// Continuous collision query between two triangle meshes, each moving on its own
// screw motion from its pose at t = 0 to its pose at t = 1 (docs/method.md section 1):
// a best-first traversal of the pair of OBB trees over (node pair, time interval),
// culled by interval separating-axis tests with time subdivision, ending in the exact
// vertex/face and edge/edge tests of the triangle pairs that survive.
//
// Contract: the reported time of impact is never later than the first contact of the
// two surfaces and at most `time_tolerance` earlier; no contact is missed. "Contact"
// is of the surfaces: a body entirely inside the other without touching is not one.
#include <Eigen/Core>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/collision/feature_toi.hpp"
#include "simulator/geometry/screw_motion.hpp"

namespace arphys::collision {


struct ContactFeatures {
  FeaturePair kind = FeaturePair::kNone;
  int triangle_A = -1, triangle_B = -1;
  int corner_A = -1, corner_B = -1;  // 0..2 within the triangle
};

struct ContinuousOptions {
  // Width, in units of the motion's t, below which a root enclosure is accepted.
  double time_tolerance = 1e-9;
  // Smallest time interval the culling subdivides (the elementary tests go further).
  double min_culling_interval = 1.0 / 4096;
  // The culling halves the time interval when B's box sweeps more than this many
  // times the larger box's half extent over it, and splits a box otherwise.
  double time_split_ratio = 1.0;
  // Work budget in triangle pairs (0: none). A query that exceeds it stops and reports
  // the end of what it proved contact-free as a time of impact without features
  // (budget_exhausted): never late, only earlier. A simulation uses it to bound the
  // cost of pathological pairs (one mesh sunk inside another).
  long max_triangle_pairs = 0;
  // Work budget in elementary search nodes over all triangle pairs (0: none), with the
  // same conservative answer: bounds the cost of nearly coplanar meshes turning against
  // each other, where a few pairs can take millions of nodes.
  long max_search_nodes = 0;
  // The caller has found the two meshes apart at the motions' start poses (a simulation
  // tests that for its contacts at the same poses): the query's own start test, as
  // costly as a discrete intersection test, is skipped. Must be exact, not a guess.
  bool apart_at_start = false;
  // Convex sets: piece pairs closer than this at the start whose points move less than a
  // quarter of the thinner piece's thickness relative to each other are not swept: they
  // cannot pass through each other, and ContinuousResult::touching_unswept tells the
  // caller to check the end of their motion instead (0: every piece pair is swept).
  double touching_unswept_m = 0;
};

struct ContinuousStats {
  long node_pairs_tested = 0;
  long time_splits = 0;
  long triangle_pairs_tested = 0;
  long search_nodes = 0;
  bool budget_exhausted = false;
};

struct ContinuousResult {
  bool collides = false;
  double time_of_impact = 1.0;  // in [0, 1]; 1 when there is no contact
  ContactFeatures features;
  Eigen::Vector3d point_W = Eigen::Vector3d::Zero();   // contact point at the TOI, world, metres
  Eigen::Vector3d normal_W = Eigen::Vector3d::Zero();  // unit, pointing from A towards B
  // Without contact: a proven lower bound on the two bodies' distance all along the
  // motions (convex sets only; 0 where not proven).
  double clearance_m = 0;
  // Some piece pairs were left to the caller's end check (ContinuousOptions::touching_unswept_m).
  bool touching_unswept = false;
  ContinuousStats stats;
};

ContinuousResult time_of_impact(const CollisionMesh& A, const geometry::ScrewMotion& motion_A, const CollisionMesh& B,
                                const geometry::ScrewMotion& motion_B, const ContinuousOptions& options = {});

}  // namespace arphys::collision
