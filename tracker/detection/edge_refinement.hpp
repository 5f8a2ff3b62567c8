#pragma once
#include <opencv2/core.hpp>

#include "tracker/detection/marker_detector.hpp"

namespace arphys::tracking {

// Sub-pixel corner refinement from the marker's four outer edges, for any detector.
//
// A corner found locally is only as good as the few pixels around it (libapriltag
// ~0.08 px RMS, ArUco subpix ~0.24 px). The outer edge of a marker is a straight line
// (pinhole camera) with black on one side and the white quiet zone on the other, and
// every pixel along it says where it is: along each edge the crossing of the mid-level
// between the local black and white levels is found on the normal profile (bilinear
// samples), a line is fitted through those crossings, and the corners become the
// intersections of adjacent lines. Area-sampled pixels make the mid-level crossing of
// an ideal step unbiased.
//
// Returns false, leaving the marker unchanged, when an edge has too little contrast or
// too few usable samples, or a corner would move by more than max_shift_px.
bool refine_corners_on_edges(const cv::Mat& gray, DetectedMarker& marker, double max_shift_px = 1.5);

}  // namespace arphys::tracking
