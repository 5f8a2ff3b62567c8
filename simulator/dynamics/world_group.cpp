// A group's step: bodies that may meet within the step, moved part by part. Each part is
// solved, swept by the CCD and re-solved with what meets inside it as constraints (a few
// rounds); a bounce met in turn, or a meeting the rounds cannot hold, cuts the part at its
// time of impact and the next part starts there.
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "simulator/collision/broad_phase.hpp"
#include "simulator/dynamics/world.hpp"
#include "simulator/dynamics/world_internal.hpp"

namespace arphys::dynamics {

using world_internal::pairs_of;
using world_internal::slot_of;

namespace {

// Projections before a part of a step falls back to re-solving its deep points.
constexpr int kMaxProjectionsPerMotion = 4;
// Re-solves of a part before it is cut at what still meets: a cut costs a new part (its
// contacts, a solve and a sweep), more than a round. (With three, the 100-bunny pile
// and the 1000-box pile cut about twice as often, for 6 % and 4 % more time.)
constexpr int kMaxResolveRounds = 5;

}  // namespace

World::GroupOutcome World::advance_group(double dt_s, const std::vector<int>& participants, const FirstSolve& first,
                                         ImpactCache& first_ccd, StepReport& report) {
  GroupOutcome outcome;
  outcome.swept.assign(participants.size(), Eigen::AlignedBox3d());
  double elapsed = 0;
  int events = 0;
  Cut cut;                    // the last cut's motions and answers
  bool cut_at_start = false;  // the last cut was at the start of its motion
  while (dt_s - elapsed > 1e-12 * dt_s) {
    double h = dt_s - elapsed;
    set_kinematic_state(participants, state_.time_s + elapsed, h);
    // The poses do not change while a part is re-solved: its contacts are found once. The
    // step's first solve (all groups at once) is given, its contacts not copied (a whole
    // pile's are a megabyte).
    const bool at_start = elapsed == 0;
    std::vector<Contact> gathered;
    if (!at_start)
      gathered = gather_contacts(bodies_, radius_m_, options_, state_.hints, state_.mesh, pool_, participants, 0);
    // Gravity and the gyroscopic term act once per step, over all of it, in its first
    // solve: the velocities are end-of-step velocities (symplectic Euler), and a cut
    // carries them on. (Applied again after each cut, bodies with many events fell at
    // up to twice the free-fall speed.)
    SolvedIslands fresh_islands;
    PartSolve part{elapsed,
                   h,
                   at_start ? dt_s : 0.0,
                   at_start ? first.resting : gathered,
                   {},
                   at_start ? first.islands : fresh_islands,
                   std::nullopt};
    part.resting_pairs = pairs_of(part.resting);
    PartMotion motion;
    if (at_start) {
      motion.u = first.u;
      outcome.contacts = first.solved;
    } else {
      part.setup = prepare_solve(bodies_, options_, h, part.force_h, participants, part.resting);
      StepSolve solved =
          solve_step(bodies_, radius_m_, options_, *part.setup, participants, part.resting, {}, &part.islands);
      tally(solved, report);
      motion.squeezed = solved.infeasible;
      motion.u = std::move(solved.u);
      outcome.contacts = std::move(solved.solved);
    }
    motion.next = candidate_poses(participants, motion.u, elapsed, h);
    // Answers valid while the start poses are these: the step's first sweep, then fresh
    // but for the pairs that go on as before the cut.
    ImpactCache fresh;
    if (!at_start) fresh = carry_over_cut(bodies_, participants, motion.u, motion.next, cut);
    ImpactCache& cache = at_start ? first_ccd : fresh;
    resolve_rounds(participants, part, cache, cut_at_start, motion, outcome.contacts, report);
    if (motion.tau < 1.0) {
      // Still meeting (a turning body whose constraints were linearised): stop at the
      // impact, with the velocities of the step, and go on from there.
      motion.tau = unswept_clear_fraction(bodies_, options_, participants, motion.next, cache, motion.tau, h);
      h *= motion.tau;
      if (++events >= options_.max_events_per_step) outcome.capped = true;
      // A second cut at the start of what is left: nothing has moved since the last, the
      // step's force is spent, and the solve would give the same motion until the cap:
      // the group's step ends here.
      if (motion.tau == 0 && cut_at_start) outcome.capped = true;
      cut_at_start = motion.tau == 0;
      cut = {motion.u, motion.next, motion.tau, {}};
      if (at_start) {
        // The group's answers move out of the step's first sweep (copying them was a
        // twentieth of a 1000-box pile's step); were the group stepped again after a
        // merge, its pairs would be swept again, to the same answers.
        for (int i : participants)
          for (auto it = cache.lower_bound({i, -1}); it != cache.end() && it->first.first == i;)
            if (slot_of(participants, it->first.second) >= 0) {
              cut.answers.insert(cut.answers.end(), cache.extract(it++));
            } else {
              ++it;
            }
      } else {
        cut.answers = std::move(fresh);
      }
    }
    commit_part(participants, motion, outcome, report);
    elapsed += h;
    if (outcome.capped) break;
  }
  report.events = std::max(report.events, events);
  report.events_capped |= outcome.capped;
  return outcome;
}

void World::resolve_rounds(const std::vector<int>& participants, PartSolve& part, ImpactCache& cache, bool cut_at_start,
                           PartMotion& motion, std::vector<Contact>& contacts, StepReport& report) {
  // The participants' swept boxes and their overlapping pairs, for the end poses they were
  // swept to: a re-solve changes the motions of the islands it touches, so only those
  // bodies are swept again (sweeping all of a 1000-box pile in every round was a twentieth
  // of its step).
  std::vector<Eigen::AlignedBox3d> swept_boxes(participants.size());
  std::vector<geometry::Pose> swept_to;
  std::vector<std::pair<int, int>> swept_pairs;
  const auto sweep = [&] {
    std::vector<char> changed(participants.size(), 1);
    for (std::size_t s = 0; s < participants.size(); ++s) {
      if (!swept_to.empty() && motion.next[s].matrix() == swept_to[s].matrix()) {
        changed[s] = 0;
      } else {
        swept_boxes[s] = swept_box(bodies_[participants[s]], radius_m_[participants[s]], motion.next[s]);
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
        sweep_motions(sweep_world(), participants, motion.next, &part.resting_pairs, &cache, &meeting, &swept_pairs);
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
      motion.tau = last_round_fraction(participants, motion.next, cache, meeting, motion.tau, deepening, cut_at_start);
      return;
    }
    // Nothing meets inside the step; resting pairs only end it too deep: their end poses
    // are lifted (the velocities stay the solve's), and the next round checks the motion
    // to the lifted poses as it checked this one. With a meeting inside, the re-solve
    // replaces the motion anyway, and the deep points become rows of it (lifting poses a
    // re-solve then discarded was a third of a tumbling pile's step).
    if (options_.project_deep_points && deepening && motion.tau >= 1.0 && !lifts_meet &&
        projections < kMaxProjectionsPerMotion &&
        project_deep_points(bodies_, options_, participants, motion.next, meeting, cache, part.resting_pairs)) {
      lifted = true;
      ++report.projections;
      ++projections;
      --round;  // (not a re-solve: it does not count against kMaxResolveRounds)
      continue;
    }
    if (add_impact_points(participants, motion, part, meeting, impacts)) {
      // Cut at the meeting, but not past where a touching pair digs in (a mesh pair
      // crossing at once: cut past it, it crossed and sank unseen). Such a pair crossing
      // at once would make it a cut of nothing, again and again (a 20-bunny scene froze
      // for a second): the bounce is then solved with the rest, and the crossing with it.
      const double cut_at =
          deepening ? std::min(motion.tau, shallow_fraction(bodies_, participants, motion.next, cache, meeting))
                    : motion.tau;
      if (cut_at > 0) {
        motion.tau = cut_at;
        return;
      }
    }
    if (!part.setup) part.setup = prepare_solve(bodies_, options_, part.h, part.force_h, participants, part.resting);
    StepSolve resolved =
        solve_step(bodies_, radius_m_, options_, *part.setup, participants, part.resting, impacts, &part.islands);
    tally(resolved, report);
    motion.squeezed = resolved.infeasible;
    contacts = std::move(resolved.solved);
    std::vector<BodyVelocity> u_resolved = std::move(resolved.u);
    // Asked only to stop digging in, and it cannot be had: keep the motion.
    if (motion.squeezed && motion.tau >= 1.0) return;
    std::vector<geometry::Pose> next_resolved = candidate_poses(participants, u_resolved, part.elapsed, part.h);
    keep_motions(bodies_, participants, motion.u, motion.next, u_resolved,
                 next_resolved);  // (after a cut, the end poses kept there)
    motion.u = std::move(u_resolved);
    motion.next = std::move(next_resolved);
  }
}

double World::last_round_fraction(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                                  const ImpactCache& cache, const ImpactMap& meeting, double tau, bool deepening,
                                  bool cut_at_start) const {
  // Linearised constraints still let a touching pair dig in: stop where it is no deeper
  // than allowed (halving: the linearisation's error shrinks with the square). Unless that
  // is a cut of nothing again (a mesh pair crossing at once, which the re-solves did not
  // lift) while a tracked body moves: the group's step would end there and the tracked
  // body move on into it (up to 70 mm deep in the 20-bunny scene). The motion goes on
  // instead; the pair crosses by what this motion dips it and is pushed apart in the next
  // step (mesh_crossing_depth). With nothing tracked moving, waiting costs only time.
  if (!deepening) return tau;
  const double shallow = shallow_fraction(bodies_, participants, next, cache, meeting);
  const bool would_wait = shallow == 0 && cut_at_start;
  const auto tracked_moving = [&] {
    return std::any_of(participants.begin(), participants.end(), [&](int i) {
      const RigidBody& body = bodies_[i];
      return body.motion == BodyMotion::kKinematic &&
             (body.v_WBcm_m_s.squaredNorm() > 0 || body.w_WB_rad_s.squaredNorm() > 0);
    });
  };
  if (!would_wait || !tracked_moving()) return std::min(tau, shallow);
  return tau;
}

bool World::add_impact_points(const std::vector<int>& participants, const PartMotion& motion, const PartSolve& part,
                              ImpactMap& meeting, ImpactMap& impacts) {
  // A point's velocity in the motion that let it in.
  const auto velocity = [&](int body, const Eigen::Vector3d& p_W) -> Eigen::Vector3d {
    const RigidBody& b = bodies_[body];
    if (!b.is_dynamic()) return b.velocity_of_point(p_W);
    const int slot = slot_of(participants, body);
    return motion.u[slot].v_WBcm_m_s + motion.u[slot].w_WB_rad_s.cross(p_W - b.com_W());
  };
  bool chained = false;
  for (auto& [pair, hits] : meeting) {
    const geometry::Pose& X_A_end = motion.next[slot_of(participants, pair.first)];
    const geometry::Pose& X_B_end = motion.next[slot_of(participants, pair.second)];
    const RigidBody& body_a = bodies_[pair.first];
    const RigidBody& body_b = bodies_[pair.second];
    for (ImpactPoint& hit : hits) {
      // How deep the point ends the motion: a touching pair's as measured, a CCD meeting's
      // material points along A's normal there (the row's linearised bound misses it by
      // the turn's second-order term: re-solved with the same bound, such a pair met again
      // in every round and cut the step).
      const double end_depth_m =
          hit.end_depth_m >= 0
              ? hit.end_depth_m
              : (X_A_end.linear() * hit.normal_A_B).dot(X_A_end * hit.point_A_B - X_B_end * hit.point_B_B);
      const Eigen::Vector3d p_A = body_a.X_WB * hit.point_A_B, p_B = body_b.X_WB * hit.point_B_B;
      const Eigen::Vector3d n = body_a.X_WB.linear() * hit.normal_A_B;
      // At the midpoint, as the constraint row measures it (the two material points can be
      // millimetres apart along the surface at the start of a sliding step).
      const Eigen::Vector3d m = 0.5 * (p_A + p_B);
      const double v_n = n.dot(velocity(pair.second, m) - velocity(pair.first, m));
      hit.min_normal_velocity_m_s = v_n + (end_depth_m + options_.contact_gap_m) / part.h;
      // A bouncing meeting this step's solve brought about (a ball struck by another within
      // the step, which then strikes a third): the row's bounce comes from the velocities
      // at the step's start, which do not have it, and solved with the first impact at once
      // it shares the momentum out (a chain of three elastic balls ended at a third of the
      // speed each). Only where the bounce missed is itself one (restitution times the
      // approach the solve added, beyond gravity's over the step).
      if (hit.end_depth_m >= 0 || v_n >= -options_.restitution_threshold_m_s) continue;
      const double restitution = std::max(body_a.restitution, body_b.restitution);
      const double v_n_start = n.dot(body_b.velocity_of_point(m) - body_a.velocity_of_point(m));
      const double missed_bounce_m_s =
          restitution * (std::abs(v_n - v_n_start) - options_.gravity_m_s2.norm() * part.force_h);
      if (missed_bounce_m_s <= options_.restitution_threshold_m_s) continue;
      if (restitution >= options_.sequential_bounce_restitution) {
        chained = true;
      } else {
        state_.held_back_bounces.push_back({pair, n, missed_bounce_m_s});
      }
    }
    impacts[pair].insert(impacts[pair].end(), hits.begin(), hits.end());
  }
  return chained;
}

void World::commit_part(const std::vector<int>& participants, const PartMotion& motion, GroupOutcome& outcome,
                        StepReport& report) {
  for (std::size_t s = 0; s < participants.size(); ++s) {
    RigidBody& body = bodies_[participants[s]];
    if (!body.is_dynamic()) continue;
    const BodyVelocity& u = motion.u[s];
    const geometry::Pose X =
        motion.tau >= 1.0 ? motion.next[s] : geometry::ScrewMotion(body.X_WB, motion.next[s]).pose_at(motion.tau);
    if (X.matrix().allFinite() && u.v_WBcm_m_s.allFinite() && u.w_WB_rad_s.allFinite()) {
      outcome.swept[s].extend(swept_box(bodies_[participants[s]], radius_m_[participants[s]], X));
      body.X_WB = X;
      body.v_WBcm_m_s = u.v_WBcm_m_s;
      body.w_WB_rad_s = u.w_WB_rad_s;
    } else {
      // Last line of defence: a numerical failure anywhere in the step (solve, CCD cut,
      // integration) leaves the body where it was, at rest. Never NaN.
      outcome.swept[s].extend(body.X_WB.translation());
      body.v_WBcm_m_s.setZero();
      body.w_WB_rad_s.setZero();
      ++report.non_finite_held;
    }
  }
}

}  // namespace arphys::dynamics
