#include "tools/launch/main_job_spawner.hpp"

#include <algorithm>

#include "arphys/sim_command_t.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"

namespace arphys::launch {

MainJobSpawner::MainJobSpawner(const config::SceneConfig& scene, double every_s, bool enabled) : every_s_(every_s) {
  const config::ObjectConfig* model = thrown_model(scene);
  if (!model || !enabled || !(every_s > 0)) return;
  model_ = model->id;
  limit_ = model->max_instances - static_cast<int64_t>(model->spawn_at_start.size());
}

void MainJobSpawner::maybe_spawn(msg::Bus& bus, const std::string& channel, double elapsed_s) {
  if (model_.empty() || seq_ >= limit_ || elapsed_s - last_s_ < every_s_) return;
  arphys::sim_command_t c{};
  c.utime = msg::now_utime();
  c.seq = ++seq_;
  c.sender = "arphys-launch";
  c.command = arphys::sim_command_t::COMMAND_SPAWN;
  c.model = model_;
  const Throw thrown = throws_.next();
  c.X_WB = msg::to_message(thrown.X_WB);
  std::copy(thrown.v_WB_m_s.data(), thrown.v_WB_m_s.data() + 3, c.v_WB_m_s);
  bus.publish(channel, c);
  last_s_ = elapsed_s;
}

}  // namespace arphys::launch
