#pragma once
// What the integration tests watch in the simulator's world states: how many arrived,
// whether any pose was non-finite, and the fastest a virtual body moved between two
// consecutive states, as distance over simulation time (a teleport or a launch shows
// there; a state the test itself missed does not). Bodies below the table top are left
// out: they are falling off the table, fast by right.
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
  std::map<std::string, Eigen::Vector3d> last_position;

  void on_world_state(const arphys::world_state_t& m) {
    ++states;
    std::map<std::string, Eigen::Vector3d> positions;
    for (const auto& b : m.bodies) {
      for (double x : b.X_WB.position_m) non_finite += std::isfinite(x) ? 0 : 1;
      for (double x : b.X_WB.orientation_wxyz) non_finite += std::isfinite(x) ? 0 : 1;
      if (b.role != arphys::body_state_t::ROLE_VIRTUAL) continue;
      const Eigen::Vector3d p(b.X_WB.position_m[0], b.X_WB.position_m[1], b.X_WB.position_m[2]);
      positions[b.body_id] = p;
      auto last = last_position.find(b.body_id);
      const double dt = m.sim_time_s - last_sim_time_s;
      if (last == last_position.end() || !p.allFinite() || p.z() < -0.05 || !(dt > 0)) continue;
      const double speed = (p - last->second).norm() / dt;
      if (speed > fastest_m_s) {
        fastest_m_s = speed;
        fastest_body = b.body_id;
        fastest_at_s = m.sim_time_s;
      }
    }
    last_position = positions;
    last_sim_time_s = m.sim_time_s;
  }
};

}  // namespace arphys::testing
