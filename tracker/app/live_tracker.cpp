#include "tracker/app/live_tracker.hpp"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "arphys/image_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/tracker_control_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "lcmtypes/msg/image_message.hpp"
#include "tracker/app/lcm_image_source.hpp"
#include "tracker/app/tracker_output.hpp"

namespace arphys::tracking {
namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

class LiveTracker {
 public:
  LiveTracker(const config::SceneConfig& scene, const config::CameraConfig& camera, TrackerPipeline& pipeline,
              const RunOptions& options)
      : scene_(scene),
        camera_(camera),
        pipeline_(pipeline),
        options_(options),
        lcm_source_(options.source.rfind("lcm:", 0) == 0),
        camera_id_(camera.camera_id.empty() ? "camera" : camera.camera_id) {}

  // Opens the bus (when needed) and the source; false (reason printed) when either fails.
  bool open();
  void subscribe_control();
  // Returns the exit code.
  int run();

 private:
  // False when the frame shows the camera is not the one calibrated.
  bool track(const Frame& frame);
  void wait_for_turn(const Frame& frame);
  void publish_heartbeat(Clock::time_point now);
  void print_summary() const;

  const config::SceneConfig& scene_;
  const config::CameraConfig& camera_;
  TrackerPipeline& pipeline_;
  RunOptions options_;
  const bool lcm_source_;
  const std::string camera_id_;
  std::unique_ptr<msg::Bus> bus_;
  std::unique_ptr<FrameSource> frames_;
  LcmImageSource* lcm_frames_ = nullptr;
  Clock::time_point start_ = Clock::now(), last_status_ = start_;
  int64_t frame_index_ = 0, published_ = 0, frames_since_status_ = 0;
  double detect_ms_since_status_ = 0;
  std::optional<int64_t> paced_first_utime_;  // --pace: the first frame's time and when it was shown
  Clock::time_point paced_start_;
};

bool LiveTracker::open() {
  if (!options_.no_lcm || lcm_source_) {
    try {
      bus_ = std::make_unique<msg::Bus>(options_.lcm_url.empty() ? scene_.lcm_url : options_.lcm_url);
    } catch (const std::exception& e) {
      if (lcm_source_ || !options_.json) {
        std::fprintf(stderr, "tracker: %s\n", e.what());
        return false;
      }
      std::fprintf(stderr, "tracker: LCM unavailable, JSON only (%s)\n", e.what());
    }
  }
  try {
    if (lcm_source_) {
      auto source = std::make_unique<LcmImageSource>(*bus_, options_.source.substr(4));
      lcm_frames_ = source.get();
      frames_ = std::move(source);
    } else {
      frames_ = open_frame_source(options_.source, options_.fps, options_.width, options_.height, options_.camera_fps);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tracker: %s\n", e.what());
    return false;
  }
  return true;
}

// A control message switches the detector or sets its parameters; a bad one leaves the
// detector as it was and is counted.
void LiveTracker::subscribe_control() {
  if (!bus_) return;
  bus_->subscribe<arphys::tracker_control_t>(
      scene_.channels.tracker_control, [&](const arphys::tracker_control_t& m, const lcm::ReceiveBuffer&, const std::string&) {
        if (!m.target.empty() && m.target != options_.name) return;
        try {
          if (m.param_names.size() != m.param_values.size()) throw std::invalid_argument("names and values differ in count");
          if (!m.implementation.empty()) {
            DetectorSpec spec;
            spec.implementation = m.implementation;
            for (size_t i = 0; i < m.param_names.size(); ++i) spec.params.emplace_back(m.param_names[i], m.param_values[i]);
            pipeline_.switch_detector(spec);
          } else {
            for (size_t i = 0; i < m.param_names.size(); ++i) pipeline_.set_detector_param(m.param_names[i], m.param_values[i]);
          }
          std::fprintf(stderr, "tracker: detector now %s\n", pipeline_.detector().describe().c_str());
        } catch (const std::exception& e) {
          pipeline_.count_rejected_control();
          std::fprintf(stderr, "tracker: control refused, detector unchanged: %s\n", e.what());
          throw;  // counted by the bus as a rejected message too
        }
      });
}

// Frame times of a file count from its first frame: waits for each one's turn.
void LiveTracker::wait_for_turn(const Frame& frame) {
  if (!paced_first_utime_) {
    paced_first_utime_ = frame.capture_utime;
    paced_start_ = Clock::now();
  }
  std::this_thread::sleep_until(paced_start_ + std::chrono::microseconds(frame.capture_utime - *paced_first_utime_));
}

bool LiveTracker::track(const Frame& frame) {
  if (frame_index_ == 0 && !lcm_source_ && (frame.image.cols != camera_.width_px || frame.image.rows != camera_.height_px)) {
    std::fprintf(stderr, "tracker: camera file %s is calibrated for %dx%d but %s gives %dx%d frames; refusing to "
                 "track with the wrong calibration\n",
                 options_.camera_path.c_str(), camera_.width_px, camera_.height_px, frames_->describe().c_str(),
                 frame.image.cols, frame.image.rows);
    return false;
  }
  if (bus_ && options_.publish_images && !lcm_source_) {
    bus_->publish(scene_.channels.camera_image, msg::encode_image_message(frame.image, frame.capture_utime, frame.seq, camera_id_));
  }
  const auto report = pipeline_.process(frame, frames_->frames_independent());
  if (report) {
    if (options_.json) std::cout << frame_json(*report, frame_index_).dump() << std::endl;
    if (options_.print) std::cout << frame_summary(*report) << std::endl;
    if (bus_) {
      bus_->publish(scene_.channels.marker_detections, detections_message(*report, camera_id_));
      bus_->publish(scene_.channels.object_poses, poses_message(*report, camera_id_));
      published_ += 2;
    }
    ++frames_since_status_;
    detect_ms_since_status_ += report->detect_ms;
  }
  ++frame_index_;
  return true;
}

void LiveTracker::publish_heartbeat(Clock::time_point now) {
  const double window_s = std::chrono::duration<double>(now - last_status_).count();
  const auto& c = pipeline_.counters();
  arphys::process_status_t status = msg::heartbeat(options_.name, pipeline_.detector().describe(),
                                                   std::chrono::duration<double>(now - start_).count(), *bus_);
  status.rate_hz = frames_since_status_ / window_s;
  status.stage_duration_ms = frames_since_status_ ? detect_ms_since_status_ / frames_since_status_ : 0.0;
  status.published = published_;
  status.dropped = lcm_frames_ ? lcm_frames_->dropped_frames() : 0;
  status.decode_errors += frames_->skipped_frames();
  const int64_t out_of_order = lcm_frames_ ? lcm_frames_->out_of_order_frames() : 0;
  status.rejected += c.wrong_size + c.wrong_format + out_of_order;
  status.state = frames_since_status_ ? "tracking" : "waiting for frames";
  const std::vector<std::pair<std::string, double>> figures = {
      {"frames", static_cast<double>(c.frames)},
      {"wrong_size_frames", static_cast<double>(c.wrong_size)},
      {"wrong_format_frames", static_cast<double>(c.wrong_format)},
      {"duplicate_or_out_of_order_frames", static_cast<double>(out_of_order)},
      {"unknown_markers", static_cast<double>(c.unknown_markers)},
      {"rejected_poses", static_cast<double>(c.rejected_poses)},
      {"rejected_markers", static_cast<double>(c.rejected_markers)},
      {"poor_fits", static_cast<double>(c.poor_fits)},
      {"detector_switches", static_cast<double>(c.detector_switches)},
      {"rejected_controls", static_cast<double>(c.rejected_controls)}};
  for (const auto& [n, v] : figures) msg::add_figure(status, n, v);
  bus_->publish(scene_.channels.process_status, status);
  last_status_ = now;
  frames_since_status_ = 0;
  detect_ms_since_status_ = 0;
}

void LiveTracker::print_summary() const {
  const auto& c = pipeline_.counters();
  const int64_t unreadable = frames_->skipped_frames();
  std::fprintf(stderr, "tracker: %lld frames, %lld skipped (size %lld, format %lld, unreadable %lld), %lld unknown "
               "markers ignored, %lld outlier poses dropped by the filter, %lld markers left out of fits, %lld fits above "
               "--max-fit-px, %lld detector switches, %lld controls refused\n",
               static_cast<long long>(c.frames), static_cast<long long>(c.wrong_size + c.wrong_format + unreadable),
               static_cast<long long>(c.wrong_size), static_cast<long long>(c.wrong_format),
               static_cast<long long>(unreadable), static_cast<long long>(c.unknown_markers),
               static_cast<long long>(c.rejected_poses), static_cast<long long>(c.rejected_markers),
               static_cast<long long>(c.poor_fits), static_cast<long long>(c.detector_switches),
               static_cast<long long>(c.rejected_controls));
}

int LiveTracker::run() {
  std::fprintf(stderr, "tracker: source %s, camera %s (%dx%d), %zu objects, detector %s%s\n",
               frames_->describe().c_str(), options_.camera_path.c_str(), camera_.width_px, camera_.height_px,
               pipeline_.tracker().model().objects.size(), pipeline_.detector().describe().c_str(),
               bus_ ? (", LCM " + bus_->url()).c_str() : "");
  start_ = last_status_ = Clock::now();
  while (!g_stop) {
    if (options_.duration_s > 0 && std::chrono::duration<double>(Clock::now() - start_).count() > options_.duration_s) break;
    if (options_.max_frames > 0 && frame_index_ >= options_.max_frames) break;
    if (bus_ && !lcm_source_) bus_->handle_pending();
    std::optional<Frame> frame = frames_->next(50);
    if (!frame && frames_->finished()) break;
    if (frame && options_.pace && !lcm_source_) wait_for_turn(*frame);
    if (frame && !track(*frame)) return 2;
    const auto now = Clock::now();
    if (bus_ && now - last_status_ >= std::chrono::seconds(1)) publish_heartbeat(now);
  }
  print_summary();
  return 0;
}

}  // namespace

int run_tracker(const config::SceneConfig& scene, const config::CameraConfig& camera, TrackerPipeline& pipeline,
                const RunOptions& options) {
  LiveTracker live(scene, camera, pipeline, options);
  if (!live.open()) return 2;
  live.subscribe_control();
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  return live.run();
}

}  // namespace arphys::tracking
