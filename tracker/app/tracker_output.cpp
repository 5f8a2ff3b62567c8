#include "tracker/app/tracker_output.hpp"

#include <iomanip>
#include <sstream>

#include "lcmtypes/msg/clock.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"

namespace arphys::tracking {

namespace {

void put_pose(nlohmann::json& j, const Pose& X) {
  const arphys::pose_t p = msg::to_message(X);
  j["position_m"] = {p.position_m[0], p.position_m[1], p.position_m[2]};
  j["orientation_wxyz"] = {p.orientation_wxyz[0], p.orientation_wxyz[1], p.orientation_wxyz[2], p.orientation_wxyz[3]};
}

int8_t status_code(TrackStatus s) {
  switch (s) {
    case TrackStatus::kTracked: return arphys::object_pose_t::STATUS_TRACKED;
    case TrackStatus::kPredicted: return arphys::object_pose_t::STATUS_PREDICTED;
    case TrackStatus::kLost: return arphys::object_pose_t::STATUS_LOST;
  }
  return arphys::object_pose_t::STATUS_LOST;
}

// Both per-frame messages start with the same frame identity and stage times.
template <class Message>
Message message_with_header(const FrameReport& report, const std::string& camera_id) {
  Message out{};
  out.utime = report.capture_utime;
  out.seq = report.seq;
  out.camera_id = camera_id;
  out.tracker_implementation = report.implementation;
  out.detect_start_utime = report.detect_start_utime;
  out.detect_end_utime = report.detect_end_utime;
  return out;
}

}  // namespace

nlohmann::json frame_json(const FrameReport& report, int64_t frame_index) {
  nlohmann::json j;
  j["frame"] = frame_index;
  if (!report.name.empty()) j["source"] = report.name;
  j["utime"] = report.capture_utime;
  j["detect_ms"] = report.detect_ms;
  j["markers"] = nlohmann::json::array();
  for (const auto& m : report.result.markers) {
    nlohmann::json marker;
    marker["family"] = m.marker.family;
    marker["id"] = m.marker.id;
    marker["corners"] = nlohmann::json::array();
    for (const auto& c : m.marker.corners_px) marker["corners"].push_back({c.x(), c.y()});
    if (m.has_pose) {
      put_pose(marker, m.X_CM);
      marker["reprojection_error_px"] = m.rms_px;
    }
    if (!m.owner.empty()) marker["object"] = m.owner;
    if (m.rejected) marker["rejected"] = true;
    j["markers"].push_back(marker);
  }
  j["objects"] = nlohmann::json::array();
  for (const auto& o : report.result.objects) {
    nlohmann::json object;
    object["id"] = o.id;
    object["status"] = to_string(o.status);
    if (!o.reason.empty()) object["reason"] = o.reason;
    if (!o.rejected_marker_ids.empty()) object["markers_rejected"] = o.rejected_marker_ids;
    if (o.status != TrackStatus::kLost) {
      put_pose(object, o.X_CO);
      object["markers_used"] = o.marker_ids;
      object["reprojection_error_px"] = o.rms_px;
      object["position_sigma_m"] = o.position_sigma_m;
      object["rotation_sigma_rad"] = o.rotation_sigma_rad;
    }
    j["objects"].push_back(object);
  }
  return j;
}

std::string frame_summary(const FrameReport& report) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(4);
  out << "frame " << report.seq << (report.name.empty() ? "" : " (" + report.name + ")") << ": "
      << report.result.markers.size() << " markers, detect " << std::setprecision(2) << report.detect_ms << " ms";
  out.precision(4);
  for (const auto& o : report.result.objects) {
    out << " | " << o.id << " " << to_string(o.status);
    if (o.status == TrackStatus::kLost) continue;
    const Eigen::Vector3d p = o.world_valid ? o.X_WO.translation() : o.X_CO.translation();
    out << (o.world_valid ? " W[" : " C[") << p.x() << " " << p.y() << " " << p.z() << "] m";
  }
  return out.str();
}

arphys::marker_detections_t detections_message(const FrameReport& report, const std::string& camera_id) {
  auto out = message_with_header<arphys::marker_detections_t>(report, camera_id);
  for (const auto& m : report.result.markers) {
    arphys::marker_detection_t d{};
    d.family = m.marker.family;
    d.id = m.marker.id;
    for (int k = 0; k < 4; ++k) {
      d.corners_px[k][0] = m.marker.corners_px[k].x();
      d.corners_px[k][1] = m.marker.corners_px[k].y();
    }
    d.marker_size_m = m.size_m;
    d.X_CM = msg::to_message(m.has_pose ? m.X_CM : Pose::Identity());
    d.reprojection_error_px = m.has_pose ? m.rms_px : -1.0;
    d.ambiguity_ratio = m.ambiguity_ratio;
    d.decision_margin = m.marker.decision_margin;
    d.hamming = m.marker.hamming;
    out.markers.push_back(d);
  }
  out.num_markers = static_cast<int32_t>(out.markers.size());
  out.publish_utime = msg::now_utime();
  return out;
}

arphys::object_poses_t poses_message(const FrameReport& report, const std::string& camera_id) {
  auto out = message_with_header<arphys::object_poses_t>(report, camera_id);
  out.camera_world_valid = report.result.camera_world_valid;
  out.X_WC = msg::to_message(report.result.X_WC);
  for (const auto& o : report.result.objects) {
    arphys::object_pose_t p{};
    p.object_id = o.id;
    p.status = status_code(o.status);
    p.X_CO = msg::to_message(o.X_CO);
    p.world_valid = o.world_valid;
    p.X_WO = msg::to_message(o.X_WO);
    p.marker_ids = o.marker_ids;
    p.num_markers_used = static_cast<int32_t>(o.marker_ids.size());
    p.rejected_marker_ids = o.rejected_marker_ids;
    p.num_markers_rejected = static_cast<int32_t>(o.rejected_marker_ids.size());
    p.status_reason = o.reason;
    p.reprojection_error_px = o.rms_px;
    p.position_error_m = o.position_sigma_m;
    p.rotation_error_rad = o.rotation_sigma_rad;
    p.last_seen_utime = o.last_seen_utime;
    out.objects.push_back(p);
  }
  out.num_objects = static_cast<int32_t>(out.objects.size());
  out.publish_utime = msg::now_utime();
  return out;
}

}  // namespace arphys::tracking
