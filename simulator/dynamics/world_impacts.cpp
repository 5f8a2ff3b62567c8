// Sweeping a step's motions: the CCD of every pair whose swept boxes meet, the check at
// the end of a resting pair's motion, the lift of resting points left too deep, and where
// a step must be cut. The stages before: the contacts and the solve (step_contacts.hpp,
// step_solve.hpp).
#include "simulator/dynamics/world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "simulator/collision/broad_phase.hpp"
#include "simulator/collision/separation_certificate.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/dynamics/manifold_reduction.hpp"
#include "simulator/dynamics/position_projection.hpp"
#include "simulator/dynamics/world_internal.hpp"

namespace arphys::dynamics {

using world_internal::depth_measured;
using world_internal::meets_inside;
using world_internal::slot_of;

namespace {

// Rounding allowance of a gap between boxes computed from metre-sized coordinates.
constexpr double kGapRounding_m = 1e-9;
// Gauss-Seidel sweeps of a projection (World::project_deep_points): the lifted points
// are a few dozen in a pile's round, most settled in two or three.
constexpr int kProjectionSweeps = 50;
// Rounds of a projection: lift, measure every touched pair at the lifted poses, lift the
// pairs found too deep with the rest.
constexpr int kProjectionRounds = 8;

// The CCD says the pair already touches (or overlaps) at the start: it cannot time anything after.
bool touching_at_start(const collision::ContinuousResult& r) {
  return r.collides && !meets_inside(r);
}

}  // namespace

Eigen::AlignedBox3d World::swept_box(int body, const geometry::Pose& next) const {
  return collision::swept_bounds(geometry::ScrewMotion(bodies_[body].X_WB, next), Eigen::Vector3d::Zero(), radius_m_[body]);
}

double World::earliest_impact(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                              const std::vector<std::pair<int, int>>* resting_pairs, ImpactMap* meeting,
                              ImpactCache* cache, bool* deepening, StepReport& report,
                              const std::vector<std::pair<int, int>>* swept_pairs) {
  std::vector<std::pair<int, int>> own;
  if (!swept_pairs) {
    std::vector<Eigen::AlignedBox3d> swept;
    swept.reserve(participants.size());
    for (std::size_t s = 0; s < participants.size(); ++s) swept.push_back(swept_box(participants[s], next[s]));
    own = collision::overlapping_pairs(swept);
  }
  // How far each body's points can move over the step: its origin's displacement and
  // its rotation angle times its radius about the origin.
  std::vector<Eigen::Vector3d> shift(participants.size());
  std::vector<double> turn(participants.size()), curve(participants.size());
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const RigidBody& body = bodies_[participants[s]];
    shift[s] = next[s].translation() - body.X_WB.translation();
    const double angle = Eigen::AngleAxisd(next[s].linear() * body.X_WB.linear().transpose()).angle();
    turn[s] = angle > 0 ? angle * radius_m_[participants[s]] : 0.0;
    // On its screw the origin strays from moving along its shift uniformly by less than
    // this (the arc's sagitta, and its uneven pace along the chord, are both below it).
    curve[s] = angle > 0 ? angle * shift[s].norm() : 0.0;
  }
  // Each participant's screw motion, built when a pair first needs it (a body in a pile
  // is in a dozen pairs: built per pair, they were 7 % of its time).
  std::vector<std::optional<geometry::ScrewMotion>> motions(participants.size());
  const auto motion_of = [&](int slot) -> const geometry::ScrewMotion& {
    if (!motions[slot]) motions[slot].emplace(bodies_[participants[slot]].X_WB, next[slot]);
    return *motions[slot];
  };
  // The pairs come in the cache's order: a pair's entry is usually the one after the
  // last pair's (looked up from the root each time, the tree's pointer chase was a
  // third of this function's own time in a 1000-box pile).
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
    const RigidBody& a = bodies_[i];
    const RigidBody& b = bodies_[j];
    if (!a.is_dynamic() && !b.is_dynamic()) continue;
    if (a.shape.type() == collision::Shape::Type::kPlane && b.shape.type() == collision::Shape::Type::kPlane) continue;
    // Resting pairs barely move relative to each other: a relative motion below half
    // the resting gap cannot close it, so the CCD query is skipped (a pile of boxes is
    // almost all such pairs). The price: a pair closer than that may end up to half
    // the gap (0.5 um) inside each other.
    const double relative_motion_m = (shift[q] - shift[p]).norm() + turn[p] + turn[q];
    if (relative_motion_m < 0.5 * options_.contact_gap_m) continue;
    // A re-solve changes the motions of the island it touches only; every other pair's
    // motions, and so its answer, are as in the last round.
    CachedImpact& query = cache ? cached(i, j) : uncached.emplace_back();
    PairSweep sweep{p, q, &query};
    sweep.fresh = !query.valid || query.next_A.matrix() != next[p].matrix() || query.next_B.matrix() != next[q].matrix();
    // A pair proven apart by a clearance that the change of both motions cannot close
    // keeps its answer: a meeting's re-solve moves every body of a pile's island a little,
    // and pairs further apart than that need no new sweep.
    if (sweep.fresh && query.valid && query.result.clearance_m > 0 &&
        motion_change_m(i, query.next_A, motion_of(p)) + motion_change_m(j, query.next_B, motion_of(q)) <
            query.result.clearance_m - kGapRounding_m)
      sweep.fresh = false;
    if (sweep.fresh) {
      classify_sweep(sweep, participants, relative_motion_m, curve[p] + curve[q], resting_pairs);
      motion_of(p);
      motion_of(q);
    }
    sweeps.push_back(sweep);
  }
  pool_.for_each(static_cast<int>(sweeps.size()), [&](int k) {
    PairSweep& sweep = sweeps[k];
    if (sweep.fresh) answer_sweep(sweep, participants, next, *motions[sweep.p], *motions[sweep.q]);
  });
  double earliest = 1.0;
  for (PairSweep& sweep : sweeps) {
    const int i = participants[sweep.p], j = participants[sweep.q];
    CachedImpact& query = *sweep.query;
    if (sweep.fresh) finish_sweep(sweep, participants, next, *motions[sweep.p], *motions[sweep.q], report);
    if (query.deepens) {
      if (deepening) *deepening = true;
      if (meeting) (*meeting)[{i, j}].insert((*meeting)[{i, j}].end(), query.hits.begin(), query.hits.end());
      continue;
    }
    if (!meets_inside(query.result)) continue;
    earliest = std::min(earliest, query.result.time_of_impact);
    if (meeting) (*meeting)[{i, j}].insert((*meeting)[{i, j}].end(), query.hits.begin(), query.hits.end());
  }
  return earliest;
}

void World::classify_sweep(PairSweep& sweep, const std::vector<int>& participants, double relative_motion_m,
                           double curve_m, const std::vector<std::pair<int, int>>* resting_pairs) const {
  const int i = participants[sweep.p], j = participants[sweep.q];
  const RigidBody& a = bodies_[i];
  const RigidBody& b = bodies_[j];
  sweep.relative_motion_m = relative_motion_m;
  // A resting pair (constraints of the step already) whose points move less than
  // max_unswept_motion_m relative to each other is held by its contacts, and its motion
  // checked at the end like a touching pair's: a point that ends outside the other
  // body and moved less than that can have been at most half of it inside in between
  // (a box clipping another's corner), which matters only where the step is cut
  // mid-motion (unswept_clear_fraction). The CCD of such
  // pairs (surfaces 1 um apart, edges nearly parallel) took thousands of search nodes
  // and cut steps at times of impact of 1e-6: most of a 1000-box pile's step.
  // Primitives are checked by their contact manifolds, which measure depth exactly. A
  // mesh pair (a mesh's manifold can miss a vertex that went in: a bunny dropped 2 cm
  // onto a table then sank 0.6 mm) is checked by whether its surfaces cross at the end
  // (check_mesh_crossing), so only when the contact pass found them apart at these
  // start poses: in a pile of 16 resting bunnies the CCD of such pairs, 250-400 queries
  // a frame, was 40 % of the live simulator's time and put it seconds behind the camera.
  const auto primitive = [](const RigidBody& body) { return body.shape.type() != collision::Shape::Type::kMesh; };
  sweep.apart_at_start =
      MeshCrossingMemo::known_apart(mesh_memo_.apart_at, i, j, a.X_WB, b.X_WB);  // (i < j: participants are sorted)
  sweep.resting_slowly = resting_pairs && ((primitive(a) && primitive(b)) || sweep.apart_at_start) &&
                         relative_motion_m <= max_unswept_motion_m(a, b) &&
                         std::binary_search(resting_pairs->begin(), resting_pairs->end(), std::make_pair(i, j));
  // Two bodies whose bounding boxes are further apart at the start than their points
  // move relative to each other cannot meet in the step (in a tumbling pile, most of
  // the pairs whose swept boxes overlap): proven without building their motions.
  const bool far_apart = !sweep.resting_slowly && collision::gap_lower_bound_m(a.shape, a.X_WB, b.shape, b.X_WB) >
                                                      relative_motion_m + curve_m + kGapRounding_m;
  sweep.swept_by_ccd = !sweep.resting_slowly && !far_apart;
}

void World::answer_sweep(PairSweep& sweep, const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                         const geometry::ScrewMotion& motion_A, const geometry::ScrewMotion& motion_B) const {
  const RigidBody& a = bodies_[participants[sweep.p]];
  const RigidBody& b = bodies_[participants[sweep.q]];
  const geometry::Pose& next_A = next[sweep.p];
  const geometry::Pose& next_B = next[sweep.q];
  CachedImpact& query = *sweep.query;
  collision::ContinuousOptions ccd = options_.ccd;
  ccd.apart_at_start = sweep.apart_at_start;
  // Pieces that touch at the start and move too little to pass through each other are
  // checked at the end, as a resting pair is; their bounce, if any, is solved at the next
  // step's start (below sequential_bounce_restitution, as for a bounce a solve brings
  // about). The sweep stalls on such pairs: in a tumbling pile they were most of its cost.
  if (depth_measured(a, b) && std::max(a.restitution, b.restitution) <= options_.sequential_bounce_restitution)
    ccd.touching_unswept_m = options_.contact_tolerance_m;
  const double start_depth_m = query.start_depth_m;  // (-1 for a pair not asked before)
  query = {true, next_A, next_B,
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
  // at the start, and the contacts, linearised, let a turning body dig in (1e-5 m in a
  // pile of 1000 boxes). So the end of the motion is checked: points deeper than
  // overlap_tolerance_m (and than the pair was at the start) become constraints of a
  // re-solve, as a CCD meeting would. (Mesh pairs: finish_sweep.)
  query.hits.clear();
  if (!depth_measured(a, b)) return;
  const double start_depth = query.start_depth_m =
      start_depth_m >= 0 ? start_depth_m
                         : deepest_overlap(participants[sweep.p], a.X_WB, participants[sweep.q], b.X_WB);
  // (A tenth of the tolerance over the start depth keeps a pair that rounding deepens by
  // nanometres from being cut into ever smaller steps, in which the depenetration speed
  // can no longer undo anything.)
  const double allowed = query.allowed_depth_m =
      std::max(start_depth + 0.1 * options_.overlap_tolerance_m, options_.overlap_tolerance_m);
  for (const auto& point : collision::contact_manifold(a.shape, next_A, b.shape, next_B, 0.0)) {
    if (-point.distance_m <= allowed) continue;
    query.hits.push_back({next_A.inverse() * point.point_A_W, next_B.inverse() * point.point_B_W,
                          next_A.linear().transpose() * point.normal_W, -point.distance_m});
  }
  query.deepens = !query.hits.empty();
}

void World::finish_sweep(PairSweep& sweep, const std::vector<int>& participants,
                         const std::vector<geometry::Pose>& next, const geometry::ScrewMotion& motion_A,
                         const geometry::ScrewMotion& motion_B, StepReport& report) {
  const int i = participants[sweep.p], j = participants[sweep.q];
  const RigidBody& a = bodies_[i];
  const RigidBody& b = bodies_[j];
  CachedImpact& query = *sweep.query;
  const collision::ContinuousResult& r = query.result;
  if (sweep.swept_by_ccd) ++report.ccd_queries;
  if (depth_measured(a, b)) return;
  // Swept from apart without meeting: apart at the end (MeshCrossingMemo::apart_at_end).
  if (query.swept && !r.collides) mesh_memo_.apart_at_end[{i, j}] = {next[sweep.p], next[sweep.q]};
  if (!sweep.resting_slowly && !touching_at_start(r)) return;
  if (r.features.kind != collision::FeaturePair::kOverlapAtStart) {
    check_mesh_crossing(a, motion_A, b, motion_B, sweep.relative_motion_m, query, mesh_memo_.nearby_pairs(i, j));
    if (query.free_until == 1) mesh_memo_.apart_at_end[{i, j}] = {next[sweep.p], next[sweep.q]};
  }
  query.deepens = !query.hits.empty() || query.free_until < 1;
}

double World::motion_change_m(int body, const geometry::Pose& swept_to, const geometry::ScrewMotion& now) const {
  if (swept_to.matrix() == now.end().matrix()) return 0;
  return geometry::motion_change_bound_m(geometry::ScrewMotion(bodies_[body].X_WB, swept_to), now, radius_m_[body]);
}

double World::deepest_overlap(int a, const geometry::Pose& X_WA, int b, const geometry::Pose& X_WB) const {
  double deepest = 0;
  for (const auto& point : collision::contact_manifold(bodies_[a].shape, X_WA, bodies_[b].shape, X_WB, 0.0))
    deepest = std::max(deepest, -point.distance_m);
  return deepest;
}

void World::check_mesh_crossing(const RigidBody& a, const geometry::ScrewMotion& motion_a, const RigidBody& b,
                                const geometry::ScrewMotion& motion_b, double relative_motion_m,
                                CachedImpact& query, collision::NearbyTrianglePairs* nearby) const {
  // A mesh's manifold cannot say how deep a point went (a scanned bunny has no inside:
  // its distances are unsigned), and the CCD, touching at the start, times nothing after
  // it. Whether the surfaces cross it can say. If they do at the end, the last fraction
  // of the motion where they do not is bisected, and the features that touch there
  // become constraints of a re-solve, as a CCD meeting's would; if they still cross, the
  // step is cut there (shallow_fraction). (Unchecked, a pair of resting bunnies rolled
  // into each other by 5 mm over ten steps: new features met as they turned.)
  // No crossing is allowed, not even a tolerated micrometre as for primitives: a pair left
  // crossing starts its next motion overlapping, where neither the CCD nor this can follow
  // it (tried: measuring and allowing crossings along the touching normal, pairs crept
  // 300 um deep cut by cut).
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
  const double reach_m = options_.contact_gap_m + relative_motion_m * (crossing - free);
  for (const auto& point :
       reduce_manifold(collision::contact_manifold(a.shape, X_A, b.shape, X_B, reach_m, nearby), options_.max_contacts_per_pair))
    query.hits.push_back({X_A.inverse() * point.point_A_W, X_B.inverse() * point.point_B_W,
                          X_A.linear().transpose() * point.normal_W});
}

bool World::project_deep_points(const std::vector<int>& participants, std::vector<geometry::Pose>& next,
                                const ImpactMap& meeting, const ImpactCache& cache,
                                const std::vector<std::pair<int, int>>& resting_pairs) const {
  // The pairs to lift: those ending too deep. A CCD meeting's points (end_depth_m < 0) are
  // an impact, left for the re-solve, which bounces it; a mesh pair ending too deep is
  // left to it too (its depth is not measured), and then so is everything.
  std::set<std::pair<int, int>> lifted;
  for (const auto& [pair, hits] : meeting) {
    if (std::none_of(hits.begin(), hits.end(), [](const ImpactPoint& hit) { return hit.end_depth_m >= 0; })) continue;
    if (!depth_measured(bodies_[pair.first], bodies_[pair.second]) || !cache.count(pair)) return false;
    lifted.insert(pair);
  }
  if (lifted.empty()) return false;
  const double tolerance = options_.overlap_tolerance_m;
  // How deep a pair may end: as the end check allows, the deeper of the tolerance and a
  // tenth of it over the pair's start depth (measured here, once, for a pair the check
  // skipped: one that barely moved; the start poses do not change between rounds).
  std::map<std::pair<int, int>, double> allowed_unchecked;
  const auto allowed_depth = [&](const std::pair<int, int>& pair) {
    const auto it = cache.find(pair);
    if (it != cache.end() && it->second.allowed_depth_m > 0) return it->second.allowed_depth_m;
    const auto [known, fresh] = allowed_unchecked.try_emplace(pair, 0.0);
    if (fresh) {
      const double start_depth =
          deepest_overlap(pair.first, bodies_[pair.first].X_WB, pair.second, bodies_[pair.second].X_WB);
      known->second = std::max(start_depth + 0.1 * tolerance, tolerance);
    }
    return known->second;
  };
  std::vector<ProjectedBody> moved;
  std::vector<int> slot_of_moved;                       // participant slot of each projected body
  std::vector<int> index(bodies_.size(), -1);           // body -> index in moved
  const auto body_index = [&](int body) {
    if (index[body] < 0) {
      const RigidBody& b = bodies_[body];
      const int slot = slot_of(participants, body);
      ProjectedBody projected;
      projected.X_WB = next[slot];  // (a non-dynamic body's end pose, which it keeps)
      projected.center_of_mass_B = b.mass.center_of_mass_m;
      if (b.is_dynamic()) {
        projected.inverse_mass_1_kg = 1.0 / b.mass.mass_kg;
        projected.inverse_inertia_W = b.inverse_inertia_W();
      }
      index[body] = static_cast<int>(moved.size());
      moved.push_back(projected);
      slot_of_moved.push_back(slot);
    }
    return index[body];
  };
  const auto pose_of = [&](int body) { return moved[body_index(body)].X_WB; };
  // Every point of a lifted pair within a few tolerances (lifting a box's deepest corner
  // turns it onto its others) is held at half a tolerance under what the pair may end at:
  // held at the resting gap instead, pairs resting within the tolerance were pushed apart
  // too and the lift spread through a pile. Pairs that the lifts deepen beyond what they
  // may join them, round by round.
  for (int round = 0; round < kProjectionRounds; ++round) {
    std::vector<ProjectedPoint> points;
    for (const auto& pair : lifted) {
      const RigidBody& a = bodies_[pair.first];
      const RigidBody& b = bodies_[pair.second];
      const geometry::Pose X_A = pose_of(pair.first), X_B = pose_of(pair.second);
      const double allowed = allowed_depth(pair);
      const double target = allowed - 0.5 * tolerance;
      for (const auto& f : collision::contact_manifold(a.shape, X_A, b.shape, X_B, 4 * tolerance))
        points.push_back({body_index(pair.first), body_index(pair.second), X_A.inverse() * f.point_A_W,
                          X_B.inverse() * f.point_B_W, X_A.linear().transpose() * f.normal_W, target});
    }
    // A quarter of the tolerance over the targets: the pairs are measured again below.
    if (!project_points(moved, points, 0.25 * tolerance, kProjectionSweeps).converged) return false;
    // Every resting pair of a body the lifts moved, measured at the lifted poses. (Which
    // bodies moved is settled once per round: the group's resting pairs are thousands in
    // a pile, and a pose comparison per pair was most of a lift's own time.)
    std::vector<char> lifted_body(bodies_.size(), 0);
    for (std::size_t k = 0; k < moved.size(); ++k)
      if (moved[k].X_WB.matrix() != next[slot_of_moved[k]].matrix()) lifted_body[participants[slot_of_moved[k]]] = 1;
    bool settled = true;
    for (const auto& pair : resting_pairs) {
      if (!(lifted_body[pair.first] || lifted_body[pair.second]) ||
          !depth_measured(bodies_[pair.first], bodies_[pair.second]))
        continue;
      const double allowed = allowed_depth(pair);
      for (const auto& f : collision::contact_manifold(bodies_[pair.first].shape, pose_of(pair.first),
                                                       bodies_[pair.second].shape, pose_of(pair.second), 0.0))
        if (-f.distance_m > allowed) {
          settled = false;
          lifted.insert(pair);
          break;
        }
    }
    if (settled) {
      for (std::size_t k = 0; k < moved.size(); ++k)
        if (moved[k].inverse_mass_1_kg > 0) next[slot_of_moved[k]] = moved[k].X_WB;
      return true;
    }
  }
  return false;
}

double World::max_unswept_motion_m(const RigidBody& a, const RigidBody& b) const {
  // Two kinds of pair keep to the contact tolerance, as before the two were separate
  // options: a mesh's, whose thinnest part is not known (a bunny's ear, a cup's wall); and
  // a bouncing one's, because what the end check finds is held, not bounced (a point that
  // starts within the tolerance is a contact row, which bounces; with motion below it,
  // nothing from further away can reach).
  if (a.shape.type() == collision::Shape::Type::kMesh || b.shape.type() == collision::Shape::Type::kMesh ||
      std::max(a.restitution, b.restitution) > 0)
    return std::min(options_.resting_unswept_motion_m, options_.contact_tolerance_m);
  // A point moving less than a quarter of a body's thickness cannot pass through it: it
  // ends outside, or inside on its own side, where the end check finds it.
  const auto half_thickness_m = [](const RigidBody& body) {
    switch (body.shape.type()) {
      case collision::Shape::Type::kBox: return 0.5 * body.shape.size_m().minCoeff();
      case collision::Shape::Type::kSphere: return body.shape.radius_m();
      case collision::Shape::Type::kConvexSet: return body.shape.convex()->half_thickness_m;
      default: return std::numeric_limits<double>::infinity();
    }
  };
  return std::min(options_.resting_unswept_motion_m, 0.5 * std::min(half_thickness_m(a), half_thickness_m(b)));
}

double World::unswept_clear_fraction(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                                     const ImpactCache& cache, double tau, double h_s) const {
  // (The group's pairs only: at the step's start the cache holds every group's.)
  for (int p = 0; p < static_cast<int>(participants.size()) && tau > 0; ++p)
    for (auto it = cache.lower_bound({participants[p], -1}); it != cache.end() && it->first.first == participants[p]; ++it) {
      const auto& [pair, query] = *it;
      if (!query.valid || query.swept || !depth_measured(bodies_[pair.first], bodies_[pair.second])) continue;
      const int q = slot_of(participants, pair.second);
      if (q < 0) continue;  // another group's pair
      if (query.next_A.matrix() != next[p].matrix() || query.next_B.matrix() != next[q].matrix()) continue;
      const geometry::ScrewMotion motion_a(bodies_[pair.first].X_WB, next[p]), motion_b(bodies_[pair.second].X_WB, next[q]);
      // (Twelve halvings: a pair that moved a centimetre is then within 3 um of its start.)
      const double allowed_m = query.allowed_depth_m;
      tau = halved_until_within(pair, motion_a, motion_b, tau, 12, [&](double fraction) {
        // What the rest of the step undoes (at half the depenetration speed) may be left:
        // halving to the end check's micrometre made cut after cut, to the event cap.
        return std::max(allowed_m, 0.5 * options_.max_depenetration_speed_m_s * h_s * (1 - fraction));
      });
    }
  return tau;
}

double World::halved_until_within(const std::pair<int, int>& pair, const geometry::ScrewMotion& motion_a,
                                  const geometry::ScrewMotion& motion_b, double fraction, int max_halvings,
                                  const std::function<double(double)>& allowed_depth_m) const {
  for (int halving = 0; halving < max_halvings; ++halving) {
    const double depth_m = deepest_overlap(pair.first, motion_a.pose_at(fraction), pair.second, motion_b.pose_at(fraction));
    if (depth_m <= allowed_depth_m(fraction)) break;
    fraction *= 0.5;
  }
  return fraction;
}

double World::shallow_fraction(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                               const ImpactCache& cache, const ImpactMap& meeting) const {
  double fraction = 1.0;
  // (In the pairs' order, as the cache holds them: each pair halves from where the last
  // one left the fraction.)
  for (const auto& entry : meeting) {
    const std::pair<int, int>& pair = entry.first;
    const auto found = cache.find(pair);
    if (found == cache.end()) continue;
    const CachedImpact& query = found->second;
    if (!query.valid || !query.deepens) continue;
    const int p = slot_of(participants, pair.first), q = slot_of(participants, pair.second);
    if (p < 0 || q < 0) continue;  // another group's pair
    if (query.next_A.matrix() != next[p].matrix() || query.next_B.matrix() != next[q].matrix()) continue;
    if (query.free_until < 1) {
      fraction = std::min(fraction, query.free_until);  // a mesh pair: where its surfaces last did not cross
      continue;
    }
    const geometry::ScrewMotion motion_a(bodies_[pair.first].X_WB, next[p]), motion_b(bodies_[pair.second].X_WB, next[q]);
    fraction = halved_until_within(pair, motion_a, motion_b, fraction, 6, [&](double) { return query.allowed_depth_m; });
  }
  return fraction;
}

std::vector<char> World::keep_motions(const std::vector<int>& participants, const std::vector<BodyVelocity>& u_before,
                                      const std::vector<geometry::Pose>& next_before,
                                      const std::vector<BodyVelocity>& u, std::vector<geometry::Pose>& next) const {
  std::vector<char> kept(participants.size(), 0);
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const RigidBody& body = bodies_[participants[s]];
    if (body.motion == BodyMotion::kStatic) {
      kept[s] = 1;
    } else if (body.is_dynamic() && u[s].v_WBcm_m_s == u_before[s].v_WBcm_m_s && u[s].w_WB_rad_s == u_before[s].w_WB_rad_s) {
      // Exactly: a pair a thousandth of the overlap tolerance too deep is corrected by a
      // velocity change of that size (keeping motions that changed by less than 1 nm, such
      // pairs stayed deep round after round: the 100-bunny spawn took 1.9 s per step).
      kept[s] = 1;
      next[s] = next_before[s];
    }
  }
  return kept;
}

World::ImpactCache World::carry_over_cut(const std::vector<int>& participants, const std::vector<BodyVelocity>& u,
                                         std::vector<geometry::Pose>& next, Cut& cut) const {
  // A dynamic body the solve after a cut left as it was goes on along the same screw
  // motion (integrate's constant twist): its end pose is the one before the cut, and a
  // pair of such bodies (or of one and a static body) moves over the rest of the step
  // as it did over that part of the motion. Its CCD answer carries over, its time
  // rescaled. (Queried afresh after every cut, a spawn of 100 bunnies made 8,000 mesh
  // queries per step.)
  const std::vector<char> goes_on = keep_motions(participants, cut.u, cut.next, u, next);
  for (auto it = cut.answers.begin(); it != cut.answers.end();) {
    const int a = slot_of(participants, it->first.first), b = slot_of(participants, it->first.second);
    CachedImpact& query = it->second;
    // Only answers for the motion the cut was made in, that timed it and met nothing
    // until well after the cut.
    bool keep = goes_on[a] && goes_on[b] && query.valid && query.swept &&
                query.next_A.matrix() == cut.next[a].matrix() && query.next_B.matrix() == cut.next[b].matrix() &&
                (!query.result.collides || query.result.time_of_impact > cut.tau + 1e-9);
    if (keep && query.result.collides)
      query.result.time_of_impact = (query.result.time_of_impact - cut.tau) / (1 - cut.tau);
    query.start_depth_m = -1;  // (the cut moved the start poses)
    it = keep ? std::next(it) : cut.answers.erase(it);
  }
  return std::move(cut.answers);
}

}  // namespace arphys::dynamics
