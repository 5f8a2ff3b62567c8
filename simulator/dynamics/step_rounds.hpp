#pragma once
// The rounds of a part of a group's step (a part: from the step's start or a cut to the
// step's end or the next cut): sweep the solved motion; lift points it leaves too deep, or
// re-solve with what meets inside it as constraints; until nothing meets (the part runs to
// the end of the step) or it must be cut at a time of impact. A stage of World::step with
// its inputs and outputs typed.
#include <optional>
#include <vector>

#include "simulator/dynamics/contact.hpp"
#include "simulator/dynamics/contact_solver.hpp"
#include "simulator/dynamics/step_contacts.hpp"
#include "simulator/dynamics/step_solve.hpp"
#include "simulator/dynamics/step_sweep.hpp"

namespace arphys::dynamics {

// What every solve of one part of a group's step shares (a part: from the step's start or
// a cut to the step's end or the next cut): the time left, the time its force acts over,
// the resting contacts at its start poses and the islands solved there.
struct PartSolve {
  double elapsed = 0, h = 0, force_h = 0;
  const std::vector<Contact>& resting;
  std::vector<BodyPair> resting_pairs;
  SolvedIslands& islands;
  std::optional<SolveSetup> setup;  // built when a solve needs it
};

// A part's motion: velocities and end poses by participant, and the fraction of it taken
// (1: to the end of the step; less: cut at a time of impact).
struct PartMotion {
  std::vector<BodyVelocity> u;
  std::vector<geometry::Pose> next;
  double tau = 1;
  bool squeezed = false;  // the last solve could not keep a body out of fixed ones
};

// What the rounds read and write of the world: the sweep's view, the step's start time
// (kinematic bodies' trajectories are timed from it) and the bounces held back for the next
// step.
struct RoundsWorld {
  SweepWorld sweep;
  double step_start_s = 0;
  std::vector<ContactHints::Bounce>& held_back_bounces;
};

// Rounds of CCD and re-solve of a part's motion, each meeting a constraint of the next
// solve, until nothing meets inside it (tau 1) or it must be cut (tau < 1). `contacts`:
// the last solve's; cut_at_start: the last cut was at the start of its motion.
void resolve_rounds(const RoundsWorld& world, const std::vector<int>& participants, PartSolve& part, ImpactCache& cache,
                    bool cut_at_start, PartMotion& motion, std::vector<Contact>& contacts, StepReport& report);

}  // namespace arphys::dynamics
