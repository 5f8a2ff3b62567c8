#pragma once
// What the integration tests watch in the simulator's world states: how many arrived,
// whether any pose was non-finite, the fastest a virtual body moved between two
// consecutive states (distance over simulation time; a state the test itself missed does
// not count), and teleports: a virtual body that moved further in one step than anything
// in the scene was moving could carry it (a jump, not motion: within a step a body can be
// struck and stopped again, so its own speeds at the two ends do not bound it). Bodies below the table top are left out of the
// speed: they are falling off the table, fast by right.
#include <cmath>
#include <map>
#include <string>

#include <Eigen/Core>

#include "arphys/world_state_t.hpp"

namespace arphys::testing {

struct WorldWatch {
  long states = 0;
  long non_finite = 0;
  double fastest_m_s = 0;
  std::string fastest_body;
  double fastest_at_s = 0;  // simulation time
  double last_sim_time_s = -1;
  long teleports = 0;
  std::string teleport_body;
  std::map<std::string, Eigen::Vector3d> last_position;
  double last_fastest_reported_m_s = 0;

  void on_world_state(const arphys::world_state_t& m) {
    ++states;
    std::map<std::string, Eigen::Vector3d> positions;
    double fastest_reported_m_s = 0;  // any body, real ones too (the box strikes bunnies)
    for (const auto& b : m.bodies) {
      fastest_reported_m_s = std::max(fastest_reported_m_s, Eigen::Vector3d(b.v_WB_m_s[0], b.v_WB_m_s[1], b.v_WB_m_s[2]).norm());
    }
    for (const auto& b : m.bodies) {
      for (double x : b.X_WB.position_m) non_finite += std::isfinite(x) ? 0 : 1;
      for (double x : b.X_WB.orientation_wxyz) non_finite += std::isfinite(x) ? 0 : 1;
      if (b.role != arphys::body_state_t::ROLE_VIRTUAL) continue;
      const Eigen::Vector3d p(b.X_WB.position_m[0], b.X_WB.position_m[1], b.X_WB.position_m[2]);
      positions[b.body_id] = p;
      auto last = last_position.find(b.body_id);
      const double dt = m.sim_time_s - last_sim_time_s;
      if (last == last_position.end() || !p.allFinite() || !(dt > 0)) continue;
      // Struck by the fastest body (restitution at most 1: twice its speed), plus margin
      // for the origin turning about the centre.
      if ((p - last->second).norm() > 2 * std::max(fastest_reported_m_s, last_fastest_reported_m_s) * dt + 0.01) {
        ++teleports;
        teleport_body = b.body_id;
      }
      if (p.z() < -0.05) continue;
      const double speed = (p - last->second).norm() / dt;
      if (speed > fastest_m_s) {
        fastest_m_s = speed;
        fastest_body = b.body_id;
        fastest_at_s = m.sim_time_s;
      }
    }
    last_position = positions;
    last_fastest_reported_m_s = fastest_reported_m_s;
    last_sim_time_s = m.sim_time_s;
  }
};

}  // namespace arphys::testing
