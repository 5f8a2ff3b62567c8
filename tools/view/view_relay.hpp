#pragma once
// What arphys-view does with each LCM message: converts it (foxglove_messages.hpp) and hands
// it to the server, only for topics somebody subscribes to, camera frames at a rate limit.
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "lcmtypes/msg/bus.hpp"
#include "tools/view/foxglove_messages.hpp"
#include "tools/view/foxglove_server.hpp"

namespace arphys::view {

struct RelayOptions {
  double image_rate_hz = 30;  // most frames a second per image topic (the newest is sent)
};

class ViewRelay {
 public:
  ViewRelay(const config::SceneConfig& scene, RelayOptions options);
  // The scene's model files as HTTP paths under path_prefix ("/models/").
  std::map<std::string, std::string> files(const std::string& path_prefix) const;
  // Where those files are reached from a client ("http://127.0.0.1:8765/models/").
  void set_model_url_prefix(const std::string& url_prefix);
  // Subscribes to the scene's channels; each message goes to `server` (both outlive the bus's use).
  void subscribe(msg::Bus& bus, FoxgloveServer& server);
  int64_t refused() const { return refused_; }            // frames that did not decode
  int64_t rate_limited() const { return rate_limited_; }  // frames skipped by the image rate
  const std::string& status_channel() const { return scene_.channels.process_status; }
  // Takes a client's message on "/spawn" ({"model", "position": {x,y,z}, "velocity": {x,y,z}},
  // metres and m/s in the world): a dynamic virtual model of the scene, finite, within 10 m
  // and 20 m/s (the simulator's own bounds, which also cap the instances), at most 10 a
  // second; publishes the spawn command on the scene's channel. Returns "" or why not.
  std::string spawn(msg::Bus& bus, const std::string& payload);
  // Takes a client's message on "/replay_control" ({"command": pause, resume, toggle, step,
  // seek or rate, "value": seconds or times real time}) and publishes it as a replay_control_t
  // on `channel` for arphys-replay. Returns "" or why not.
  std::string replay_control(msg::Bus& bus, const std::string& channel, const std::string& payload);
  // The models a client may spawn (for the serverInfo's metadata).
  std::string spawnable_models() const;

 private:
  void image(FoxgloveServer& server, int topic, const arphys::image_t& frame);
  config::SceneConfig scene_;
  RelayOptions options_;
  std::unique_ptr<SceneDrawing> drawing_;
  struct Allowance {
    double frames = 1, at_s = 0;  // frames that may be sent now, as of at_s
  };
  Allowance image_allowance_[kTopicCount];
  int64_t refused_ = 0, rate_limited_ = 0;
  int64_t spawn_seq_ = 0, control_seq_ = 0;
  double last_spawn_s_ = 0;
};

// The page served at "/" (web_dir/index.html) with the files it loads added to `files`: its
// script and three.js from web_dir/node_modules (tools/install_deps.sh). Without them, a
// text that says what the server is, how to open it in Foxglove or Lichtblick, and how to
// install the page.
std::string page(const std::string& web_dir, const std::string& scene_name, std::map<std::string, std::string>& files);

}  // namespace arphys::view
