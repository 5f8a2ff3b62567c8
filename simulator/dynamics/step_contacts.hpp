#pragma once
// A step's contacts at the current poses: every feature pair of two bodies closer than the
// contact tolerance (reduced per pair), with the hints the previous step left them, and
// for mesh pairs the contact that pushes crossed surfaces apart. A stage of World::step
// with its inputs and outputs typed; it reads the bodies, never writes them.
#include <map>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "simulator/collision/discrete_query.hpp"
#include "simulator/dynamics/contact.hpp"
#include "simulator/dynamics/worker_pool.hpp"
#include "simulator/dynamics/world_model.hpp"

namespace arphys::dynamics {

using BodyPair = std::pair<int, int>;  // body indices, first < second

// What a step leaves the next one's contacts, each sorted by pair.
struct ContactHints {
  // Where each pair pushed in the last solve of the step: the exact solver starts its
  // active set from the contacts within the contact tolerance of these.
  struct Pushed {
    BodyPair bodies;
    Eigen::Vector3d point_W;
  };
  std::vector<Pushed> pushed_before;
  // The forces of the step's first solve (every group over the whole step, with gravity):
  // where the iterative solver and the friction sweeps start from.
  struct Force {
    BodyPair bodies;
    Eigen::Vector3d point_W, force_W_N;
  };
  std::vector<Force> warm_forces;
  // Bounces a step held back (WorldOptions::sequential_bounce_restitution): the pair's
  // contacts along that normal (first to second body) separate at least that fast.
  struct Bounce {
    BodyPair bodies;
    Eigen::Vector3d normal_W;
    double speed_m_s = 0;
  };
  std::vector<Bounce> pending_bounces;
};

// What mesh pairs' crossing tests know, shared by a step's contacts and its sweep and
// carried to the next step: a mesh's distances are unsigned, so whether two meshes cross
// is a test of its own, and the same test at the same poses is not run twice.
struct MeshCrossingMemo {
  struct ApartAt {
    geometry::Pose X_WA, X_WB;
  };
  // Pairs the contacts found not crossing at these poses (this step): their sweep skips
  // its start test.
  std::map<BodyPair, ApartAt> apart_at;
  // Pairs the sweep proved apart at the end poses of a motion (written in a step, read in
  // the next as apart_at_last_end: the step usually ends there).
  std::map<BodyPair, ApartAt> apart_at_end, apart_at_last_end;
  // Triangle pairs near each other, kept while a step uses them.
  struct Nearby {
    collision::NearbyTrianglePairs pairs;
    bool used = false;
  };
  std::map<BodyPair, Nearby> nearby;
  // Bodies added or placed since the last step (by body): only they can cross deeper than
  // the contact tolerance. Their pairs are tested with no feature within the tolerance,
  // and one found crossing stays in placed_crossing (tested every step) until apart.
  std::vector<char> placed_since_step;
  std::set<BodyPair> placed_crossing;
  int crossing_tests = 0;  // this step's

  // Whether `known` holds pair (i, j) apart at exactly these poses.
  static bool known_apart(const std::map<BodyPair, ApartAt>& known, int i, int j, const geometry::Pose& X_WA,
                          const geometry::Pose& X_WB);
  collision::NearbyTrianglePairs* nearby_pairs(int i, int j);
  // At a step's start: the last step's ends become what it ended at, unused entries go.
  void begin_step();
};

// Mesh crossings deeper than this are not measured.
constexpr double kDeepestCrossingMeasured_m = 0.01;

// The contacts among the participants (sorted body indices) at the bodies' poses (state, by
// body), each with its hints. expected: how many to reserve room for. Depth-measured pairs on
// the pool's threads, mesh pairs in order.
std::vector<Contact> gather_contacts(const WorldModel& model, const std::vector<BodyState>& state,
                                     const ContactHints& hints, MeshCrossingMemo& memo, const WorkerPool& pool,
                                     const std::vector<int>& participants, std::size_t expected);

}  // namespace arphys::dynamics
