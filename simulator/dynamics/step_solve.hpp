#pragma once
// A step's constrained solve over a set of participants (Gauss's principle, docs/method.md
// section 2): the unknowns and their unconstrained velocities, each contact's row (its
// gap, its bounce, its own bound), the solve of contact_solver.hpp and the launch guard.
// A stage of World::step with its inputs and outputs typed; it reads the bodies, never
// writes them.
#include <vector>

#include "simulator/dynamics/contact.hpp"
#include "simulator/dynamics/contact_solver.hpp"
#include "simulator/dynamics/world_model.hpp"

namespace arphys::dynamics {

// What every solve at the same poses shares before the impacts are known (a part's
// rounds): the unknowns (the dynamic participants), their inertia and unconstrained
// velocities, and the resting contacts' rows.
struct SolveSetup {
  double h = 0;  // the time the solve's velocities act over
  // Rows start their iterative solve from their warm forces times this: h in a solve that
  // applies the step's forces, as the step's first solve does; 0 after a cut.
  double warm_h_s = 0;
  std::vector<int> unknown_of_slot, slot_of_unknown, body_of_unknown;
  std::vector<BodyInertia> inertia;
  std::vector<BodyVelocity> u_unconstrained;
  std::vector<ContactRow> resting_rows;
  double deepest_m = 0;  // deepest overlap among the resting contacts
};

// model, state: every body of the world (contacts and participants index them); participants:
// sorted body indices. h: the time left in the step; force_h: the time over which gravity
// and the gyroscopic term act in this solve (the whole step in its first solve, 0 after a
// cut).
SolveSetup prepare_solve(const WorldModel& model, const std::vector<BodyState>& state, double h, double force_h,
                         const std::vector<int>& participants, const std::vector<Contact>& resting);

// A contact's constraint row for a solve over setup.h: close at most to the resting gap,
// undo an overlap at up to the depenetration speed, bounce with the pair's restitution
// when it closes fast enough to meet within h, and keep the contact's own lower bound.
ContactRow contact_row(const WorldModel& model, const std::vector<BodyState>& state, const Contact& contact,
                       const SolveSetup& setup, const std::vector<int>& participants);

// The meetings the CCD found, as contacts at the bodies' current poses.
std::vector<Contact> impact_contacts(const std::vector<BodyState>& state, const ImpactMap& impacts);

// What a solve gave: velocities by participant (non-dynamic ones zero), the contacts it
// solved (the resting ones, then the meetings') with their impulses, and its figures.
struct StepSolve {
  std::vector<BodyVelocity> u;
  std::vector<Contact> solved;
  double kkt_residual_m_s = 0;
  bool infeasible = false;  // a body squeezed between non-dynamic ones
  int iterative_islands = 0;
  int iterations = 0;
  int launches_prevented = 0;
  double deepest_resting_m = 0;  // the setup's: the resting contacts' overlaps only
};
StepSolve solve_step(const WorldModel& model, const std::vector<BodyState>& state, const SolveSetup& setup,
                     const std::vector<int>& participants, const std::vector<Contact>& resting,
                     const ImpactMap& impacts, SolvedIslands* memo);

// The launch guard. Contacts are passive: with restitution <= 1 a solve can at most reverse
// (and pass on) the fastest motion among the bodies it couples, plus what moving
// non-dynamic bodies and depenetration impose. A body of `u` (by unknown) left faster than
// twice that, by the speed of its kinetic energy, or with points faster than
// options.max_body_speed_m_s, is slowed to the bound; one left non-finite takes its
// unconstrained velocity. Returns how many were.
int guard_launches(const WorldModel& model, const std::vector<BodyState>& state, const SolveSetup& setup,
                   const std::vector<int>& participants, const std::vector<ContactRow>& rows,
                   std::vector<BodyVelocity>& u);

// Adds a solve's figures to the step's report.
void tally(const StepSolve& solve, StepReport& report);

}  // namespace arphys::dynamics
