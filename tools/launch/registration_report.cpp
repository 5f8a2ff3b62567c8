#include "tools/launch/registration_report.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>

#include "lcmtypes/msg/pose_conversions.hpp"

namespace arphys::tools {

RegistrationReport::RegistrationReport(config::CameraConfig camera, std::string object_id,
                                       std::vector<Eigen::Vector3d> corners_O)
    : camera_(std::move(camera)), object_id_(std::move(object_id)), corners_O_(std::move(corners_O)) {}

void RegistrationReport::on_ground_truth(const arphys::ground_truth_t& m) {
  for (int i = 0; i < m.num_objects; ++i) {
    if (m.object_ids[i] != object_id_) continue;
    try {
      truth_by_capture_[m.utime] = {msg::from_message(m.X_WC, "X_WC"), msg::from_message(m.X_WO[i], object_id_)};
    } catch (const std::exception&) {
      return;  // a malformed truth message measures nothing
    }
  }
  while (truth_by_capture_.size() > 600) truth_by_capture_.erase(truth_by_capture_.begin());
}

void RegistrationReport::on_world_state(const arphys::world_state_t& m) {
  for (const auto& b : m.bodies) {
    if (b.body_id != object_id_) continue;
    try {
      drawn_.emplace_back(m.sim_time_s, msg::from_message(b.X_WB, object_id_));
    } catch (const std::exception&) {
      return;
    }
  }
  while (drawn_.size() > 2000) drawn_.pop_front();
}

void RegistrationReport::on_render_status(const arphys::render_status_t& m) {
  if (m.world_state_match == arphys::render_status_t::MATCH_NONE) return;
  const auto truth = truth_by_capture_.find(m.utime);
  if (truth == truth_by_capture_.end()) return;
  const auto drawn = std::find_if(drawn_.rbegin(), drawn_.rend(), [&](const auto& s) {
    return std::abs(s.first - m.world_state_sim_time_s) < 1e-9;
  });
  if (drawn == drawn_.rend()) return;
  const Eigen::Isometry3d X_CW = truth->second.X_WC.inverse();
  double sum_sq = 0;
  for (const Eigen::Vector3d& p_O : corners_O_) {
    // Where the camera shows the point: through its lens, as the frame and the overlay do.
    auto pixel = [&](const Eigen::Isometry3d& X_WO) {
      const Eigen::Vector3d p_C = X_CW * (X_WO * p_O);
      if (!camera_.has_distortion())
        return Eigen::Vector2d(camera_.fx_px * p_C.x() / p_C.z() + camera_.cx_px, camera_.fy_px * p_C.y() / p_C.z() + camera_.cy_px);
      std::vector<cv::Point2d> uv;
      cv::projectPoints(std::vector<cv::Point3d>{{p_C.x(), p_C.y(), p_C.z()}}, cv::Vec3d::all(0), cv::Vec3d::all(0),
                        cv::Matx33d(camera_.fx_px, 0, camera_.cx_px, 0, camera_.fy_px, camera_.cy_px, 0, 0, 1),
                        camera_.distortion, uv);
      return Eigen::Vector2d(uv[0].x, uv[0].y);
    };
    sum_sq += (pixel(drawn->second) - pixel(truth->second.X_WO)).squaredNorm();
  }
  errors_px_.push_back(std::sqrt(sum_sq / corners_O_.size()));
}

nlohmann::json RegistrationReport::to_json() const {
  nlohmann::json j{{"object", object_id_}, {"count", errors_px_.size()}};
  if (errors_px_.empty()) return j;
  std::vector<double> v = errors_px_;
  std::sort(v.begin(), v.end());
  auto q = [&](double p) { return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))]; };
  j["p50_px"] = q(0.5);
  j["p95_px"] = q(0.95);
  j["max_px"] = v.back();
  return j;
}

}  // namespace arphys::tools
