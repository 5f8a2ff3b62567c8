#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "arphys/image_t.hpp"
#include "arphys/marker_detections_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/world_state_t.hpp"

namespace arphys::tools {

// Per-stage latency of the pipeline, from the stamps the messages carry (capture utime,
// detection end, publish, render end), so it reads live traffic and log files alike:
// capture -> detection end, detection -> pose published, pose -> first world state of
// that frame, world state -> overlay drawn with it (exact matches), capture -> overlay end.
class LatencyReport {
 public:
  void on_image(const arphys::image_t& m);
  void on_detections(const arphys::marker_detections_t& m);
  void on_poses(const arphys::object_poses_t& m);
  void on_world_state(const arphys::world_state_t& m);
  void on_render_status(const arphys::render_status_t& m);

  // {"stages": {name: {count, p50_ms, p95_ms, p99_ms, max_ms}}, "frames": {...}}
  nlohmann::json to_json() const;
  void print() const;  // a table on stdout
  void write_samples_csv(const std::string& path) const;  // stage,ms per sample
  // Frame messages counted so far (images, poses, first world states of a frame, renders):
  // once the source has stopped, the pipeline has carried its last frame through when this
  // stops growing.
  int64_t frame_messages() const { return images_ + poses_ + static_cast<int64_t>(world_publish_.size()) + renders_; }

 private:
  struct Stage {
    std::string name;
    std::vector<double> samples_ms;
  };
  Stage capture_to_detection_{"capture_to_detection", {}}, detection_to_pose_{"detection_to_pose", {}},
      pose_to_world_{"pose_to_world_state", {}}, world_to_overlay_{"world_state_to_overlay", {}},
      end_to_end_{"capture_to_overlay", {}};
  std::vector<const Stage*> stages() const {
    return {&capture_to_detection_, &detection_to_pose_, &pose_to_world_, &world_to_overlay_, &end_to_end_};
  }
  std::map<int64_t, int64_t> poses_publish_, world_publish_;
  int64_t images_ = 0, poses_ = 0, renders_ = 0, renders_exact_ = 0;
};

}  // namespace arphys::tools
