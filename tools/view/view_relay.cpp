#include "tools/view/view_relay.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace arphys::view {
namespace {

uint64_t now_ns() {
  return static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}
double now_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

}  // namespace

ViewRelay::ViewRelay(const config::SceneConfig& scene, RelayOptions options)
    : scene_(scene), options_(options), drawing_(std::make_unique<SceneDrawing>(scene, "/models/")) {}

std::map<std::string, std::string> ViewRelay::files(const std::string& path_prefix) const {
  std::map<std::string, std::string> out;
  for (const auto& [name, path] : drawing_->model_files()) out[path_prefix + name] = path;
  return out;
}

void ViewRelay::set_model_url_prefix(const std::string& url_prefix) {
  drawing_ = std::make_unique<SceneDrawing>(scene_, url_prefix);
}

void ViewRelay::image(FoxgloveServer& server, int topic, const arphys::image_t& frame) {
  if (!server.subscribed(topic)) return;
  const double t = now_s();
  if (t - last_image_s_[topic] < 1.0 / options_.image_rate_hz) {
    ++rate_limited_;
    return;
  }
  try {
    server.publish(topic, now_ns(),
                   compressed_image(frame, frame.camera_id.empty() ? "camera" : frame.camera_id).dump());
    last_image_s_[topic] = t;
  } catch (const std::exception&) {
    ++refused_;
  }
}

void ViewRelay::subscribe(msg::Bus& bus, FoxgloveServer& server) {
  const config::ChannelNames& c = scene_.channels;
  bus.subscribe<arphys::image_t>(
      c.camera_image, [this, &server](const arphys::image_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        image(server, kCameraImage, m);
      });
  bus.subscribe<arphys::image_t>(c.overlay_image, [this, &server](const arphys::image_t& m, const lcm::ReceiveBuffer&,
                                                                  const std::string&) { image(server, kOverlay, m); });
  bus.subscribe<arphys::world_state_t>(
      c.world_state, [this, &server](const arphys::world_state_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        if (server.subscribed(kWorld)) server.publish(kWorld, now_ns(), drawing_->scene_update(m).dump());
      });
  bus.subscribe<arphys::object_poses_t>(
      c.object_poses, [&server](const arphys::object_poses_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        if (server.subscribed(kTf)) server.publish(kTf, now_ns(), frame_transforms(m).dump());
        if (server.subscribed(kObjects)) server.publish(kObjects, now_ns(), tracked_objects(m).dump());
      });
  bus.subscribe<arphys::process_status_t>(
      c.process_status, [&server](const arphys::process_status_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        if (server.subscribed(kStatus)) server.publish(kStatus, now_ns(), status(m).dump());
      });
  bus.subscribe<arphys::render_status_t>(
      c.render_status, [&server](const arphys::render_status_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        if (server.subscribed(kLatency)) server.publish(kLatency, now_ns(), latency(m).dump());
      });
}

std::string page(const std::string& web_dir, const std::string& scene_name, std::map<std::string, std::string>& files) {
  const std::map<std::string, std::string> page_files = {
      {"/view_page.mjs", web_dir + "/view_page.mjs"},
      {"/three.module.js", web_dir + "/node_modules/three/build/three.module.js"},
      {"/three/addons/loaders/OBJLoader.js", web_dir + "/node_modules/three/examples/jsm/loaders/OBJLoader.js"}};
  bool complete = std::filesystem::exists(web_dir + "/index.html");
  for (const auto& [path, file] : page_files) complete = complete && std::filesystem::exists(file);
  if (complete) {
    files.insert(page_files.begin(), page_files.end());
    std::ifstream in(web_dir + "/index.html");
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::string topics_list;
  for (const Topic& t : topics()) topics_list += "<li><code>" + t.topic + "</code> " + t.schema_name + "</li>";
  return "<!doctype html><html><head><meta charset=\"utf-8\"><title>arphys-view: " + scene_name +
         "</title></head><body><h1>arphys-view: " + scene_name +
         "</h1><p>A Foxglove WebSocket server (subprotocol <code>foxglove.websocket.v1</code>, JSON) on this "
         "address. Open it in Foxglove or Lichtblick: Open connection, Foxglove WebSocket, <code>ws://</code> and "
         "this host and port. (The page of its own needs three.js from npm: tools/install_deps.sh.)</p><ul>" +
         topics_list + "</ul></body></html>\n";
}

}  // namespace arphys::view
