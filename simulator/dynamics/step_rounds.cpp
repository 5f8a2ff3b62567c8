// The rounds of a part of a step: sweep, lift or re-solve, until nothing meets or a cut.
#include "simulator/dynamics/step_rounds.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "simulator/collision/broad_phase.hpp"
#include "simulator/dynamics/step_commit.hpp"
#include "simulator/dynamics/step_cut.hpp"
#include "simulator/dynamics/step_helpers.hpp"

namespace arphys::dynamics {

using step_helpers::slot_of;

namespace {

// Projections before a part of a step falls back to re-solving its deep points.
constexpr int kMaxProjectionsPerMotion = 4;
// Re-solves of a part before it is cut at what still meets: a cut costs a new part (its
// contacts, a solve and a sweep), more than a round.
constexpr int kMaxResolveRounds = 5;

// Where the last round stops a motion that still meets or digs in (tau: the earliest
// meeting; deepening: a touching pair ends too deep).
double last_round_fraction(const RoundsWorld& w, const std::vector<int>& participants,
                           const std::vector<geometry::Pose>& next, const ImpactCache& cache, const ImpactMap& meeting,
                           double tau, bool deepening, bool cut_at_start) {
  // Linearised constraints still let a touching pair dig in: stop where it is no deeper
  // than allowed (halving: the linearisation's error shrinks with the square). Unless that
  // is a cut of nothing again (a mesh pair crossing at once) while a tracked body moves:
  // the group's step would end there and the tracked body move on into it. The motion goes
  // on instead; the pair crosses by what this motion dips it and is pushed apart in the
  // next step. With nothing tracked moving, waiting costs only time.
  if (!deepening) return tau;
  const double shallow = shallow_fraction(w.sweep.model, w.sweep.state, participants, next, cache, meeting);
  const bool would_wait = shallow == 0 && cut_at_start;
  const auto tracked_moving = [&] {
    return std::any_of(participants.begin(), participants.end(), [&](int i) {
      const BodyState& now = w.sweep.state[i];
      return w.sweep.model.bodies[i].motion == BodyMotion::kKinematic &&
             (now.v_WBcm_m_s.squaredNorm() > 0 || now.w_WB_rad_s.squaredNorm() > 0);
    });
  };
  if (!would_wait || !tracked_moving()) return std::min(tau, shallow);
  return tau;
}

// Adds the meetings' points to `impacts`, each with the normal velocity that lifts it out
// of where the motion leaves it; a bounce the solve brought about below
// sequential_bounce_restitution is held back to the next step
// (RoundsWorld::held_back_bounces). True when one is to be met in turn (the part is cut at it).
bool add_impact_points(const RoundsWorld& w, const std::vector<int>& participants, const PartMotion& motion,
                       const PartSolve& part, ImpactMap& meeting, ImpactMap& impacts) {
  // A point's velocity in the motion that let it in.
  const auto velocity = [&](int body, const Eigen::Vector3d& p_W) -> Eigen::Vector3d {
    const BodyModel& b = w.sweep.model.bodies[body];
    const BodyState& now = w.sweep.state[body];
    if (!moves(b, now)) return velocity_of_point(b, now, p_W);
    const int slot = slot_of(participants, body);
    return motion.u[slot].v_WBcm_m_s + motion.u[slot].w_WB_rad_s.cross(p_W - com_W(b, now));
  };
  bool chained = false;
  for (auto& [pair, hits] : meeting) {
    const geometry::Pose& X_A_end = motion.next[slot_of(participants, pair.first)];
    const geometry::Pose& X_B_end = motion.next[slot_of(participants, pair.second)];
    const BodyModel& body_a = w.sweep.model.bodies[pair.first];
    const BodyModel& body_b = w.sweep.model.bodies[pair.second];
    const BodyState& state_a = w.sweep.state[pair.first];
    const BodyState& state_b = w.sweep.state[pair.second];
    for (ImpactPoint& hit : hits) {
      // How deep the point ends the motion: a touching pair's as measured, a CCD meeting's
      // material points along A's normal there (the row's linearised bound misses it by
      // the turn's second-order term, so the bound is a Newton step on the true depth).
      const double end_depth_m =
          hit.end_depth_m >= 0
              ? hit.end_depth_m
              : (X_A_end.linear() * hit.normal_A_B).dot(X_A_end * hit.point_A_B - X_B_end * hit.point_B_B);
      const Eigen::Vector3d p_A = state_a.X_WB * hit.point_A_B, p_B = state_b.X_WB * hit.point_B_B;
      const Eigen::Vector3d n = state_a.X_WB.linear() * hit.normal_A_B;
      // At the midpoint, as the constraint row measures it (the two material points can be
      // millimetres apart along the surface at the start of a sliding step).
      const Eigen::Vector3d m = 0.5 * (p_A + p_B);
      const double v_n = n.dot(velocity(pair.second, m) - velocity(pair.first, m));
      hit.min_normal_velocity_m_s = v_n + (end_depth_m + w.sweep.model.options.contact_gap_m) / part.h;
      // A bouncing meeting this step's solve brought about (a ball struck by another within
      // the step, which then strikes a third): the row's bounce comes from the velocities
      // at the step's start, which do not have it, and solved with the first impact at once
      // it would share the momentum out. Only where the bounce missed is itself one
      // (restitution times the approach the solve added, beyond gravity's over the step).
      if (hit.end_depth_m >= 0 || v_n >= -w.sweep.model.options.restitution_threshold_m_s) continue;
      const double restitution = std::max(body_a.restitution, body_b.restitution);
      const double v_n_start = n.dot(velocity_of_point(body_b, state_b, m) - velocity_of_point(body_a, state_a, m));
      const double missed_bounce_m_s =
          restitution * (std::abs(v_n - v_n_start) - w.sweep.model.options.gravity_m_s2.norm() * part.force_h);
      if (missed_bounce_m_s <= w.sweep.model.options.restitution_threshold_m_s) continue;
      if (restitution >= w.sweep.model.options.sequential_bounce_restitution) {
        chained = true;
      } else {
        w.held_back_bounces.push_back({pair, n, missed_bounce_m_s});
      }
    }
    impacts[pair].insert(impacts[pair].end(), hits.begin(), hits.end());
  }
  return chained;
}

}  // namespace

void resolve_rounds(const RoundsWorld& w, const std::vector<int>& participants, PartSolve& part, ImpactCache& cache,
                    bool cut_at_start, PartMotion& motion, std::vector<Contact>& contacts, StepReport& report) {
  step_helpers::require_size("resolve_rounds", "motion.u", motion.u.size(), participants.size());
  step_helpers::require_size("resolve_rounds", "motion.next", motion.next.size(), participants.size());
  // The participants' swept boxes and their overlapping pairs, for the end poses they were
  // swept to: a re-solve changes the motions of the islands it touches, so only those
  // bodies are swept again.
  std::vector<Eigen::AlignedBox3d> swept_boxes(participants.size());
  std::vector<geometry::Pose> swept_to;
  std::vector<std::pair<int, int>> swept_pairs;
  const auto sweep = [&] {
    std::vector<char> changed(participants.size(), 1);
    for (std::size_t s = 0; s < participants.size(); ++s) {
      if (!swept_to.empty() && motion.next[s].matrix() == swept_to[s].matrix()) {
        changed[s] = 0;
      } else {
        swept_boxes[s] =
            swept_box(w.sweep.state[participants[s]].X_WB, w.sweep.model.radius_m[participants[s]], motion.next[s]);
      }
    }
    swept_pairs = swept_to.empty() ? collision::overlapping_pairs(swept_boxes)
                                   : collision::overlapping_pairs_updated(swept_boxes, changed, swept_pairs);
    swept_to = motion.next;
  };
  int projections = 0;  // rounds that lifted end poses instead of solving
  ImpactMap impacts;    // every round's meetings: constraints of every later solve
  // A lift whose lifted motion then meets something (a body lifted into a third) is not
  // tried again in this part: its re-solve leaves the pair it lifted deep again, and lift
  // and re-solve alternated until the lifts ran out. Deep points become rows instead.
  bool lifted = false, lifts_meet = false;
  for (int round = 0;; ++round) {
    ImpactMap meeting;
    sweep();
    const Sweep swept =
        sweep_motions(w.sweep, participants, motion.next, &part.resting_pairs, &cache, &meeting, &swept_pairs);
    report.ccd_queries += swept.ccd_queries;
    motion.tau = swept.tau;
    bool deepening = swept.deepening;
    lifts_meet |= lifted && motion.tau < 1.0;
    lifted = false;
    // A squeezed body overlaps whatever the solve does: reported, not chased.
    if (motion.squeezed) deepening = false;
    if (motion.tau >= 1.0 && !deepening) return;
    ++report.impacts_resolved;
    if (round == kMaxResolveRounds) {
      motion.tau =
          last_round_fraction(w, participants, motion.next, cache, meeting, motion.tau, deepening, cut_at_start);
      return;
    }
    // Nothing meets inside the step; resting pairs only end it too deep: their end poses
    // are lifted (the velocities stay the solve's), and the next round checks the motion
    // to the lifted poses as it checked this one. With a meeting inside, the re-solve
    // replaces the motion anyway, and the deep points become rows of it.
    if (w.sweep.model.options.project_deep_points && deepening && motion.tau >= 1.0 && !lifts_meet &&
        projections < kMaxProjectionsPerMotion &&
        project_deep_points(w.sweep.model, w.sweep.state, participants, motion.next, meeting, cache,
                            part.resting_pairs)) {
      lifted = true;
      ++report.projections;
      ++projections;
      --round;  // (not a re-solve: it does not count against kMaxResolveRounds)
      continue;
    }
    if (add_impact_points(w, participants, motion, part, meeting, impacts)) {
      // Cut at the meeting, but not past where a touching pair digs in (cut past it, a
      // mesh pair would cross and sink unseen). A pair crossing at once would make it a cut
      // of nothing, again and again: the bounce is then solved with the rest.
      const double cut_at = deepening
                                ? std::min(motion.tau, shallow_fraction(w.sweep.model, w.sweep.state, participants,
                                                                        motion.next, cache, meeting))
                                : motion.tau;
      if (cut_at > 0) {
        motion.tau = cut_at;
        return;
      }
    }
    if (!part.setup)
      part.setup = prepare_solve(w.sweep.model, w.sweep.state, part.h, part.force_h, participants, part.resting);
    StepSolve resolved =
        solve_step(w.sweep.model, w.sweep.state, *part.setup, participants, part.resting, impacts, &part.islands);
    tally(resolved, report);
    motion.squeezed = resolved.infeasible;
    contacts = std::move(resolved.solved);
    std::vector<BodyVelocity> u_resolved = std::move(resolved.u);
    // Asked only to stop digging in, and it cannot be had: keep the motion.
    if (motion.squeezed && motion.tau >= 1.0) return;
    std::vector<geometry::Pose> next_resolved =
        candidate_poses(w.sweep.model, w.sweep.state, participants, u_resolved, w.step_start_s + part.elapsed, part.h);
    keep_motions(w.sweep.model, w.sweep.state, participants, motion.u, motion.next, u_resolved,
                 next_resolved);  // (after a cut, the end poses kept there)
    motion.u = std::move(u_resolved);
    motion.next = std::move(next_resolved);
  }
}

}  // namespace arphys::dynamics
