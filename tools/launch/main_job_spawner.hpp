#pragma once
// The launcher's hand that throws virtual objects in, as a user would: the scene's first
// dynamic virtual model, every `every_s` seconds (from every_s on), up to the scene's
// max_instances less those it starts with, as spawn commands on the bus.
#include <cstdint>
#include <string>

#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "tools/launch/main_job_throws.hpp"

namespace arphys::launch {

class MainJobSpawner {
 public:
  // enabled false (no simulator started here) or every_s 0: never spawns.
  MainJobSpawner(const config::SceneConfig& scene, double every_s, bool enabled);
  // Publishes a spawn command on `channel` when one is due at elapsed_s.
  void maybe_spawn(msg::Bus& bus, const std::string& channel, double elapsed_s);

 private:
  std::string model_;
  int64_t limit_ = 0;
  double every_s_ = 0, last_s_ = 0;
  int64_t seq_ = 0;
  MainJobThrows throws_;
};

}  // namespace arphys::launch
