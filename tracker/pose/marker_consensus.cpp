#include "tracker/pose/marker_consensus.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace arphys::tracking {

namespace {

double marker_rms_px(const MarkerCorners& m, const Pose& X_CO, const CameraModel& camera) {
  const std::vector<Eigen::Vector3d> p(m.p_O.begin(), m.p_O.end());
  const std::vector<Eigen::Vector2d> uv(m.uv_px.begin(), m.uv_px.end());
  return reprojection_rms_px(p, uv, X_CO, camera);
}

std::vector<double> rms_of_each(const std::vector<MarkerCorners>& markers, const Pose& X_CO,
                                const CameraModel& camera) {
  std::vector<double> rms;
  rms.reserve(markers.size());
  for (const auto& m : markers) rms.push_back(marker_rms_px(m, X_CO, camera));
  return rms;
}

PoseFit refine_over(const std::vector<MarkerCorners>& markers, const std::vector<bool>& use, const Pose& X_CO,
                    const CameraModel& camera) {
  std::vector<Eigen::Vector3d> p_O;
  std::vector<Eigen::Vector2d> uv;
  for (size_t i = 0; i < markers.size(); ++i) {
    if (!use[i]) continue;
    p_O.insert(p_O.end(), markers[i].p_O.begin(), markers[i].p_O.end());
    uv.insert(uv.end(), markers[i].uv_px.begin(), markers[i].uv_px.end());
  }
  return refine_pose(p_O, uv, X_CO, camera);
}

// Markers within bound_px; all of them when too few agree to overrule the rest.
std::vector<bool> agreeing(const std::vector<double>& rms_px, double bound_px) {
  std::vector<bool> in(rms_px.size());
  int count = 0;
  for (size_t i = 0; i < rms_px.size(); ++i) count += (in[i] = rms_px[i] <= bound_px);
  const int against = static_cast<int>(rms_px.size()) - count;
  if (count < 2 || count <= against) std::fill(in.begin(), in.end(), true);
  return in;
}

}  // namespace

int ConsensusFit::outliers() const { return static_cast<int>(std::count(inlier.begin(), inlier.end(), false)); }

ConsensusFit fit_with_consensus(const std::vector<MarkerCorners>& markers, const std::vector<Pose>& hypotheses,
                                const CameraModel& camera, const ConsensusOptions& options) {
  if (markers.empty()) throw std::invalid_argument("fit_with_consensus: no markers");
  if (hypotheses.empty()) throw std::invalid_argument("fit_with_consensus: no hypotheses");
  if (!(options.marker_outlier_px > 0) || !(options.hypothesis_px > 0)) {
    throw std::invalid_argument("fit_with_consensus: marker_outlier_px " + std::to_string(options.marker_outlier_px) +
                                " and hypothesis_px " + std::to_string(options.hypothesis_px) + " must be > 0");
  }
  const double cap2 = options.hypothesis_px * options.hypothesis_px;
  const Pose* best = &hypotheses.front();
  double best_cost = std::numeric_limits<double>::infinity();
  for (const Pose& h : hypotheses) {
    double cost = 0;
    for (const auto& m : markers) cost += std::min(cap2, std::pow(marker_rms_px(m, h, camera), 2));
    if (cost < best_cost) {
      best_cost = cost;
      best = &h;
    }
  }
  ConsensusFit fit;
  fit.inlier = agreeing(rms_of_each(markers, *best, camera), options.hypothesis_px);
  fit.pose = refine_over(markers, fit.inlier, *best, camera);
  // The loose first set may hold a marker that is off by a few pixels; tighten until stable.
  for (int round = 0; round < 4; ++round) {
    fit.marker_rms_px = rms_of_each(markers, fit.pose.X_CO, camera);
    const std::vector<bool> in = agreeing(fit.marker_rms_px, options.marker_outlier_px);
    if (in == fit.inlier) break;
    fit.inlier = in;
    fit.pose = refine_over(markers, fit.inlier, fit.pose.X_CO, camera);
  }
  fit.marker_rms_px = rms_of_each(markers, fit.pose.X_CO, camera);
  return fit;
}

}  // namespace arphys::tracking
