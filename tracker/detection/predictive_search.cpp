#include "tracker/detection/predictive_search.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace arphys::tracking {

namespace {

bool same_marker(const DetectedMarker& a, const DetectedMarker& b) { return a.id == b.id && a.family == b.family; }

// Full-resolution corners replace coarse ones for the same marker.
void merge(std::vector<DetectedMarker>& found, std::vector<DetectedMarker>&& fine) {
  for (auto& m : fine) {
    auto it = std::find_if(found.begin(), found.end(), [&](const DetectedMarker& f) { return same_marker(f, m); });
    if (it != found.end()) {
      *it = std::move(m);
    } else {
      found.push_back(std::move(m));
    }
  }
}

// A search window around a marker: its bounds grown by half their size (inter-frame
// motion) and a quiet-zone margin.
cv::Rect window_around(const cv::Rect& b, const cv::Rect& frame) {
  const int grow = std::max(12, std::max(b.width, b.height) / 2);
  return cv::Rect(b.x - grow, b.y - grow, b.width + 2 * grow, b.height + 2 * grow) & frame;
}

}  // namespace

cv::Rect marker_bounds(const DetectedMarker& m) {
  double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
  for (const auto& c : m.corners_px) {
    x0 = std::min(x0, c.x());
    y0 = std::min(y0, c.y());
    x1 = std::max(x1, c.x());
    y1 = std::max(y1, c.y());
  }
  return cv::Rect(cv::Point(static_cast<int>(std::floor(x0)), static_cast<int>(std::floor(y0))),
                  cv::Point(static_cast<int>(std::ceil(x1)) + 1, static_cast<int>(std::ceil(y1)) + 1));
}

void PredictiveSearch::set_scan_tiles(int tiles) {
  if (tiles < 0 || tiles > 256) {
    throw std::invalid_argument("scan_tiles = " + std::to_string(tiles) + ": expected 0..256");
  }
  scan_tiles_ = tiles;
  next_tile_ = 0;
}

void PredictiveSearch::set_coarse_every(int frames) {
  if (frames < 1 || frames > 30) {
    throw std::invalid_argument("coarse_every = " + std::to_string(frames) + ": expected 1..30");
  }
  coarse_every_ = frames;
  frames_since_coarse_ = 0;
}

void PredictiveSearch::set_refine_coarse_below_px(int side_px) {
  if (side_px < 0 || side_px > 1000) {
    throw std::invalid_argument("refine_coarse_below_px = " + std::to_string(side_px) + ": expected 0..1000");
  }
  refine_coarse_below_px_ = side_px;
}

bool PredictiveSearch::follow_previous(const cv::Mat& gray, const RegionSearch& fine,
                                       std::vector<DetectedMarker>& found) const {
  const cv::Rect frame(0, 0, gray.cols, gray.rows);
  // (window, decimation): full resolution for markers too small for half of it.
  std::vector<std::pair<cv::Rect, int>> windows;
  for (const auto& m : previous_) {
    const cv::Rect b = marker_bounds(m);
    const cv::Rect w = window_around(b, frame);
    if (w.area() <= 0) return false;
    windows.emplace_back(w, std::max(b.width, b.height) < std::max(40, refine_coarse_below_px_) ? 1 : 2);
  }
  // Overlapping windows of one resolution are searched as their union, once.
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < windows.size() && !merged; ++i)
      for (std::size_t j = i + 1; j < windows.size() && !merged; ++j)
        if (windows[i].second == windows[j].second && (windows[i].first & windows[j].first).area() > 0) {
          windows[i].first |= windows[j].first;
          windows.erase(windows.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
  }
  for (const auto& [w, decimation] : windows) merge(found, fine(gray, w, decimation));
  return std::all_of(previous_.begin(), previous_.end(), [&](const DetectedMarker& m) {
    return std::any_of(found.begin(), found.end(), [&](const DetectedMarker& f) { return same_marker(f, m); });
  });
}

void PredictiveSearch::scan_tile(const cv::Mat& gray, const RegionSearch& fine, std::vector<DetectedMarker>& found) {
  // One scan tile per frame at full resolution, tiles overlapping by 32 px so that any
  // marker the coarse pass is too coarse for (< ~60 px) lies wholly inside one of them.
  if (scan_tiles_ <= 0) return;
  const cv::Rect frame(0, 0, gray.cols, gray.rows);
  const int columns = static_cast<int>(std::ceil(std::sqrt(scan_tiles_ * 4.0 / 3.0)));
  const int rows = (scan_tiles_ + columns - 1) / columns;
  const int tile = next_tile_ % (columns * rows);
  next_tile_ = (next_tile_ + 1) % (columns * rows);
  const int w = (gray.cols + columns - 1) / columns, h = (gray.rows + rows - 1) / rows;
  const int overlap = 32;
  const cv::Rect region =
      cv::Rect((tile % columns) * w - overlap, (tile / columns) * h - overlap, w + 2 * overlap, h + 2 * overlap) &
      frame;
  merge(found, fine(gray, region, 1));
}

std::vector<DetectedMarker> PredictiveSearch::detect(const cv::Mat& gray, const CoarseSearch& coarse,
                                                     const RegionSearch& fine) {
  const cv::Rect frame(0, 0, gray.cols, gray.rows);
  // Between coarse passes, last frame's markers are followed in their windows alone.
  if (coarse_every_ > 1 && !previous_.empty() && ++frames_since_coarse_ < coarse_every_) {
    std::vector<DetectedMarker> followed;
    if (follow_previous(gray, fine, followed)) {
      scan_tile(gray, fine, followed);
      previous_ = followed;
      return followed;
    }
  }
  frames_since_coarse_ = 0;
  std::vector<DetectedMarker> found = coarse(gray);
  // Small markers of the coarse pass found again at full resolution (detectors whose
  // coarse corners are too rough). Only the marker itself is taken from its window:
  // another one there is whole in the coarse pass or in its own window.
  for (auto& m : found) {
    const cv::Rect b = marker_bounds(m);
    if (std::max(b.width, b.height) >= refine_coarse_below_px_) continue;
    std::vector<DetectedMarker> again = fine(gray, window_around(b, frame), 1);
    auto it = std::find_if(again.begin(), again.end(), [&](const DetectedMarker& f) { return same_marker(f, m); });
    if (it != again.end()) m = std::move(*it);
  }
  // Markers of last frame that the coarse pass missed (too small for it) are searched
  // again in a window around their last corners, at full resolution for small markers
  // and half resolution for the others (full below refine_coarse_below_px).
  for (const auto& m : previous_) {
    if (std::any_of(found.begin(), found.end(), [&](const DetectedMarker& f) { return same_marker(f, m); })) continue;
    const cv::Rect b = marker_bounds(m);
    const int side = std::max(b.width, b.height);
    const cv::Rect w = window_around(b, frame);
    if (w.area() <= 0) continue;
    merge(found, fine(gray, w, side < std::max(40, refine_coarse_below_px_) ? 1 : 2));
  }
  scan_tile(gray, fine, found);
  previous_ = found;
  return found;
}

}  // namespace arphys::tracking
