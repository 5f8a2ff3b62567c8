#include "simulator/dynamics/step_commit.hpp"

#include "simulator/dynamics/step_helpers.hpp"
#include "simulator/dynamics/step_sweep.hpp"

namespace arphys::dynamics {
namespace {

// A body's pose after moving its centre of mass with v and turning with w for h.
geometry::Pose integrate(const RigidBody& body, const BodyVelocity& u, double h) {
  return moved_about_com(body.X_WB, body.mass.center_of_mass_m, u.v_WBcm_m_s * h, u.w_WB_rad_s,
                         u.w_WB_rad_s.norm() * h);
}

}  // namespace

std::vector<geometry::Pose> candidate_poses(const std::vector<RigidBody>& bodies, const std::vector<int>& participants,
                                            const std::vector<BodyVelocity>& u, double t_s, double h) {
  step_helpers::require_participants("candidate_poses", participants, bodies.size());
  step_helpers::require_size("candidate_poses", "u", u.size(), participants.size());
  std::vector<geometry::Pose> next(participants.size());
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const RigidBody& body = bodies[participants[s]];
    if (body.is_dynamic()) {
      next[s] = integrate(body, u[s], h);
    } else if (body.motion == BodyMotion::kKinematic && !body.trajectory.empty()) {
      next[s] = body.trajectory.pose_at(t_s + h);
    } else {
      next[s] = body.X_WB;
    }
  }
  return next;
}

int commit_motion(std::vector<RigidBody>& bodies, const std::vector<double>& radius_m,
                  const std::vector<int>& participants, const std::vector<BodyVelocity>& u,
                  const std::vector<geometry::Pose>& next, double tau, std::vector<Eigen::AlignedBox3d>& swept) {
  step_helpers::require_participants("commit_motion", participants, bodies.size());
  step_helpers::require_size("commit_motion", "radius_m", radius_m.size(), bodies.size());
  step_helpers::require_size("commit_motion", "u", u.size(), participants.size());
  step_helpers::require_size("commit_motion", "next", next.size(), participants.size());
  step_helpers::require_size("commit_motion", "swept", swept.size(), participants.size());
  int held = 0;
  for (std::size_t s = 0; s < participants.size(); ++s) {
    RigidBody& body = bodies[participants[s]];
    if (!body.is_dynamic()) continue;
    const geometry::Pose X = tau >= 1.0 ? next[s] : geometry::ScrewMotion(body.X_WB, next[s]).pose_at(tau);
    if (X.matrix().allFinite() && u[s].v_WBcm_m_s.allFinite() && u[s].w_WB_rad_s.allFinite()) {
      swept[s].extend(swept_box(body, radius_m[participants[s]], X));
      body.X_WB = X;
      body.v_WBcm_m_s = u[s].v_WBcm_m_s;
      body.w_WB_rad_s = u[s].w_WB_rad_s;
    } else {
      swept[s].extend(body.X_WB.translation());
      body.v_WBcm_m_s.setZero();
      body.w_WB_rad_s.setZero();
      ++held;
    }
  }
  return held;
}

}  // namespace arphys::dynamics
