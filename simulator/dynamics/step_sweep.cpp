// The sweep stage of a step: CCD of the pairs whose swept boxes meet, end checks of the
// pairs that touch or rest.
#include "simulator/dynamics/step_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "simulator/collision/broad_phase.hpp"
#include "simulator/collision/separation_certificate.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/dynamics/manifold_reduction.hpp"
#include "simulator/dynamics/step_helpers.hpp"

namespace arphys::dynamics {

using step_helpers::depth_measured;
using step_helpers::meets_inside;

namespace {

// Rounding allowance of a gap between boxes computed from metre-sized coordinates.
constexpr double kGapRounding_m = 1e-9;

// The CCD says the pair already touches (or overlaps) at the start: it cannot time anything after.
bool touching_at_start(const collision::ContinuousResult& r) { return r.collides && !meets_inside(r); }

// One pair of sweep_motions: its slots, its cache entry, and how its motion is checked.
struct PairSweep {
  int p = -1, q = -1;  // slots in the participants
  CachedImpact* query = nullptr;
  bool fresh = false;  // its motions changed since its entry was answered
  bool apart_at_start = false, resting_slowly = false, swept_by_ccd = false;
  double relative_motion_m = 0;
};

// How far any point of the body can be, over the step, from where it was on the motion to
// swept_to when it moves on `now` instead (both from its pose at the step's start).
double motion_change_m(const SweepWorld& w, int body, const geometry::Pose& swept_to,
                       const geometry::ScrewMotion& now) {
  if (swept_to.matrix() == now.end().matrix()) return 0;
  return geometry::motion_change_bound_m(geometry::ScrewMotion(w.state[body].X_WB, swept_to), now,
                                         w.model.radius_m[body]);
}

// For a mesh pair the CCD found touching at the start, or one resting and moving less than
// the contact tolerance (not swept): whether its surfaces cross at the end of the motion; if
// so, the fraction of the motion before they do (query.free_until) and the features
// touching there (query.hits).
void check_mesh_crossing(const WorldOptions& options, const BodyModel& a, const geometry::ScrewMotion& motion_a,
                         const BodyModel& b, const geometry::ScrewMotion& motion_b, double relative_motion_m,
                         CachedImpact& query, collision::NearbyTrianglePairs* nearby) {
  // A mesh's manifold cannot say how deep a point went (its distances are unsigned), and
  // the CCD, touching at the start, times nothing after it; whether the surfaces cross it
  // can say. The last fraction of the motion where they do not is bisected, and the
  // features touching there become constraints of a re-solve. No crossing is allowed: a
  // pair left crossing starts its next motion overlapping, where nothing can follow it.
  const collision::CollisionMesh& mesh_a = *a.shape.triangles();
  const collision::CollisionMesh& mesh_b = *b.shape.triangles();
  const auto crosses = [&](double t) {
    return collision::intersects(mesh_a, motion_a.pose_at(t), mesh_b, motion_b.pose_at(t), nearby);
  };
  if (!crosses(1.0)) return;
  double free = 0, crossing = 1;
  for (int halving = 0; halving < 8; ++halving) {
    const double t = 0.5 * (free + crossing);
    (crosses(t) ? crossing : free) = t;
  }
  query.free_until = free;
  const geometry::Pose X_A = motion_a.pose_at(free), X_B = motion_b.pose_at(free);
  // What can touch within the bisection's last interval.
  const double reach_m = options.contact_gap_m + relative_motion_m * (crossing - free);
  for (const auto& point : reduce_manifold(collision::contact_manifold(a.shape, X_A, b.shape, X_B, reach_m, nearby),
                                           options.max_contacts_per_pair))
    query.hits.push_back(
        {X_A.inverse() * point.point_A_W, X_B.inverse() * point.point_B_W, X_A.linear().transpose() * point.normal_W});
}

// A fresh pair's passes: how it is checked (in order: reads the memo); its CCD and, for a
// depth-measured pair, its end check (any thread); then in order its counts, memo entries
// and, for a mesh pair, its end check.
void classify_sweep(const SweepWorld& w, PairSweep& sweep, const std::vector<int>& participants,
                    double relative_motion_m, double curve_m, const std::vector<BodyPair>* resting_pairs) {
  const int i = participants[sweep.p], j = participants[sweep.q];
  const BodyModel& a = w.model.bodies[i];
  const BodyModel& b = w.model.bodies[j];
  const geometry::Pose& X_WA = w.state[i].X_WB;
  const geometry::Pose& X_WB = w.state[j].X_WB;
  sweep.relative_motion_m = relative_motion_m;
  // A resting pair (constraints of the step already) whose points move less than
  // max_unswept_motion_m relative to each other is held by its contacts, and its motion
  // checked at the end like a touching pair's: a point that ends outside the other body
  // and moved less than that was at most half of it inside in between, which matters only
  // where the step is cut mid-motion (unswept_clear_fraction). The CCD of such pairs
  // (surfaces 1 um apart, edges nearly parallel) is the slowest query there is.
  // Primitives are checked by their manifolds, which measure depth exactly; a mesh pair by
  // whether its surfaces cross at the end (check_mesh_crossing), so only when the contacts
  // found it apart at these start poses (a mesh's manifold can miss a vertex that went in).
  const auto primitive = [](const BodyModel& body) { return body.shape.type() != collision::Shape::Type::kMesh; };
  sweep.apart_at_start =
      MeshCrossingMemo::known_apart(w.memo.apart_at, i, j, X_WA, X_WB);  // (i < j: participants are sorted)
  sweep.resting_slowly = resting_pairs && ((primitive(a) && primitive(b)) || sweep.apart_at_start) &&
                         relative_motion_m <= max_unswept_motion_m(w.model.options, a, b) &&
                         std::binary_search(resting_pairs->begin(), resting_pairs->end(), std::make_pair(i, j));
  // Two bodies whose bounding boxes are further apart at the start than their points
  // move relative to each other cannot meet in the step (in a tumbling pile, most of
  // the pairs whose swept boxes overlap): proven without building their motions.
  const bool far_apart = !sweep.resting_slowly && collision::gap_lower_bound_m(a.shape, X_WA, b.shape, X_WB) >
                                                      relative_motion_m + curve_m + kGapRounding_m;
  sweep.swept_by_ccd = !sweep.resting_slowly && !far_apart;
}

void answer_sweep(const SweepWorld& w, PairSweep& sweep, const std::vector<int>& participants,
                  const std::vector<geometry::Pose>& next, const geometry::ScrewMotion& motion_A,
                  const geometry::ScrewMotion& motion_B) {
  const int i = participants[sweep.p], j = participants[sweep.q];
  const BodyModel& a = w.model.bodies[i];
  const BodyModel& b = w.model.bodies[j];
  const geometry::Pose& next_A = next[sweep.p];
  const geometry::Pose& next_B = next[sweep.q];
  CachedImpact& query = *sweep.query;
  collision::ContinuousOptions ccd = w.model.options.ccd;
  ccd.apart_at_start = sweep.apart_at_start;
  // Pieces that touch at the start and move too little to pass through each other are
  // checked at the end, as a resting pair is (the advancement stalls on them); their
  // bounce, if any, is solved at the next step's start (below
  // sequential_bounce_restitution, as for a bounce a solve brings about).
  if (depth_measured(a, b) && std::max(a.restitution, b.restitution) <= w.model.options.sequential_bounce_restitution)
    ccd.touching_unswept_m = w.model.options.contact_tolerance_m;
  const double start_depth_m = query.start_depth_m;  // (-1 for a pair not asked before)
  query = {true,
           next_A,
           next_B,
           sweep.swept_by_ccd ? collision::time_of_impact(a.shape, motion_A, b.shape, motion_B, ccd)
                              : collision::ContinuousResult{},
           {}};
  // A meeting elsewhere cuts or constrains the motion: then every piece pair is timed.
  if (meets_inside(query.result) && query.result.touching_unswept) {
    ccd.touching_unswept_m = 0;
    query.result = collision::time_of_impact(a.shape, motion_A, b.shape, motion_B, ccd);
  }
  const collision::ContinuousResult& r = query.result;
  const bool end_checked = sweep.resting_slowly || touching_at_start(r) || r.touching_unswept;
  query.swept = !end_checked;
  if (meets_inside(r) && r.features.kind != collision::FeaturePair::kNone) {
    // The meeting point as material points of both bodies, and A's normal there.
    const geometry::Pose X_A = motion_A.pose_at(r.time_of_impact);
    const geometry::Pose X_B = motion_B.pose_at(r.time_of_impact);
    query.hits = {{X_A.inverse() * r.point_W, X_B.inverse() * r.point_W, X_A.linear().transpose() * r.normal_W}};
  }
  if (!end_checked) return;
  // Touching or overlapping already: the CCD cannot time a meeting of surfaces that meet
  // at the start, and the contacts, linearised, let a turning body dig in. So the end of
  // the motion is checked: points deeper than
  // overlap_tolerance_m (and than the pair was at the start) become constraints of a
  // re-solve, as a CCD meeting would. (Mesh pairs: finish_sweep.)
  query.hits.clear();
  if (!depth_measured(a, b)) return;
  const double start_depth = query.start_depth_m =
      start_depth_m >= 0 ? start_depth_m : deepest_overlap(a, w.state[i].X_WB, b, w.state[j].X_WB);
  // (A tenth of the tolerance over the start depth keeps a pair that rounding deepens by
  // nanometres from being cut into ever smaller steps, in which the depenetration speed
  // can no longer undo anything.)
  const double allowed = query.allowed_depth_m =
      std::max(start_depth + 0.1 * w.model.options.overlap_tolerance_m, w.model.options.overlap_tolerance_m);
  for (const auto& point : collision::contact_manifold(a.shape, next_A, b.shape, next_B, 0.0)) {
    if (-point.distance_m <= allowed) continue;
    query.hits.push_back({next_A.inverse() * point.point_A_W, next_B.inverse() * point.point_B_W,
                          next_A.linear().transpose() * point.normal_W, -point.distance_m});
  }
  query.deepens = !query.hits.empty();
}

void finish_sweep(const SweepWorld& w, PairSweep& sweep, const std::vector<int>& participants,
                  const std::vector<geometry::Pose>& next, const geometry::ScrewMotion& motion_A,
                  const geometry::ScrewMotion& motion_B, Sweep& out) {
  const int i = participants[sweep.p], j = participants[sweep.q];
  const BodyModel& a = w.model.bodies[i];
  const BodyModel& b = w.model.bodies[j];
  CachedImpact& query = *sweep.query;
  const collision::ContinuousResult& r = query.result;
  if (sweep.swept_by_ccd) ++out.ccd_queries;
  if (depth_measured(a, b)) return;
  // Swept from apart without meeting: apart at the end (MeshCrossingMemo::apart_at_end).
  if (query.swept && !r.collides) w.memo.apart_at_end[{i, j}] = {next[sweep.p], next[sweep.q]};
  if (!sweep.resting_slowly && !touching_at_start(r)) return;
  if (r.features.kind != collision::FeaturePair::kOverlapAtStart) {
    check_mesh_crossing(w.model.options, a, motion_A, b, motion_B, sweep.relative_motion_m, query,
                        w.memo.nearby_pairs(i, j));
    if (query.free_until == 1) w.memo.apart_at_end[{i, j}] = {next[sweep.p], next[sweep.q]};
  }
  query.deepens = !query.hits.empty() || query.free_until < 1;
}

// How far each participant's points can move over its motion to `next`: its origin's
// displacement (shift), its rotation angle times its radius about the origin (turn), and
// how far the origin strays, on its screw, from moving along its shift uniformly (curve:
// the arc's sagitta and its uneven pace along the chord are both below it).
struct MotionReach {
  std::vector<Eigen::Vector3d> shift;
  std::vector<double> turn, curve;
};
MotionReach motion_reach(const SweepWorld& w, const std::vector<int>& participants,
                         const std::vector<geometry::Pose>& next) {
  MotionReach out{std::vector<Eigen::Vector3d>(participants.size()), std::vector<double>(participants.size()),
                  std::vector<double>(participants.size())};
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const geometry::Pose& X_WB = w.state[participants[s]].X_WB;
    out.shift[s] = next[s].translation() - X_WB.translation();
    const double angle = Eigen::AngleAxisd(next[s].linear() * X_WB.linear().transpose()).angle();
    out.turn[s] = angle > 0 ? angle * w.model.radius_m[participants[s]] : 0.0;
    out.curve[s] = angle > 0 ? angle * out.shift[s].norm() : 0.0;
  }
  return out;
}

}  // namespace

Eigen::AlignedBox3d swept_box(const geometry::Pose& X_WB, double radius_m, const geometry::Pose& next) {
  return collision::swept_bounds(geometry::ScrewMotion(X_WB, next), Eigen::Vector3d::Zero(), radius_m);
}

double deepest_overlap(const BodyModel& a, const geometry::Pose& X_WA, const BodyModel& b, const geometry::Pose& X_WB) {
  double deepest = 0;
  for (const auto& point : collision::contact_manifold(a.shape, X_WA, b.shape, X_WB, 0.0))
    deepest = std::max(deepest, -point.distance_m);
  return deepest;
}

double max_unswept_motion_m(const WorldOptions& options, const BodyModel& a, const BodyModel& b) {
  // Two kinds of pair keep to the contact tolerance: a mesh's, whose thinnest part is not known (a bunny's ear, a cup's
  // wall); and a bouncing one's, because what the end check finds is held, not bounced (a point that starts within the
  // tolerance is a contact row, which bounces; with motion below it, nothing from further away can reach).
  if (a.shape.type() == collision::Shape::Type::kMesh || b.shape.type() == collision::Shape::Type::kMesh ||
      std::max(a.restitution, b.restitution) > 0)
    return std::min(options.resting_unswept_motion_m, options.contact_tolerance_m);
  // A point moving less than a quarter of a body's thickness cannot pass through it: it
  // ends outside, or inside on its own side, where the end check finds it.
  const auto half_thickness_m = [](const BodyModel& body) {
    switch (body.shape.type()) {
      case collision::Shape::Type::kBox:
        return 0.5 * body.shape.size_m().minCoeff();
      case collision::Shape::Type::kSphere:
        return body.shape.radius_m();
      case collision::Shape::Type::kConvexSet:
        return body.shape.convex()->half_thickness_m;
      default:
        return std::numeric_limits<double>::infinity();
    }
  };
  return std::min(options.resting_unswept_motion_m, 0.5 * std::min(half_thickness_m(a), half_thickness_m(b)));
}

Sweep sweep_motions(const SweepWorld& w, const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                    const std::vector<BodyPair>* resting_pairs, ImpactCache* cache, ImpactMap* meeting,
                    const std::vector<BodyPair>* swept_pairs) {
  step_helpers::require_model("sweep_motions", w.model, w.state);
  step_helpers::require_participants("sweep_motions", participants, w.state.size());
  step_helpers::require_size("sweep_motions", "next", next.size(), participants.size());
  std::vector<std::pair<int, int>> own;
  if (!swept_pairs) {
    std::vector<Eigen::AlignedBox3d> swept;
    swept.reserve(participants.size());
    for (std::size_t s = 0; s < participants.size(); ++s)
      swept.push_back(swept_box(w.state[participants[s]].X_WB, w.model.radius_m[participants[s]], next[s]));
    own = collision::overlapping_pairs(swept);
  }
  const MotionReach reach = motion_reach(w, participants, next);
  const std::vector<Eigen::Vector3d>& shift = reach.shift;
  const std::vector<double>&turn = reach.turn, &curve = reach.curve;
  // Each participant's screw motion, built when a pair first needs it (a body in a pile is
  // in a dozen pairs).
  std::vector<std::optional<geometry::ScrewMotion>> motions(participants.size());
  const auto motion_of = [&](int slot) -> const geometry::ScrewMotion& {
    if (!motions[slot]) motions[slot].emplace(w.state[participants[slot]].X_WB, next[slot]);
    return *motions[slot];
  };
  // The pairs come in the cache's order: a pair's entry is usually the one after the
  // last pair's, found without a search from the root.
  ImpactCache::iterator last = cache ? cache->end() : ImpactCache::iterator();
  const auto cached = [&](int i, int j) -> CachedImpact& {
    const std::pair<int, int> key{i, j};
    ImpactCache::iterator it = last == cache->end() ? cache->begin() : std::next(last);
    if (it == cache->end() || it->first != key) {
      it = cache->lower_bound(key);
      if (it == cache->end() || it->first != key) it = cache->try_emplace(it, key);
    }
    last = it;
    return it->second;
  };
  // Three passes: which pairs need a new answer (in order: the cache and the memos), the
  // answers of depth-measured pairs and every pair's CCD (on the worker threads, each into
  // its own entry), then in order again the mesh pairs' end checks and the step's answer.
  const std::vector<std::pair<int, int>>& pairs = swept_pairs ? *swept_pairs : own;
  std::vector<PairSweep> sweeps;
  sweeps.reserve(pairs.size());
  std::vector<CachedImpact> uncached;  // the entries when there is no cache
  uncached.reserve(cache ? 0 : pairs.size());
  for (const auto& [p, q] : pairs) {
    const int i = participants[p], j = participants[q];
    const BodyModel& a = w.model.bodies[i];
    const BodyModel& b = w.model.bodies[j];
    if (!moves(a, w.state[i]) && !moves(b, w.state[j])) continue;
    if (a.shape.type() == collision::Shape::Type::kPlane && b.shape.type() == collision::Shape::Type::kPlane) continue;
    // Resting pairs barely move relative to each other: a relative motion below half
    // the resting gap cannot close it, so the CCD query is skipped (a pile of boxes is
    // almost all such pairs). The price: a pair closer than that may end up to half
    // the gap (0.5 um) inside each other.
    const double relative_motion_m = (shift[q] - shift[p]).norm() + turn[p] + turn[q];
    if (relative_motion_m < 0.5 * w.model.options.contact_gap_m) continue;
    // A re-solve changes the motions of the island it touches only; every other pair's
    // motions, and so its answer, are as in the last round.
    CachedImpact& query = cache ? cached(i, j) : uncached.emplace_back();
    PairSweep sweep{p, q, &query};
    sweep.fresh =
        !query.valid || query.next_A.matrix() != next[p].matrix() || query.next_B.matrix() != next[q].matrix();
    // A pair proven apart by a clearance that the change of both motions cannot close
    // keeps its answer: a meeting's re-solve moves every body of a pile's island a little,
    // and pairs further apart than that need no new sweep.
    if (sweep.fresh && query.valid && query.result.clearance_m > 0 &&
        motion_change_m(w, i, query.next_A, motion_of(p)) + motion_change_m(w, j, query.next_B, motion_of(q)) <
            query.result.clearance_m - kGapRounding_m)
      sweep.fresh = false;
    if (sweep.fresh) {
      classify_sweep(w, sweep, participants, relative_motion_m, curve[p] + curve[q], resting_pairs);
      motion_of(p);
      motion_of(q);
    }
    sweeps.push_back(sweep);
  }
  w.pool.for_each(static_cast<int>(sweeps.size()), [&](int k) {
    PairSweep& sweep = sweeps[k];
    if (sweep.fresh) answer_sweep(w, sweep, participants, next, *motions[sweep.p], *motions[sweep.q]);
  });
  Sweep out;
  for (PairSweep& sweep : sweeps) {
    const int i = participants[sweep.p], j = participants[sweep.q];
    CachedImpact& query = *sweep.query;
    if (sweep.fresh) finish_sweep(w, sweep, participants, next, *motions[sweep.p], *motions[sweep.q], out);
    if (query.deepens) {
      out.deepening = true;
      if (meeting) (*meeting)[{i, j}].insert((*meeting)[{i, j}].end(), query.hits.begin(), query.hits.end());
      continue;
    }
    if (!meets_inside(query.result)) continue;
    out.tau = std::min(out.tau, query.result.time_of_impact);
    if (meeting) (*meeting)[{i, j}].insert((*meeting)[{i, j}].end(), query.hits.begin(), query.hits.end());
  }
  return out;
}

}  // namespace arphys::dynamics
