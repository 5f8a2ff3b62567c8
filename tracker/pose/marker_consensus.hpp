#pragma once
#include <array>
#include <vector>

#include <Eigen/Core>

#include "tracker/pose/camera_model.hpp"
#include "tracker/pose/marker_pose.hpp"

namespace arphys::tracking {

// One seen marker of a rigid set: its corners in the set's frame O and in the image.
struct MarkerCorners {
  int id = 0;
  std::array<Eigen::Vector3d, 4> p_O;
  std::array<Eigen::Vector2d, 4> uv_px;
};

struct ConsensusOptions {
  // A marker whose four corners miss the inliers' joint fit by more than this (RMS, px)
  // disagrees with the set: mismeasured, turned, moved or misprinted.
  double marker_outlier_px = 3.0;
  // Looser bound for the first choice among single-marker hypotheses, whose own pose
  // error moves the other markers' corners by a few pixels.
  double hypothesis_px = 12.0;
};

// A joint fit that leaves out the markers that disagree with the rest.
struct ConsensusFit {
  PoseFit pose;                       // fitted to the inliers' corners
  std::vector<bool> inlier;           // per marker, in input order
  std::vector<double> marker_rms_px;  // per marker, under pose.X_CO
  int outliers() const;
};

// Picks the hypothesis (an X_CO from one marker's solutions, or a prediction) that the
// most markers agree with (truncated squared error over markers, MSAC), refines over its
// agreeing markers, then re-classifies every marker against that fit until the set holds.
// Markers are dropped only when the agreeing ones are at least two and outnumber them: two
// markers that disagree cannot say which is wrong, so both stay and the fit's error shows
// it. Throws std::invalid_argument when markers or hypotheses are empty or a bound is not
// positive.
ConsensusFit fit_with_consensus(const std::vector<MarkerCorners>& markers, const std::vector<Pose>& hypotheses,
                                const CameraModel& camera, const ConsensusOptions& options = {});

}  // namespace arphys::tracking
