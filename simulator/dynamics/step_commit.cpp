#include "simulator/dynamics/step_commit.hpp"

#include "simulator/dynamics/step_helpers.hpp"
#include "simulator/dynamics/step_sweep.hpp"

namespace arphys::dynamics {
namespace {

// A body's pose after moving its centre of mass with v and turning with w for h.
geometry::Pose integrate(const BodyModel& body, const BodyState& now, const BodyVelocity& u, double h) {
  return moved_about_com(now.X_WB, body.mass.center_of_mass_m, u.v_WBcm_m_s * h, u.w_WB_rad_s, u.w_WB_rad_s.norm() * h);
}

}  // namespace

std::vector<geometry::Pose> candidate_poses(const WorldModel& model, const std::vector<BodyState>& state,
                                            const std::vector<int>& participants, const std::vector<BodyVelocity>& u,
                                            double t_s, double h) {
  step_helpers::require_model("candidate_poses", model, state);
  step_helpers::require_participants("candidate_poses", participants, state.size());
  step_helpers::require_size("candidate_poses", "u", u.size(), participants.size());
  std::vector<geometry::Pose> next(participants.size());
  for (std::size_t s = 0; s < participants.size(); ++s) {
    const BodyModel& body = model.bodies[participants[s]];
    const BodyState& now = state[participants[s]];
    if (moves(body, now)) {
      next[s] = integrate(body, now, u[s], h);
    } else if (body.motion == BodyMotion::kKinematic && !now.trajectory.empty()) {
      next[s] = now.trajectory.pose_at(t_s + h);
    } else {
      next[s] = now.X_WB;
    }
  }
  return next;
}

int commit_motion(const WorldModel& model, std::vector<BodyState>& state, const std::vector<int>& participants,
                  const std::vector<BodyVelocity>& u, const std::vector<geometry::Pose>& next, double tau,
                  std::vector<Eigen::AlignedBox3d>& swept) {
  step_helpers::require_model("commit_motion", model, state);
  step_helpers::require_participants("commit_motion", participants, state.size());
  step_helpers::require_size("commit_motion", "u", u.size(), participants.size());
  step_helpers::require_size("commit_motion", "next", next.size(), participants.size());
  step_helpers::require_size("commit_motion", "swept", swept.size(), participants.size());
  int held = 0;
  for (std::size_t s = 0; s < participants.size(); ++s) {
    BodyState& body = state[participants[s]];
    if (!moves(model.bodies[participants[s]], body)) continue;
    const geometry::Pose X = tau >= 1.0 ? next[s] : geometry::ScrewMotion(body.X_WB, next[s]).pose_at(tau);
    if (X.matrix().allFinite() && u[s].v_WBcm_m_s.allFinite() && u[s].w_WB_rad_s.allFinite()) {
      swept[s].extend(swept_box(body.X_WB, model.radius_m[participants[s]], X));
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
