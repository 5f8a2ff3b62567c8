#pragma once
// Overlay registration error against the synthetic camera's ground truth: for every
// frame the renderer drew, how far (pixels) the tracked real object is drawn from where
// it truly is in that frame. The drawn pose is the object's pose in the world state the
// renderer used for the frame (render_status_t names it by simulation time); the true
// pose and camera come from ground_truth_t of the same capture time. The error of an
// overlay is the RMS image distance of the object's bounding-box corners, so it holds
// tracking error, the tracking policy's delay and the frame the renderer matched.
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "arphys/ground_truth_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/world_state_t.hpp"
#include "configs/loader/camera_config.hpp"

namespace arphys::tools {

class RegistrationReport {
 public:
  // object_id: the tracked real object measured; corners_O: points of it (object frame).
  RegistrationReport(config::CameraConfig camera, std::string object_id, std::vector<Eigen::Vector3d> corners_O);

  void on_ground_truth(const arphys::ground_truth_t& m);
  void on_world_state(const arphys::world_state_t& m);
  void on_render_status(const arphys::render_status_t& m);

  // {"object", "count", "p50_px", "p95_px", "max_px"}
  nlohmann::json to_json() const;
  const std::vector<double>& errors_px() const { return errors_px_; }

 private:
  config::CameraConfig camera_;
  std::string object_id_;
  std::vector<Eigen::Vector3d> corners_O_;
  struct Truth {
    Eigen::Isometry3d X_WC, X_WO;
  };
  std::map<int64_t, Truth> truth_by_capture_;              // bounded: newest 600 frames
  std::deque<std::pair<double, Eigen::Isometry3d>> drawn_;  // (sim time, X_WO) of recent world states
  std::vector<double> errors_px_;
};

}  // namespace arphys::tools
