#pragma once
// The motions a solve gives: where they take the bodies, and, the last stage of a part of a
// step, moving the dynamic bodies along them to the fraction the part took.
#include <Eigen/Geometry>
#include <vector>

#include "simulator/dynamics/contact_solver.hpp"
#include "simulator/dynamics/world_model.hpp"

namespace arphys::dynamics {

// Where the participants (sorted body indices) are after h with velocities u (by slot),
// from t_s: a dynamic body along its constant twist, a kinematic one where its trajectory
// is at t_s + h, a static one where it is.
std::vector<geometry::Pose> candidate_poses(const WorldModel& model, const std::vector<BodyState>& state,
                                            const std::vector<int>& participants, const std::vector<BodyVelocity>& u,
                                            double t_s, double h);

// Moves each dynamic participant (by slot: u, next, swept) along its screw motion from its
// pose to next, to fraction tau of it (1: to next), with velocity u, and extends its swept
// box by where it ends. A body whose
// end pose or velocity would be non-finite (a numerical failure anywhere in the step) stays
// where it is, at rest: never NaN. Returns how many did.
int commit_motion(const WorldModel& model, std::vector<BodyState>& state, const std::vector<int>& participants,
                  const std::vector<BodyVelocity>& u, const std::vector<geometry::Pose>& next, double tau,
                  std::vector<Eigen::AlignedBox3d>& swept);

}  // namespace arphys::dynamics
