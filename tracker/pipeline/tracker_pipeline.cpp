#include "tracker/pipeline/tracker_pipeline.hpp"

#include <algorithm>
#include <chrono>

#include <opencv2/imgproc.hpp>

#include "tracker/detection/edge_refinement.hpp"
#include "tracker/sources/wall_clock.hpp"

namespace arphys::tracking {

namespace {

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

std::vector<std::string> families_of(const TrackerModel& model) {
  std::vector<std::string> families;
  for (const auto& o : model.objects) {
    for (const auto& m : o.markers) {
      if (std::find(families.begin(), families.end(), m.family) == families.end()) families.push_back(m.family);
    }
  }
  if (families.empty()) families.push_back("tag36h11");
  return families;
}

TrackerPipeline::TrackerPipeline(std::unique_ptr<MarkerDetector> detector, ObjectTracker tracker, bool refine_corners)
    : detector_(std::move(detector)), tracker_(std::move(tracker)), refine_corners_(refine_corners) {}

std::optional<FrameReport> TrackerPipeline::process(const Frame& frame, bool independent) {
  const CameraModel& camera = tracker_.camera();
  if (frame.image.cols != camera.width_px || frame.image.rows != camera.height_px) {
    ++counters_.wrong_size;
    return std::nullopt;
  }
  switch (frame.image.type()) {
    case CV_8UC1: gray_ = frame.image; break;
    case CV_8UC3: cv::cvtColor(frame.image, gray_, cv::COLOR_BGR2GRAY); break;
    case CV_8UC4: cv::cvtColor(frame.image, gray_, cv::COLOR_BGRA2GRAY); break;
    default: ++counters_.wrong_format; return std::nullopt;
  }
  if (independent) {
    detector_->reset_prediction();
    tracker_.reset();
  }
  FrameReport report;
  report.capture_utime = frame.capture_utime;
  report.seq = frame.seq;
  report.name = frame.name;
  report.implementation = detector_->describe();
  report.detect_start_utime = wall_clock_utime();
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<DetectedMarker> markers = detector_->detect(gray_);
  if (refine_corners_) {
    for (auto& m : markers) counters_.unrefined_corners += refine_corners_on_edges(gray_, m) ? 0 : 1;
  }
  report.detect_ms = elapsed_ms(t0);
  const auto t1 = std::chrono::steady_clock::now();
  report.result = tracker_.update(markers, frame.capture_utime);
  report.pose_ms = elapsed_ms(t1);
  report.detect_end_utime = wall_clock_utime();
  ++counters_.frames;
  counters_.unknown_markers += report.result.unknown_markers;
  counters_.rejected_poses += report.result.rejected_poses;
  counters_.rejected_markers += report.result.rejected_markers;
  counters_.poor_fits += report.result.poor_fits;
  return report;
}

void TrackerPipeline::switch_detector(const DetectorSpec& spec) {
  DetectorSpec full = spec;
  if (full.families.empty()) full.families = detector_->families();
  detector_ = make_detector(full);  // throws before anything changes
  ++counters_.detector_switches;
}

void TrackerPipeline::set_detector_param(const std::string& name, const std::string& value) {
  detector_->set_param(name, value);
}

}  // namespace arphys::tracking
