#include "renderer/app/live_renderer.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <random>

#include <opencv2/highgui.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "arphys/image_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/sim_command_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "lcmtypes/msg/image_message.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"
#include "renderer/drawing/overlay_renderer.hpp"
#include "renderer/output/video_file.hpp"
#include "renderer/process/frame_schedule.hpp"

namespace arphys::rendering {
namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

// Logs the first occurrence of each kind of bad input; every one is counted.
struct BadInput {
  std::map<std::string, int64_t> counts;
  void note(const std::string& kind, const std::string& detail) {
    if (counts[kind]++ == 0) std::fprintf(stderr, "renderer: %s (%s); further ones counted silently\n", kind.c_str(), detail.c_str());
  }
  int64_t total() const {
    int64_t n = 0;
    for (const auto& [k, v] : counts) n += v;
    return n;
  }
  int64_t count(const std::string& kind) const {
    const auto it = counts.find(kind);
    return it == counts.end() ? 0 : it->second;
  }
};

class LiveRenderer {
 public:
  LiveRenderer(const config::SceneConfig& scene, const CameraProjection& projection, const LiveOptions& options)
      : scene_(scene),
        projection_(projection),
        options_(options),
        bus_(options.lcm_url.empty() ? scene.lcm_url : options.lcm_url),
        renderer_(projection),
        models_(scene, renderer_),
        schedule_({options.wait_ms, options.policy}, [this](int64_t utime) { return states_.has_reached(utime); }),
        spawn_rng_(static_cast<uint32_t>(getpid())) {
    if (!options_.png_dir.empty()) std::filesystem::create_directories(options_.png_dir);
    if (options_.window && !std::getenv("DISPLAY")) {
      std::fprintf(stderr, "renderer: --window needs a display (DISPLAY is not set); continuing without a window\n");
      options_.window = false;
    }
  }

  void subscribe();
  void run();

 private:
  void draw(const arphys::image_t& message);
  OverlayLayers layers_of(const arphys::world_state_t& world, const geometry::Pose& X_WC);
  void write_outputs(const cv::Mat& overlay, const arphys::image_t& message);
  void handle_key();
  void send_command(int8_t command);
  void publish_heartbeat(Clock::time_point now);

  const config::SceneConfig& scene_;
  CameraProjection projection_;
  LiveOptions options_;
  msg::Bus bus_;
  OverlayRenderer renderer_;
  SceneModels models_;
  WorldStateMatcher<arphys::world_state_t> states_{64};
  WorldStateMatcher<geometry::Pose> camera_poses_{64};
  FrameSchedule<arphys::image_t> schedule_;
  BadInput bad_;
  cv::VideoWriter writer_;
  std::mt19937 spawn_rng_;
  int64_t command_seq_ = 0;
  bool paused_ = false;
  Clock::time_point start_ = Clock::now(), last_status_ = start_;
  int64_t rendered_ = 0, rendered_since_status_ = 0, published_ = 0, without_world_ = 0;
  double render_ms_since_status_ = 0;
};

void LiveRenderer::subscribe() {
  bus_.subscribe<arphys::world_state_t>(
      scene_.channels.world_state, [&](const arphys::world_state_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        if (!states_.add(m.utime, m, m.step_end_utime)) bad_.note("duplicate world state", "seq " + std::to_string(m.seq));
      });
  bus_.subscribe<arphys::object_poses_t>(
      scene_.channels.object_poses, [&](const arphys::object_poses_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        if (m.camera_world_valid) camera_poses_.add(m.utime, msg::from_message(m.X_WC, "X_WC"));
      });
  bus_.subscribe<arphys::image_t>(
      scene_.channels.camera_image, [&](const arphys::image_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        const auto verdict = schedule_.offer(m, Clock::now());
        if (verdict != msg::FrameOrder::Verdict::kNew) {
          bad_.note(std::string(msg::to_string(verdict)) + " camera frame", m.camera_id + " seq " + std::to_string(m.seq));
        }
      });
}

// The world state's bodies as the scene's models (bodies with a bad pose are left out and
// counted), and its contacts, seen from X_WC.
OverlayLayers LiveRenderer::layers_of(const arphys::world_state_t& world, const geometry::Pose& X_WC) {
  std::vector<BodyToDraw> bodies;
  for (const auto& b : world.bodies) {
    const std::string problem = msg::pose_problem(b.X_WB);
    if (!problem.empty()) {
      bad_.note("body with a bad pose", b.body_id + ": " + problem);
      continue;
    }
    bodies.push_back({b.model, b.role == arphys::body_state_t::ROLE_REAL, msg::from_message(b.X_WB)});
  }
  int unknown = 0;
  OverlayLayers layers = layers_for(models_, bodies, X_WC, options_.layers, &unknown);
  for (int i = 0; i < unknown; ++i) bad_.note("unknown model in the world state", "not in scene " + scene_.name);
  if (!options_.no_contacts) {
    for (const auto& c : world.contacts) {
      layers.contacts.push_back({layers.X_CW * msg::from_array(c.p_W_m), layers.X_CW.linear() * msg::from_array(c.n_W)});
    }
  }
  return layers;
}

void LiveRenderer::draw(const arphys::image_t& message) {
  const int64_t render_start = msg::now_utime();
  cv::Mat frame;
  try {
    frame = msg::decode_image_message(message);
  } catch (const std::exception& e) {
    bad_.note("undecodable image", e.what());
    return;
  }
  if (frame.cols != projection_.width_px || frame.rows != projection_.height_px) {
    bad_.note("image of the wrong size", std::to_string(frame.cols) + "x" + std::to_string(frame.rows));
    return;
  }
  const auto world = states_.match(message.utime, options_.policy);
  const auto camera = camera_poses_.match(message.utime, MatchPolicy::kNearestEarlier);
  const geometry::Pose X_WC = camera.state ? *camera.state : options_.X_WC_fixed;
  OverlayLayers layers;
  std::string note = "no world state";
  if (world.state) {
    layers = layers_of(*world.state, X_WC);
    note = "world t=" + std::to_string(world.state->sim_time_s).substr(0, 6) + " s";
  } else {
    ++without_world_;
  }
  cv::Mat overlay = renderer_.composite(layers, frame);
  const int64_t render_end = msg::now_utime();
  char text[200];
  std::snprintf(text, sizeof text, "render %.1f ms  capture->render %.1f ms  %s", 1e-3 * (render_end - render_start),
                1e-3 * (render_end - message.utime), note.c_str());
  cv::putText(overlay, text, {8, overlay.rows - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 3, cv::LINE_AA);
  cv::putText(overlay, text, {8, overlay.rows - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {255, 255, 255}, 1, cv::LINE_AA);
  write_outputs(overlay, message);
  arphys::render_status_t status{};
  status.utime = message.utime;
  status.seq = message.seq;
  status.world_state_utime = world.state ? world.capture_utime : 0;
  status.world_state_sim_time_s = world.state ? world.state->sim_time_s : 0;
  status.world_state_match = static_cast<int8_t>(world.kind);
  status.render_start_utime = render_start;
  status.render_end_utime = render_end;
  status.publish_utime = msg::now_utime();
  bus_.publish(scene_.channels.render_status, status);
  ++published_;
  ++rendered_;
  ++rendered_since_status_;
  render_ms_since_status_ += 1e-3 * (render_end - render_start);
}

void LiveRenderer::write_outputs(const cv::Mat& overlay, const arphys::image_t& message) {
  if (!options_.video.empty()) {
    if (!writer_.isOpened()) {
      try {
        writer_ = open_video_file(options_.video, 30, overlay.size(), true);
      } catch (const std::exception& e) {
        bad_.note("video file cannot be written", e.what());
      }
    }
    if (writer_.isOpened()) writer_.write(overlay);
  }
  if (!options_.png_dir.empty() && options_.png_every > 0 && rendered_ % options_.png_every == 0) {
    cv::imwrite(options_.png_dir + "/overlay_" + std::to_string(message.seq) + ".png", overlay);
  }
  if (options_.overlay_lcm) {
    bus_.publish(scene_.channels.overlay_image, msg::encode_image_message(overlay, message.utime, message.seq, message.camera_id));
    ++published_;
  }
  if (options_.window) {
    cv::imshow("arphys", overlay);
    handle_key();
  }
}

// The window's keys: b spawns, r resets, p pauses and resumes, q or Esc quits.
void LiveRenderer::handle_key() {
  const int key = cv::waitKey(1) & 0xff;
  if (key == 'q' || key == 27) g_stop = true;
  if (key == 'b') send_command(arphys::sim_command_t::COMMAND_SPAWN);
  if (key == 'r') send_command(arphys::sim_command_t::COMMAND_RESET);
  if (key == 'p') {
    paused_ = !paused_;
    send_command(paused_ ? arphys::sim_command_t::COMMAND_PAUSE : arphys::sim_command_t::COMMAND_RESUME);
  }
}

// The paper's interaction: a key throws a virtual object onto the table from above its near
// edge, with a small random spread so repeated presses do not stack exactly.
void LiveRenderer::send_command(int8_t command) {
  arphys::sim_command_t c{};
  c.utime = msg::now_utime();
  c.seq = ++command_seq_;
  c.sender = std::string("renderer@") + std::to_string(getpid());
  c.command = command;
  if (command == arphys::sim_command_t::COMMAND_SPAWN) {
    std::uniform_real_distribution<double> spread(-0.1, 0.1);
    c.model = options_.spawn_model;
    const double x = spread(spawn_rng_);
    const geometry::Pose X = geometry::make_pose({x, -0.3, 0.3}, {0.7071067811865476, 0.7071067811865476, 0, 0});
    c.X_WB = msg::to_message(X);
    const double vx = spread(spawn_rng_);
    const double v[3] = {vx, 0.8, 0.5};
    std::copy(v, v + 3, c.v_WB_m_s);
  }
  bus_.publish(scene_.channels.sim_command, c);
}

void LiveRenderer::publish_heartbeat(Clock::time_point now) {
  const double window_s = std::chrono::duration<double>(now - last_status_).count();
  arphys::process_status_t status =
      msg::heartbeat("renderer", renderer_.describe(), std::chrono::duration<double>(now - start_).count(), bus_);
  status.rate_hz = rendered_since_status_ / window_s;
  status.stage_duration_ms = rendered_since_status_ ? render_ms_since_status_ / rendered_since_status_ : 0.0;
  status.published = published_;
  status.dropped = schedule_.dropped();
  status.decode_errors += bad_.count("undecodable image");
  status.rejected += bad_.total() - bad_.count("undecodable image");
  status.state = rendered_since_status_ == 0 ? "waiting for camera frames"
                                             : (states_.empty() ? "drawing camera frames only: no world state" : "rendering");
  for (const auto& [kind, count] : bad_.counts) msg::add_figure(status, kind, static_cast<double>(count));
  msg::add_figure(status, "frames_without_world_state", static_cast<double>(without_world_));
  if (schedule_.waits()) msg::add_figure(status, "frames_past_the_wait", static_cast<double>(schedule_.past_the_wait()));
  bus_.publish(scene_.channels.process_status, status);
  last_status_ = now;
  rendered_since_status_ = 0;
  render_ms_since_status_ = 0;
}

void LiveRenderer::run() {
  std::fprintf(stderr, "renderer: scene %s, camera %s (%dx%d), match %s, wait %.0f ms, %s, LCM %s\n", scene_.name.c_str(),
               options_.camera_path.c_str(), projection_.width_px, projection_.height_px, to_string(options_.policy),
               options_.wait_ms, renderer_.describe().c_str(), bus_.url().c_str());
  while (!g_stop) {
    if (options_.duration_s > 0 && std::chrono::duration<double>(Clock::now() - start_).count() > options_.duration_s) break;
    // While a frame waits, woken by any message (its world state among them) or at its deadline.
    const double waiting_ms = schedule_.wait_left_ms(Clock::now());
    bus_.handle_timeout_ms(waiting_ms > 0 ? std::clamp(static_cast<int>(std::ceil(waiting_ms)), 1, 20) : 20);
    bus_.handle_pending();
    for (const arphys::image_t& frame : schedule_.take_due(Clock::now())) draw(frame);
    const auto now = Clock::now();
    if (now - last_status_ >= std::chrono::seconds(1)) publish_heartbeat(now);
  }
  std::fprintf(stderr, "renderer: %lld frames rendered, %lld dropped (newer frame waiting), %lld without a world state, "
               "%lld drawn at the wait's end without their own, %lld bad inputs\n",
               static_cast<long long>(rendered_), static_cast<long long>(schedule_.dropped()),
               static_cast<long long>(without_world_), static_cast<long long>(schedule_.past_the_wait()),
               static_cast<long long>(bad_.total()));
}

}  // namespace

int run_live(const config::SceneConfig& scene, const CameraProjection& projection, const LiveOptions& options) {
  std::unique_ptr<LiveRenderer> live;
  try {
    live = std::make_unique<LiveRenderer>(scene, projection, options);
    live->subscribe();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "renderer: %s\n", e.what());
    return 2;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  live->run();
  return 0;
}

}  // namespace arphys::rendering
