// After a sweep: the lift of resting points left too deep (moving end poses), where a step
// must be cut so that no unswept pair is left deep, and what a cut carries over. The stage
// before: the sweep (step_sweep.hpp).
#include "simulator/dynamics/step_cut.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <vector>

#include "simulator/collision/shape_query.hpp"
#include "simulator/dynamics/position_projection.hpp"
#include "simulator/dynamics/step_helpers.hpp"

namespace arphys::dynamics {

using step_helpers::depth_measured;
using step_helpers::slot_of;

namespace {

// Gauss-Seidel sweeps of a projection (project_deep_points): the lifted points
// are a few dozen in a pile's round, most settled in two or three.
constexpr int kProjectionSweeps = 50;
// Rounds of a projection: lift, measure every touched pair at the lifted poses, lift the
// pairs found too deep with the rest.
constexpr int kProjectionRounds = 8;

// `fraction` of the pair's motions, halved (at most max_halvings times) until the pair
// overlaps there by no more than allowed_depth_m(fraction).
double halved_until_within(const std::vector<BodyModel>& bodies, const BodyPair& pair,
                           const geometry::ScrewMotion& motion_a, const geometry::ScrewMotion& motion_b,
                           double fraction, int max_halvings, const std::function<double(double)>& allowed_depth_m) {
  for (int halving = 0; halving < max_halvings; ++halving) {
    const double depth_m = deepest_overlap(bodies[pair.first], motion_a.pose_at(fraction), bodies[pair.second],
                                           motion_b.pose_at(fraction));
    if (depth_m <= allowed_depth_m(fraction)) break;
    fraction *= 0.5;
  }
  return fraction;
}

// The pairs a lift moves out: those ending too deep. A CCD meeting's points (end_depth_m <
// 0) are an impact, left for the re-solve, which bounces it; a mesh pair ending too deep is
// left to it too (its depth is not measured), and then so is everything (none returned).
std::set<BodyPair> pairs_to_lift(const std::vector<BodyModel>& bodies, const ImpactMap& meeting,
                                 const ImpactCache& cache) {
  std::set<BodyPair> lifted;
  for (const auto& [pair, hits] : meeting) {
    if (std::none_of(hits.begin(), hits.end(), [](const ImpactPoint& hit) { return hit.end_depth_m >= 0; })) continue;
    if (!depth_measured(bodies[pair.first], bodies[pair.second]) || !cache.count(pair)) return {};
    lifted.insert(pair);
  }
  return lifted;
}

}  // namespace

bool project_deep_points(const WorldModel& model, const std::vector<BodyState>& state,
                         const std::vector<int>& participants, std::vector<geometry::Pose>& next,
                         const ImpactMap& meeting, const ImpactCache& cache,
                         const std::vector<BodyPair>& resting_pairs) {
  step_helpers::require_model("project_deep_points", model, state);
  const std::vector<BodyModel>& bodies = model.bodies;
  step_helpers::require_size("project_deep_points", "next", next.size(), participants.size());
  std::set<BodyPair> lifted = pairs_to_lift(bodies, meeting, cache);
  if (lifted.empty()) return false;
  const double tolerance = model.options.overlap_tolerance_m;
  // How deep a pair may end: as the end check allows, the deeper of the tolerance and a
  // tenth of it over the pair's start depth (measured here, once, for a pair the check
  // skipped: one that barely moved; the start poses do not change between rounds).
  std::map<BodyPair, double> allowed_unchecked;
  const auto allowed_depth = [&](const BodyPair& pair) {
    const auto it = cache.find(pair);
    if (it != cache.end() && it->second.allowed_depth_m > 0) return it->second.allowed_depth_m;
    const auto [known, fresh] = allowed_unchecked.try_emplace(pair, 0.0);
    if (fresh) {
      const double start_depth =
          deepest_overlap(bodies[pair.first], state[pair.first].X_WB, bodies[pair.second], state[pair.second].X_WB);
      known->second = std::max(start_depth + 0.1 * tolerance, tolerance);
    }
    return known->second;
  };
  std::vector<ProjectedBody> moved;
  std::vector<int> slot_of_moved;             // participant slot of each projected body
  std::vector<int> index(bodies.size(), -1);  // body -> index in moved
  const auto body_index = [&](int body) {
    if (index[body] < 0) {
      const BodyModel& b = bodies[body];
      const int slot = slot_of(participants, body);
      ProjectedBody projected;
      projected.X_WB = next[slot];  // (a non-dynamic body's end pose, which it keeps)
      projected.center_of_mass_B = b.mass.center_of_mass_m;
      if (moves(b, state[body])) {
        projected.inverse_mass_1_kg = 1.0 / b.mass.mass_kg;
        projected.inverse_inertia_W = inverse_inertia_W(b, state[body]);
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
  // held at the resting gap instead, pairs resting within the tolerance would be pushed
  // apart too and the lift spread through a pile. Pairs that the lifts deepen beyond what they
  // may join them, round by round.
  for (int round = 0; round < kProjectionRounds; ++round) {
    std::vector<ProjectedPoint> points;
    for (const auto& pair : lifted) {
      const BodyModel& a = bodies[pair.first];
      const BodyModel& b = bodies[pair.second];
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
    std::vector<char> lifted_body(bodies.size(), 0);
    for (std::size_t k = 0; k < moved.size(); ++k)
      if (moved[k].X_WB.matrix() != next[slot_of_moved[k]].matrix()) lifted_body[participants[slot_of_moved[k]]] = 1;
    bool settled = true;
    for (const auto& pair : resting_pairs) {
      if (!(lifted_body[pair.first] || lifted_body[pair.second]) ||
          !depth_measured(bodies[pair.first], bodies[pair.second]))
        continue;
      const double allowed = allowed_depth(pair);
      for (const auto& f : collision::contact_manifold(bodies[pair.first].shape, pose_of(pair.first),
                                                       bodies[pair.second].shape, pose_of(pair.second), 0.0))
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

double unswept_clear_fraction(const WorldModel& model, const std::vector<BodyState>& state,
                              const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                              const ImpactCache& cache, double tau, double h_s) {
  step_helpers::require_model("unswept_clear_fraction", model, state);
  const std::vector<BodyModel>& bodies = model.bodies;
  step_helpers::require_size("unswept_clear_fraction", "next", next.size(), participants.size());
  // (The group's pairs only: at the step's start the cache holds every group's.)
  for (int p = 0; p < static_cast<int>(participants.size()) && tau > 0; ++p)
    for (auto it = cache.lower_bound({participants[p], -1}); it != cache.end() && it->first.first == participants[p];
         ++it) {
      const auto& [pair, query] = *it;
      if (!query.valid || query.swept || !depth_measured(bodies[pair.first], bodies[pair.second])) continue;
      const int q = slot_of(participants, pair.second);
      if (q < 0) continue;  // another group's pair
      if (query.next_A.matrix() != next[p].matrix() || query.next_B.matrix() != next[q].matrix()) continue;
      const geometry::ScrewMotion motion_a(state[pair.first].X_WB, next[p]), motion_b(state[pair.second].X_WB, next[q]);
      // (Twelve halvings: a pair that moved a centimetre is then within 3 um of its start.)
      const double allowed_m = query.allowed_depth_m;
      tau = halved_until_within(bodies, pair, motion_a, motion_b, tau, 12, [&](double fraction) {
        // What the rest of the step undoes (at half the depenetration speed) may be left:
        // halving to the end check's micrometre made cut after cut, to the event cap.
        return std::max(allowed_m, 0.5 * model.options.max_depenetration_speed_m_s * h_s * (1 - fraction));
      });
    }
  return tau;
}

double shallow_fraction(const WorldModel& model, const std::vector<BodyState>& state,
                        const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                        const ImpactCache& cache, const ImpactMap& meeting) {
  step_helpers::require_model("shallow_fraction", model, state);
  step_helpers::require_size("shallow_fraction", "next", next.size(), participants.size());
  double fraction = 1.0;
  // (In the pairs' order, as the cache holds them: each pair halves from where the last
  // one left the fraction.)
  for (const auto& entry : meeting) {
    const BodyPair& pair = entry.first;
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
    const geometry::ScrewMotion motion_a(state[pair.first].X_WB, next[p]), motion_b(state[pair.second].X_WB, next[q]);
    fraction = halved_until_within(model.bodies, pair, motion_a, motion_b, fraction, 6,
                                   [&](double) { return query.allowed_depth_m; });
  }
  return fraction;
}

std::vector<char> keep_motions(const WorldModel& model, const std::vector<BodyState>& state,
                               const std::vector<int>& participants, const std::vector<BodyVelocity>& u_before,
                               const std::vector<geometry::Pose>& next_before, const std::vector<BodyVelocity>& u,
                               std::vector<geometry::Pose>& next) {
  step_helpers::require_model("keep_motions", model, state);
  step_helpers::require_size("keep_motions", "u_before", u_before.size(), participants.size());
  step_helpers::require_size("keep_motions", "next_before", next_before.size(), participants.size());
  step_helpers::require_size("keep_motions", "u", u.size(), participants.size());
  step_helpers::require_size("keep_motions", "next", next.size(), participants.size());
  std::vector<char> kept(participants.size(), 0);
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const BodyModel& body = model.bodies[participants[s]];
    const bool dynamic = moves(body, state[participants[s]]);
    if (!dynamic && body.motion != BodyMotion::kKinematic) {  // (static, or a sleeper held fixed)
      kept[s] = 1;
    } else if (dynamic && u[s].v_WBcm_m_s == u_before[s].v_WBcm_m_s && u[s].w_WB_rad_s == u_before[s].w_WB_rad_s) {
      // Exactly: a pair a thousandth of the overlap tolerance too deep is corrected by a
      // velocity change of that size, which a looser test would keep undone, round after
      // round.
      kept[s] = 1;
      next[s] = next_before[s];
    }
  }
  return kept;
}

ImpactCache carry_over_cut(const WorldModel& model, const std::vector<BodyState>& state,
                           const std::vector<int>& participants, const std::vector<BodyVelocity>& u,
                           std::vector<geometry::Pose>& next, Cut& cut) {
  // A dynamic body the solve after a cut left as it was goes on along the same screw
  // motion (integrate's constant twist): its end pose is the one before the cut, and a
  // pair of such bodies (or of one and a static body) moves over the rest of the step
  // as it did over that part of the motion. Its CCD answer carries over, its time
  // rescaled. (Queried afresh after every cut, a spawn of 100 bunnies made 8,000 mesh
  // queries per step.)
  const std::vector<char> goes_on = keep_motions(model, state, participants, cut.u, cut.next, u, next);
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
