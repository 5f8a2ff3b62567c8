// A group's step: bodies that may meet within the step, moved part by part. Each part is
// solved, then goes through its rounds (step_rounds.hpp); a bounce met in turn, or a meeting
// the rounds cannot hold, cuts the part at its time of impact and the next part starts there.
#include <algorithm>
#include <optional>
#include <vector>

#include "simulator/dynamics/step_helpers.hpp"
#include "simulator/dynamics/world.hpp"
#include "simulator/dynamics/world_internal.hpp"

namespace arphys::dynamics {

using step_helpers::pairs_of;
using step_helpers::slot_of;

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
    if (!at_start) gathered = gather_contacts(model_, state_.bodies, state_.hints, state_.mesh, pool_, participants, 0);
    // Gravity and the gyroscopic term act once per step, over all of it, in its first
    // solve: the velocities are end-of-step velocities (symplectic Euler), and a cut
    // carries them on.
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
      part.setup = prepare_solve(model_, state_.bodies, h, part.force_h, participants, part.resting);
      StepSolve solved = solve_step(model_, state_.bodies, *part.setup, participants, part.resting, {}, &part.islands);
      tally(solved, report);
      motion.squeezed = solved.infeasible;
      motion.u = std::move(solved.u);
      outcome.contacts = std::move(solved.solved);
    }
    motion.next = candidate_poses(model_, state_.bodies, participants, motion.u, state_.time_s + elapsed, h);
    // Answers valid while the start poses are these: the step's first sweep, then fresh
    // but for the pairs that go on as before the cut.
    ImpactCache fresh;
    if (!at_start) fresh = carry_over_cut(model_, state_.bodies, participants, motion.u, motion.next, cut);
    ImpactCache& cache = at_start ? first_ccd : fresh;
    resolve_rounds(rounds_world(), participants, part, cache, cut_at_start, motion, outcome.contacts, report);
    if (motion.tau < 1.0) {
      // Still meeting (a turning body whose constraints were linearised): stop at the
      // impact, with the velocities of the step, and go on from there.
      motion.tau = unswept_clear_fraction(model_, state_.bodies, participants, motion.next, cache, motion.tau, h);
      h *= motion.tau;
      if (++events >= model_.options.max_events_per_step) outcome.capped = true;
      // A second cut at the start of what is left: nothing has moved since the last, the
      // step's force is spent, and the solve would give the same motion until the cap:
      // the group's step ends here.
      if (motion.tau == 0 && cut_at_start) outcome.capped = true;
      cut_at_start = motion.tau == 0;
      cut = {motion.u, motion.next, motion.tau, {}};
      if (at_start) {
        // The group's answers move out of the step's first sweep (not copied: a pile's are
        // many); were the group stepped again after a merge, its pairs would be swept
        // again, to the same answers.
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
    report.non_finite_held +=
        commit_motion(model_, state_.bodies, participants, motion.u, motion.next, motion.tau, outcome.swept);
    elapsed += h;
    if (outcome.capped) break;
  }
  report.events = std::max(report.events, events);
  report.events_capped |= outcome.capped;
  return outcome;
}

}  // namespace arphys::dynamics
