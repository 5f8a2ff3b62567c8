#pragma once
// The tracker's detectors on real photos: the apriltag repository's three 799x533 JPEGs
// (tests/data/apriltag_photos, 47 tag36h11 detections as libapriltag finds them at
// decimation 1 without edge refinement). There is no ground truth, so what it measures is
// what real frames can say: the share of the reference detections each configuration
// finds, how far its corners sit from the reference's, how well one square marker's pose
// explains its four corners (the RMS reprojection error of the single-marker fit with the
// nominal camera: real corner noise, plus what the nominal intrinsics get wrong, the same
// for every configuration), and the time per photo.
#include <string>
#include <vector>

#include "tracker/detection/marker_detector.hpp"

namespace arphys::bench {

struct PhotoConfig {
  std::string name;
  tracking::DetectorSpec spec;
  bool refine = true;
};

struct PhotoFigures {
  std::string config;
  int references = 0, found = 0, extra = 0;  // reference detections, those found within 1 px, ids beyond them
  double corner_offset_median_px = 0, corner_offset_p90_px = 0;  // from the reference's corners
  double reprojection_median_px = 0, reprojection_p90_px = 0;    // single-marker fits
  double median_ms = 0;
};

// Runs each configuration over the photos in `folder` (each NAME.jpg beside NAME.txt),
// timing `repeats` passes, with the camera file `camera_yaml`.
std::vector<PhotoFigures> photo_pass(const std::vector<PhotoConfig>& configs, const std::string& folder,
                                     const std::string& camera_yaml, int repeats);

}  // namespace arphys::bench
