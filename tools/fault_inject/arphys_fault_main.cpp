// arphys-fault: hostile traffic for a running pipeline, on the loopback only (the URL
// must keep ttl=0). Per second, for --duration seconds, it sends on the scene's channels:
// random bytes and truncated copies of real messages (every channel), images of the
// wrong size, undecodable JPEGs and unknown pixel formats, tracked poses with NaN, inf,
// non-unit quaternions and unknown objects, sequence numbers going backwards and
// repeating, camera frames replayed and older, a flood of spawn requests beyond every limit (count, distance, speed), and
// bursts of images at ten times the camera's rate. What each process does with it shows
// in its heartbeat counters; the processes must not crash, hang or publish NaN.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <thread>

#include "arphys/image_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/sim_command_t.hpp"
#include "arphys/tracker_control_t.hpp"
#include "arphys/world_state_t.hpp"
#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"

namespace {

using namespace arphys;

arphys::image_t gray_image(int64_t utime, int64_t seq, int width, int height, uint8_t value) {
  arphys::image_t image{};
  image.utime = utime;
  image.seq = seq;
  image.camera_id = "fault";
  image.width = width;
  image.height = height;
  image.row_stride = width;
  image.pixel_format = arphys::image_t::PIXEL_FORMAT_GRAY8;
  image.data.assign(static_cast<std::size_t>(width) * height, value);
  image.size = static_cast<int32_t>(image.data.size());
  return image;
}

arphys::object_poses_t poses(int64_t utime, int64_t seq, const std::string& object, const double p[3], const double q[4]) {
  arphys::object_poses_t m{};
  m.utime = utime;
  m.seq = seq;
  m.camera_id = "fault";
  m.tracker_implementation = "arphys-fault";
  arphys::object_pose_t o{};
  o.object_id = object;
  o.status = arphys::object_pose_t::STATUS_TRACKED;
  o.world_valid = true;
  for (int i = 0; i < 3; ++i) o.X_WO.position_m[i] = p[i];
  for (int i = 0; i < 4; ++i) o.X_WO.orientation_wxyz[i] = q[i];
  o.X_CO = o.X_WO;
  m.objects.push_back(o);
  m.num_objects = 1;
  return m;
}

// One round of every fault on the scene's channels, counting what it sent.
class FaultRounds {
 public:
  FaultRounds(msg::Bus& bus, const config::ChannelNames& channels, uint32_t seed)
      : bus_(bus), ch_(channels), rng_(seed) {}
  void round(long round, int64_t now) {
    junk(round, now);
    bad_images(round, now);
    bad_poses(round, now);
    spawn_flood(round, now);
    replays(round, now);
    if (round % 10 == 0) burst(round, now);
  }
  const std::map<std::string, long>& sent() const { return sent_; }

 private:
  void junk(long round, int64_t now) {
    for (const std::string& channel : {ch_.camera_image, ch_.object_poses, ch_.world_state, ch_.sim_command,
                                       ch_.tracker_control, ch_.marker_detections, ch_.render_status}) {
      std::vector<uint8_t> junk(1 + byte(rng_) * 4);
      for (auto& b : junk) b = static_cast<uint8_t>(byte(rng_));
      raw(channel, junk, "random bytes");
    }
    std::vector<uint8_t> truncated = msg::encode(poses(now, 1000000 + round, "box", box, unit));
    truncated.resize(truncated.size() / 2);
    raw(ch_.object_poses, truncated, "truncated poses");
  }
  void bad_images(long round, int64_t now) {
    arphys::image_t image = gray_image(now, round, 320, 240, 90);
    bus_.publish(ch_.camera_image, image);
    ++sent_["image of the wrong size"];
    image.pixel_format = arphys::image_t::PIXEL_FORMAT_JPEG;
    image.data.assign(64, 0xff);
    image.size = 64;
    bus_.publish(ch_.camera_image, image);
    ++sent_["undecodable JPEG"];
    image.pixel_format = 42;
    bus_.publish(ch_.camera_image, image);
    ++sent_["unknown pixel format"];
  }
  void bad_poses(long round, int64_t now) {
    bus_.publish(ch_.object_poses, poses(now, 2000000 + 4 * round, "box", nan_p, unit));
    bus_.publish(ch_.object_poses, poses(now, 2000000 + 4 * round + 1, "box", inf_p, unit));
    bus_.publish(ch_.object_poses, poses(now, 2000000 + 4 * round + 2, "box", box, stretched));
    bus_.publish(ch_.object_poses, poses(now, 2000000 + 4 * round + 3, "box", box, nan_q));
    sent_["NaN/inf/non-unit poses"] += 4;
    bus_.publish(ch_.object_poses, poses(now, 3000000 + round, "ghost", box, unit));
    ++sent_["unknown object"];
    bus_.publish(ch_.object_poses, poses(now - 10000000, 1, "box", box, unit));  // seq and time going back
    bus_.publish(ch_.object_poses, poses(now - 10000000, 1, "box", box, unit));  // and repeated
    sent_["backwards/repeated frames"] += 2;
  }
  void spawn_flood(long round, int64_t now) {
    for (int k = 0; k < 5; ++k) {
      arphys::sim_command_t c{};
      c.utime = now;
      c.seq = round * 5 + k + 1;
      c.sender = "arphys-fault";
      c.command = arphys::sim_command_t::COMMAND_SPAWN;
      c.model = k == 0 ? "no-such-model" : "bunny";
      c.X_WB.orientation_wxyz[0] = 1;
      c.X_WB.position_m[0] = k == 1 ? 1000.0 : 0.0;  // far away
      c.X_WB.position_m[2] = 0.3;
      c.v_WB_m_s[0] = k == 2 ? 1000.0 : 0.0;  // too fast
      bus_.publish(ch_.sim_command, c);
      ++sent_["spawn requests"];
    }
    // A tracker control message asking for nonsense.
    arphys::tracker_control_t control{};
    control.utime = now;
    control.implementation = "no-such-detector";
    bus_.publish(ch_.tracker_control, control);
    ++sent_["bad tracker controls"];
  }
  void replays(long round, int64_t now) {
    arphys::image_t frame = gray_image(now, 6000000 + round, 640, 480, 100);
    frame.camera_id = "fault-replay";
    bus_.publish(ch_.camera_image, frame);
    bus_.publish(ch_.camera_image, frame);
    frame.utime -= 1000000;
    frame.seq -= 1;
    bus_.publish(ch_.camera_image, frame);
    sent_["replayed/older camera frames"] += 2;
  }
  void burst(long round, int64_t now) {
    arphys::image_t frame = gray_image(now, 0, 640, 480, 128);
    for (int k = 0; k < 10; ++k) {
      frame.seq = 5000000 + round * 10 + k;
      bus_.publish(ch_.camera_image, frame);
    }
    sent_["burst frames"] += 10;
  }
  void raw(const std::string& channel, const std::vector<uint8_t>& bytes, const char* what) {
    bus_.publish_raw(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
    ++sent_[what];
  }

  msg::Bus& bus_;
  const config::ChannelNames& ch_;
  std::mt19937 rng_;
  std::uniform_int_distribution<int> byte{0, 255};
  std::map<std::string, long> sent_;
  static constexpr double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  static constexpr double unit[4] = {1, 0, 0, 0}, stretched[4] = {2, 0, 0, 0}, nan_q[4] = {nan, 0, 0, 0};
  static constexpr double box[3] = {0.25, 0, 0.075}, nan_p[3] = {nan, 0, 0}, inf_p[3] = {inf, 0, 0};
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys-fault: hostile LCM traffic for a running pipeline (loopback only), to test what each process\n"
               "does with it. Counts what it sent; the processes' heartbeats count what they refused."};
  std::string scene_path = config::default_config_dir() + "/scenes/bunny_box_table.yaml", url;
  double duration_s = 5, rate_hz = 20;
  uint32_t seed = 1;
  app.add_option("--scene", scene_path, "scene YAML (its channels)")->capture_default_str();
  app.add_option("--lcm-url", url, "LCM URL (must have ttl=0; default: the scene's)");
  app.add_option("--duration", duration_s, "seconds of faults")->capture_default_str();
  app.add_option("--rate", rate_hz, "fault rounds per second")->capture_default_str();
  app.add_option("--seed", seed, "random seed")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  config::SceneConfig scene;
  std::unique_ptr<msg::Bus> bus;
  try {
    scene = config::load_scene(scene_path);
    if (url.empty()) url = scene.lcm_url;
    if (url.rfind("udpm://", 0) == 0 && url.find("ttl=0") == std::string::npos) {
      throw std::invalid_argument("refusing " + url + ": hostile traffic stays on this host (ttl=0)");
    }
    bus = std::make_unique<msg::Bus>(url);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arphys-fault: %s\n", e.what());
    return 2;
  }
  FaultRounds faults(*bus, scene.channels, seed);
  const auto start = std::chrono::steady_clock::now();
  for (long round = 0;; ++round) {
    const auto due = start + std::chrono::duration<double>(round / rate_hz);
    if (std::chrono::duration<double>(due - start).count() > duration_s) break;
    std::this_thread::sleep_until(due);
    faults.round(round, msg::now_utime());
  }
  for (const auto& [what, count] : faults.sent()) std::printf("%-26s %ld\n", what.c_str(), count);
  return 0;
}
