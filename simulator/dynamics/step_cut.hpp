#pragma once
// What follows a sweep, short of a re-solve: lifting resting points the motion left too deep
// (moving end poses, velocities kept), where a step must be cut so that nothing is left
// deeper than allowed, and what a cut carries over of the motion it cut. Stages of
// World::step with typed inputs and outputs; they read the bodies, never write them.
#include <vector>

#include "simulator/dynamics/contact.hpp"
#include "simulator/dynamics/contact_solver.hpp"
#include "simulator/dynamics/step_sweep.hpp"
#include "simulator/dynamics/world_model.hpp"

namespace arphys::dynamics {

// Lifts the pairs of `meeting` that end too deep (resting primitive pairs) out by moving
// the end poses `next` (by participant), with the resting pairs the lift deepens; CCD
// meetings are left for the re-solve. False (next unchanged) when a mesh pair ends too deep
// or the lift does not converge (a body squeezed between fixed ones).
bool project_deep_points(const WorldModel& model, const std::vector<BodyState>& state,
                         const std::vector<int>& participants, std::vector<geometry::Pose>& next,
                         const ImpactMap& meeting, const ImpactCache& cache,
                         const std::vector<BodyPair>& resting_pairs);

// The fraction tau of the motion to next (over h_s), or less (halved), at which no unswept
// pair whose depth is measured (see CachedImpact::swept; not a mesh pair) overlaps deeper
// than allowed or than the rest of the step can undo: a step cut at tau must not leave such
// a pair where its motion only passes through (a box clipping another's corner).
double unswept_clear_fraction(const WorldModel& model, const std::vector<BodyState>& state,
                              const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                              const ImpactCache& cache, double tau, double h_s);

// The fraction of the motions to `next` at which no touching pair that deepens is deeper
// than it may be (halving from 1): the pairs `meeting` names, as sweep_motions left them in
// `cache` (every pair that deepens is in `meeting`).
double shallow_fraction(const WorldModel& model, const std::vector<BodyState>& state,
                        const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                        const ImpactCache& cache, const ImpactMap& meeting);

// Keeps the end pose next_before of each dynamic body whose velocity u is exactly u_before
// (static bodies and held sleepers: always); returns which, by participant.
std::vector<char> keep_motions(const WorldModel& model, const std::vector<BodyState>& state,
                               const std::vector<int>& participants, const std::vector<BodyVelocity>& u_before,
                               const std::vector<geometry::Pose>& next_before, const std::vector<BodyVelocity>& u,
                               std::vector<geometry::Pose>& next);

// A cut of a group's step at a time of impact: the motion it cut (participants' velocities
// and end poses), where, and the CCD answers for that motion.
struct Cut {
  std::vector<BodyVelocity> u;
  std::vector<geometry::Pose> next;
  double tau = 1;
  ImpactCache answers;
};
// The CCD answers of the cut motion that hold for the motion after it (u, next: by
// participant, from the cut's poses); sets the end pose of each body that goes on as
// before back to the one the cut motion had.
ImpactCache carry_over_cut(const WorldModel& model, const std::vector<BodyState>& state,
                           const std::vector<int>& participants, const std::vector<BodyVelocity>& u,
                           std::vector<geometry::Pose>& next, Cut& cut);

}  // namespace arphys::dynamics
