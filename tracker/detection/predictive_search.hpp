#pragma once
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "tracker/detection/marker_detector.hpp"

namespace arphys::tracking {

// Where a video frame is searched, for any detector: the whole frame coarsely, windows
// around last frame's markers that the coarse pass missed, and one full-resolution scan
// tile per frame in turn, so that a small marker that appears anywhere is found within
// `scan_tiles` frames. The detector supplies the two searches; corner accuracy comes from
// the pipeline's edge refinement at full resolution, not from the search.
class PredictiveSearch {
 public:
  // Markers in `region` of the frame, corners in frame pixels, the region searched at
  // 1 / `decimation` of full resolution (1 or 2).
  using RegionSearch = std::function<std::vector<DetectedMarker>(const cv::Mat& gray, const cv::Rect& region, int decimation)>;
  // Markers in the whole frame at the detector's coarse resolution.
  using CoarseSearch = std::function<std::vector<DetectedMarker>(const cv::Mat& gray)>;

  explicit PredictiveSearch(int scan_tiles = 64) { set_scan_tiles(scan_tiles); }

  std::vector<DetectedMarker> detect(const cv::Mat& gray, const CoarseSearch& coarse, const RegionSearch& fine);
  void reset() {
    previous_.clear();
    frames_since_coarse_ = 0;
  }
  // Markers the coarse pass found with a side under `side_px` (full-resolution pixels)
  // are found again in a full-resolution window: for a detector whose coarse corners are
  // only as good as the coarse grid (ArUco's), a small marker's are too rough for the
  // pipeline's edge refinement and flip a lone marker's pose. 0 (the default) keeps them.
  void set_refine_coarse_below_px(int side_px);
  // 0 disables the scan; at most 256. Throws std::invalid_argument naming the value.
  void set_scan_tiles(int tiles);
  int scan_tiles() const { return scan_tiles_; }
  // The coarse whole-frame pass runs every `frames`-th frame (1: every frame) while last
  // frame's markers are all found again in windows around them; a frame that misses one
  // runs it at once. A new marker the scan tile does not catch is then found within
  // `frames` frames. 1..30; throws std::invalid_argument naming the value.
  void set_coarse_every(int frames);
  int coarse_every() const { return coarse_every_; }

 private:
  // Last frame's markers searched again in windows around them, merged where the windows
  // overlap (a board's markers share one); false when one of them was not found.
  bool follow_previous(const cv::Mat& gray, const RegionSearch& fine, std::vector<DetectedMarker>& found) const;
  void scan_tile(const cv::Mat& gray, const RegionSearch& fine, std::vector<DetectedMarker>& found);

  int scan_tiles_ = 64;
  int coarse_every_ = 1;
  int frames_since_coarse_ = 0;
  int refine_coarse_below_px_ = 0;
  int next_tile_ = 0;
  std::vector<DetectedMarker> previous_;
};

// The pixel bounds of a marker's corners (exclusive right and bottom).
cv::Rect marker_bounds(const DetectedMarker& m);

}  // namespace arphys::tracking
