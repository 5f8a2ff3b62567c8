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
  double image_rate_hz = 15;  // most frames a second per image topic (the newest is sent)
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

 private:
  void image(FoxgloveServer& server, int topic, const arphys::image_t& frame);
  config::SceneConfig scene_;
  RelayOptions options_;
  std::unique_ptr<SceneDrawing> drawing_;
  double last_image_s_[kTopicCount] = {};
  int64_t refused_ = 0, rate_limited_ = 0;
};

// The page served at "/" (web_dir/index.html) with the files it loads added to `files`: its
// script and three.js from web_dir/node_modules (tools/install_deps.sh). Without them, a
// text that says what the server is, how to open it in Foxglove or Lichtblick, and how to
// install the page.
std::string page(const std::string& web_dir, const std::string& scene_name, std::map<std::string, std::string>& files);

}  // namespace arphys::view
