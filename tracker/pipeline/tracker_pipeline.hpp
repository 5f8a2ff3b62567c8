#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "tracker/detection/marker_detector.hpp"
#include "tracker/sources/frame_source.hpp"
#include "tracker/tracking/object_tracker.hpp"

namespace arphys::tracking {

// What the tracker made of one frame.
struct FrameReport {
  int64_t capture_utime = 0;
  int64_t seq = 0;
  std::string name;            // file name for folder sources
  std::string implementation;  // detector implementation and parameters in short
  int64_t detect_start_utime = 0;
  int64_t detect_end_utime = 0;
  double detect_ms = 0;  // detection alone
  double pose_ms = 0;    // pose estimation and tracking
  TrackingResult result;
};

struct PipelineCounters {
  int64_t frames = 0;             // frames processed
  int64_t wrong_size = 0;         // skipped: size differs from the camera calibration
  int64_t wrong_format = 0;       // skipped: not 8-bit grey/BGR/BGRA
  int64_t unknown_markers = 0;    // detections of markers no object declares (ignored)
  int64_t rejected_poses = 0;     // object or camera fits the pose filter dropped as outliers
  int64_t rejected_markers = 0;   // owned markers left out of their object's fit (disagreeing)
  int64_t poor_fits = 0;          // object fits above the tracker's max_fit_rms_px (not TRACKED)
  int64_t unrefined_corners = 0;  // detections whose edges could not refine the corners (kept as detected)
  int64_t detector_switches = 0;  // implementation changes at run time
  int64_t rejected_controls = 0;  // switch or parameter requests refused
};

// Frame in, poses out: checks the frame against the calibration, converts to grey,
// detects, estimates poses. Holds the detector so it can be replaced between frames
// (live swap) without losing the tracks. No LCM here: the executable wires it.
class TrackerPipeline {
 public:
  // refine_corners: refine every detection's corners from its edges
  // (detection/edge_refinement.hpp), which cuts corner noise 2-8x for either detector.
  TrackerPipeline(std::unique_ptr<MarkerDetector> detector, ObjectTracker tracker, bool refine_corners = true);

  // nullopt when the frame was refused (counted in counters()). independent: the frame
  // is unrelated to the previous one (folder of photos), so no prediction is used.
  std::optional<FrameReport> process(const Frame& frame, bool independent = false);

  // Replaces the detector (new implementation and parameters). On a bad request the
  // old detector stays and std::invalid_argument says why.
  void switch_detector(const DetectorSpec& spec);
  // Sets one parameter of the current detector; throws std::invalid_argument if refused.
  void set_detector_param(const std::string& name, const std::string& value);

  const MarkerDetector& detector() const { return *detector_; }
  const ObjectTracker& tracker() const { return tracker_; }
  const PipelineCounters& counters() const { return counters_; }
  void count_rejected_control() { ++counters_.rejected_controls; }

 private:
  std::unique_ptr<MarkerDetector> detector_;
  ObjectTracker tracker_;
  PipelineCounters counters_;
  bool refine_corners_ = true;
  cv::Mat gray_;
};

// The marker families a scene's objects use (tag36h11 when it declares none).
std::vector<std::string> families_of(const TrackerModel& model);

}  // namespace arphys::tracking
