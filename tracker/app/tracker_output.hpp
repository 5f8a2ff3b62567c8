#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "arphys/marker_detections_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "tracker/pipeline/tracker_pipeline.hpp"

namespace arphys::tracking {

// The JSON line of one frame (the `tracker --json` contract): corners in OpenCV's pixel
// convention, poses camera-from-marker and camera-from-object.
nlohmann::json frame_json(const FrameReport& report, int64_t frame_index);

// A short human line per frame (`--print`).
std::string frame_summary(const FrameReport& report);

arphys::marker_detections_t detections_message(const FrameReport& report, const std::string& camera_id);
arphys::object_poses_t poses_message(const FrameReport& report, const std::string& camera_id);

}  // namespace arphys::tracking
