#include "tools/view/view_relay.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "arphys/replay_control_t.hpp"
#include "arphys/sim_command_t.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"

namespace arphys::view {
namespace {

// The Message Data frame's receive time.
uint64_t now_ns() { return static_cast<uint64_t>(msg::now_utime()) * 1000; }

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
  // A token bucket: the rate on average, a frame early by the camera's jitter still sent
  // (spacing alone sent 20 of a 30 FPS camera's frames at a 30 Hz limit).
  const double t = msg::steady_s();
  Allowance& a = image_allowance_[topic];
  a.frames = std::min(2.0, a.frames + (t - a.at_s) * options_.image_rate_hz);
  a.at_s = t;
  if (a.frames < 1) {
    ++rate_limited_;
    return;
  }
  try {
    server.publish(topic, now_ns(),
                   compressed_image(frame, frame.camera_id.empty() ? "camera" : frame.camera_id).dump());
    a.frames -= 1;
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

std::string ViewRelay::spawnable_models() const {
  std::string models;
  for (const config::ObjectConfig& o : scene_.objects)
    if (o.role == config::Role::kVirtual && o.motion == config::Motion::kDynamic)
      models += (models.empty() ? "" : ",") + o.id;
  return models;
}

std::string ViewRelay::spawn(msg::Bus& bus, const std::string& payload) {
  Eigen::Vector3d p, v = Eigen::Vector3d::Zero();
  const config::ObjectConfig* model = nullptr;
  try {
    const nlohmann::json request = nlohmann::json::parse(payload);
    model = scene_.find_object(request.at("model").get<std::string>());
    const auto vector = [](const nlohmann::json& j) {
      return Eigen::Vector3d(j.at("x").get<double>(), j.at("y").get<double>(), j.at("z").get<double>());
    };
    p = vector(request.at("position"));
    if (request.contains("velocity")) v = vector(request.at("velocity"));
  } catch (const std::exception& e) {
    return std::string("expected {\"model\", \"position\": {x, y, z}, \"velocity\"}: ") + e.what();
  }
  if (!model || model->role != config::Role::kVirtual || model->motion != config::Motion::kDynamic)
    return "not a dynamic virtual model of the scene (spawnable: " + spawnable_models() + ")";
  if (!p.allFinite() || p.norm() > 10 || !v.allFinite() || v.norm() > 20)
    return "position beyond 10 m or velocity beyond 20 m/s, or not finite";
  const double t = msg::steady_s();
  if (t - last_spawn_s_ < 0.1) return "more than 10 spawns a second";
  last_spawn_s_ = t;
  arphys::sim_command_t command{};
  command.utime = msg::now_utime();
  command.seq = ++spawn_seq_;
  command.sender = "view";
  command.command = arphys::sim_command_t::COMMAND_SPAWN;
  command.model = model->id;
  geometry::Pose X_WB = model->X_WO;  // the model's orientation, at the asked position
  X_WB.translation() = p;
  command.X_WB = msg::to_message(X_WB);
  for (int k = 0; k < 3; ++k) command.v_WB_m_s[k] = v[k];
  bus.publish(scene_.channels.sim_command, command);
  return "";
}

std::string ViewRelay::replay_control(msg::Bus& bus, const std::string& channel, const std::string& payload) {
  arphys::replay_control_t control{};
  try {
    const nlohmann::json request = nlohmann::json::parse(payload);
    control.command = request.at("command").get<std::string>();
    control.value = request.value("value", 0.0);
  } catch (const std::exception& e) {
    return std::string("expected {\"command\", \"value\"}: ") + e.what();
  }
  static const char* const kCommands[] = {"pause", "resume", "toggle", "step", "seek", "rate"};
  if (std::find(std::begin(kCommands), std::end(kCommands), control.command) == std::end(kCommands))
    return "unknown command '" + control.command + "' (pause, resume, toggle, step, seek, rate)";
  if (!std::isfinite(control.value)) return "value not finite";
  control.utime = msg::now_utime();
  control.seq = ++control_seq_;
  control.sender = "view";
  bus.publish(channel, control);
  return "";
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
