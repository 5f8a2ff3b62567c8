#include "tracker/tracking/object_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace arphys::tracking {

namespace {

double seconds_between(int64_t later_utime, int64_t earlier_utime) {
  return static_cast<double>(later_utime - earlier_utime) * 1e-6;
}

// Picks one of a loose marker's two solutions: by the errors when they differ clearly,
// else the one nearer its last pose.
int choose_nearest(const MarkerPoseSolutions& solutions, const std::optional<Pose>& X_CM_previous,
                   double ratio_threshold) {
  if (solutions.count < 2 || solutions.ambiguity_ratio() > ratio_threshold || !X_CM_previous) return 0;
  return geometry::rotation_distance_rad(solutions.X_CM[1], *X_CM_previous) <
                 geometry::rotation_distance_rad(solutions.X_CM[0], *X_CM_previous)
             ? 1
             : 0;
}

Pose exp_twist(const Pose& X, const Eigen::Vector3d& v, const Eigen::Vector3d& w, double dt) {
  Pose out = X;
  out.translation() += v * dt;
  const double angle = w.norm() * dt;
  if (angle > 0) out.linear() = Eigen::AngleAxisd(angle, w.normalized()).toRotationMatrix() * X.linear();
  return out;
}

std::string ids_text(const std::vector<int>& ids) {
  std::string out;
  for (int id : ids) out += (out.empty() ? "" : " ") + std::to_string(id);
  return out;
}

std::string milliseconds_text(double seconds) { return std::to_string(std::lround(seconds * 1e3)) + " ms"; }

}  // namespace

const char* to_string(TrackStatus status) {
  switch (status) {
    case TrackStatus::kTracked: return "TRACKED";
    case TrackStatus::kPredicted: return "PREDICTED";
    case TrackStatus::kLost: return "LOST";
  }
  return "?";
}

TrackerModel TrackerModel::from_scene(const config::SceneConfig& scene, double default_marker_size_m) {
  TrackerModel model;
  model.default_marker_size_m = default_marker_size_m;
  std::map<std::pair<std::string, int>, std::string> owners;
  for (const auto& object : scene.objects) {
    if (object.role != config::Role::kReal || object.markers.empty()) continue;
    ObjectModel o;
    o.id = object.id;
    o.defines_world = object.motion == config::Motion::kStatic;
    o.X_WO = object.X_WO;
    for (const auto& m : object.markers) {
      const auto key = std::make_pair(m.family, m.id);
      if (owners.count(key)) {
        throw std::invalid_argument(scene.file + ": marker " + m.family + " " + std::to_string(m.id) +
                                    " is declared by both '" + owners[key] + "' and '" + object.id + "'");
      }
      owners[key] = object.id;
      o.markers.push_back({m.family, m.id, m.size_m, m.X_OM});
    }
    model.objects.push_back(std::move(o));
  }
  return model;
}

const ObjectModel* TrackerModel::find(const std::string& object_id) const {
  for (const auto& o : objects) {
    if (o.id == object_id) return &o;
  }
  return nullptr;
}

ObjectTracker::ObjectTracker(TrackerModel model, CameraModel camera, TrackerOptions options)
    : model_(std::move(model)), camera_(std::move(camera)), options_(options) {
  if (!(options_.max_fit_rms_px > 0)) {
    throw std::invalid_argument("ObjectTracker: max_fit_rms_px " + std::to_string(options_.max_fit_rms_px) +
                                " must be > 0 (pixels)");
  }
  for (const auto& o : model_.objects) {
    tracks_[o.id].filter = PoseFilter(options_.filter);
    if (!o.defines_world) continue;
    for (const auto& m : o.markers) world_markers_.push_back({m.family, m.id, m.size_m, o.X_WO * m.X_OM});
  }
  world_track_.filter = PoseFilter(options_.filter);
}

void ObjectTracker::reset() {
  for (auto& [id, track] : tracks_) {
    track = Track{};
    track.filter = PoseFilter(options_.filter);
  }
  world_track_ = Track{};
  world_track_.filter = PoseFilter(options_.filter);
  loose_markers_.clear();
  loose_seen_utime_.clear();
}

std::optional<Pose> ObjectTracker::predicted(const Track& track, int64_t utime) const {
  if (!track.seen) return std::nullopt;
  const double age = seconds_between(utime, track.last_seen_utime);
  if (age > options_.memory_s || age < 0) return std::nullopt;
  return exp_twist(track.X_CS, track.v_m_s, track.w_rad_s, age);
}

void ObjectTracker::record(Track& track, const Pose& X_CO, int64_t utime) {
  if (track.seen) {
    const double dt = seconds_between(utime, track.last_seen_utime);
    if (dt > 0 && dt <= options_.memory_s) {
      track.v_m_s = (X_CO.translation() - track.X_CS.translation()) / dt;
      const Eigen::AngleAxisd dR(X_CO.linear() * track.X_CS.linear().transpose());
      track.w_rad_s = dR.axis() * dR.angle() / dt;
    } else {
      track.v_m_s.setZero();
      track.w_rad_s.setZero();
    }
  }
  track.seen = true;
  track.last_seen_utime = utime;
  track.X_CS = X_CO;
}

int ObjectTracker::choose_branch(Track& track, const std::array<Pose, 2>& X_CO, const MarkerPoseSolutions& solutions,
                                 int64_t utime) {
  // Evidence: each solution's sum of squared corner residuals (4 corners), px^2. A corner
  // noise scale would multiply both branches alike and change no decision.
  std::array<double, 2> cost;
  for (int i = 0; i < 2; ++i) cost[i] = 4 * solutions.rms_px[i] * solutions.rms_px[i];
  const bool recent = track.branches_valid && seconds_between(utime, track.branches_utime) <= options_.memory_s &&
                      utime > track.branches_utime;
  // Near frontal the two solutions merge and the branches cannot be told apart by
  // continuity (the tilt may pass through zero or turn back): start afresh there.
  const bool merged = geometry::rotation_distance_rad(X_CO[0], X_CO[1]) < options_.branch_merge_rad;
  if (!recent || merged) {
    // Near frontal the residuals say nothing either way: keep no evidence from there,
    // or a guess made at frontal would carry the mirror branch out of it.
    track.branch_cost = merged ? std::array<double, 2>{0.0, 0.0} : cost;
    track.branch_X_CO = X_CO;
    if (merged) {
      track.branches_valid = true;
      track.branches_utime = utime;
      return 0;  // the lower-error solution; both are within branch_merge_rad of each other
    }
  } else {
    // Each branch continues with the solution nearest to it.
    const auto d = [](const Pose& a, const Pose& b) { return geometry::rotation_distance_rad(a, b); };
    const bool swap = d(track.branch_X_CO[0], X_CO[1]) + d(track.branch_X_CO[1], X_CO[0]) <
                      d(track.branch_X_CO[0], X_CO[0]) + d(track.branch_X_CO[1], X_CO[1]);
    for (int b = 0; b < 2; ++b) {
      const int s = swap ? 1 - b : b;
      track.branch_cost[b] = options_.branch_evidence_decay * track.branch_cost[b] + cost[s];
      track.branch_X_CO[b] = X_CO[s];
    }
  }
  track.branches_valid = true;
  track.branches_utime = utime;
  const int branch = track.branch_cost[1] < track.branch_cost[0] ? 1 : 0;
  // Which solution the winning branch holds now.
  return geometry::rotation_distance_rad(track.branch_X_CO[branch], X_CO[0]) <
                 geometry::rotation_distance_rad(track.branch_X_CO[branch], X_CO[1])
             ? 0
             : 1;
}

ObjectTracker::Fit ObjectTracker::fit_rigid_set(const std::vector<MarkerModel>& set,
                                                const std::vector<const DetectedMarker*>& seen, Track& track,
                                                int64_t utime) {
  Fit fit;
  std::vector<MarkerCorners> corners;
  std::vector<Pose> hypotheses;
  const MarkerModel* single = nullptr;
  MarkerPoseSolutions single_solutions;
  for (const DetectedMarker* d : seen) {
    for (const auto& m : set) {
      if (m.id != d->id || m.family != d->family) continue;
      MarkerCorners c;
      c.id = m.id;
      const auto corners_M = marker_corners_M(m.size_m);
      for (int k = 0; k < 4; ++k) {
        c.p_O[k] = m.X_OM * corners_M[k];
        c.uv_px[k] = d->corners_px[k];
      }
      corners.push_back(c);
      const MarkerPoseSolutions s = solve_marker_pose(*d, m.size_m, camera_);
      for (int i = 0; i < s.count; ++i) hypotheses.push_back(s.X_CM[i] * m.X_OM.inverse());
      single = &m;
      single_solutions = s;
    }
  }
  if (corners.empty()) return fit;

  if (corners.size() == 1) {
    int pick = 0;
    if (single_solutions.count == 2) {
      const std::array<Pose, 2> X_CO{single_solutions.X_CM[0] * single->X_OM.inverse(),
                                     single_solutions.X_CM[1] * single->X_OM.inverse()};
      pick = choose_branch(track, X_CO, single_solutions, utime);
    }
    const std::vector<Eigen::Vector3d> p_O(corners[0].p_O.begin(), corners[0].p_O.end());
    const std::vector<Eigen::Vector2d> uv(corners[0].uv_px.begin(), corners[0].uv_px.end());
    fit.pose = refine_pose(p_O, uv, single_solutions.X_CM[pick] * single->X_OM.inverse(), camera_);
    fit.marker_ids.push_back(corners[0].id);
  } else {
    track.branches_valid = false;
    // Several markers: every marker's solutions (and the prediction) are hypotheses for
    // the whole set; the markers that agree decide, and those that do not are left out.
    if (const std::optional<Pose> X_CO_predicted = predicted(track, utime)) hypotheses.push_back(*X_CO_predicted);
    const ConsensusFit consensus = fit_with_consensus(corners, hypotheses, camera_, options_.consensus);
    fit.pose = consensus.pose;
    for (size_t i = 0; i < corners.size(); ++i) {
      (consensus.inlier[i] ? fit.marker_ids : fit.rejected_ids).push_back(corners[i].id);
    }
  }
  fit.ok = std::isfinite(fit.pose.X_CO.translation().sum()) && std::isfinite(fit.pose.X_CO.linear().sum());
  return fit;
}

void ObjectTracker::assign_markers(const std::vector<DetectedMarker>& markers, TrackingResult& result,
                                   std::map<std::string, SeenMarkers>& seen_by_object, SeenMarkers& seen_world) const {
  result.markers.reserve(markers.size());
  for (const auto& d : markers) {
    MarkerObservation obs;
    obs.marker = d;
    for (const auto& o : model_.objects) {
      for (const auto& m : o.markers) {
        if (m.id == d.id && m.family == d.family) {
          obs.owner = o.id;
          obs.size_m = m.size_m;
        }
      }
    }
    if (obs.owner.empty()) {
      ++result.unknown_markers;
      obs.size_m = model_.default_marker_size_m;
    } else {
      seen_by_object[obs.owner].push_back(&d);
      if (model_.find(obs.owner)->defines_world) seen_world.push_back(&d);
    }
    result.markers.push_back(std::move(obs));
  }
}

void ObjectTracker::update_camera_world(const SeenMarkers& seen_world, int64_t utime, TrackingResult& result) {
  if (!seen_world.empty()) {
    const Fit fit = fit_rigid_set(world_markers_, seen_world, world_track_, utime);
    // A wrong world layout: the camera keeps its last world pose (the world objects' own
    // fits count and name what is wrong).
    if (fit.ok && fit.pose.rms_px <= options_.max_fit_rms_px) {
      const Pose X_CW = world_track_.filter.filter(fit.pose.X_CO, utime * 1e-6);
      if (world_track_.filter.rejected_last()) {
        ++result.rejected_poses;  // the camera keeps its last world pose
      } else {
        record(world_track_, X_CW, utime);
      }
    }
  }
  // A fixed camera keeps its last world pose while the world markers are hidden.
  result.camera_world_valid = world_track_.seen;
  if (world_track_.seen) result.X_WC = world_track_.X_CS.inverse();
}

ObjectObservation ObjectTracker::observe_object(const ObjectModel& object, const SeenMarkers* seen, int64_t utime,
                                                TrackingResult& result) {
  Track& track = tracks_[object.id];
  ObjectObservation obs;
  obs.id = object.id;
  Fit fit;
  if (seen) fit = fit_rigid_set(object.markers, *seen, track, utime);
  result.rejected_markers += static_cast<int>(fit.rejected_ids.size());
  obs.rejected_marker_ids = fit.rejected_ids;
  if (fit.ok && fit.pose.rms_px > options_.max_fit_rms_px) {
    // The markers seen do not fit the object's layout: no pose from them is a measurement.
    ++result.poor_fits;
    char text[160];
    std::snprintf(text, sizeof text, "fit error %.2f px > %.2f px over markers %s", fit.pose.rms_px,
                  options_.max_fit_rms_px, ids_text(fit.marker_ids).c_str());
    obs.reason = text;
    fit.ok = false;
  }
  const Pose X_filtered = fit.ok ? track.filter.filter(fit.pose.X_CO, utime * 1e-6) : Pose::Identity();
  if (fit.ok && track.filter.rejected_last()) {
    // A fit far from where the object is going (a flipped single-marker pose): the
    // filter's prediction stands in, and the track is not seen in this frame.
    ++result.rejected_poses;
    obs.status = TrackStatus::kPredicted;
    obs.X_CO = X_filtered;
    obs.reason = "fit dropped by the pose filter as an outlier";
  } else if (fit.ok) {
    record(track, X_filtered, utime);
    obs.status = TrackStatus::kTracked;
    obs.X_CO = X_filtered;
    obs.marker_ids = fit.marker_ids;
    obs.rms_px = fit.pose.rms_px;
    obs.position_sigma_m = fit.pose.position_sigma_m;
    obs.rotation_sigma_rad = fit.pose.rotation_sigma_rad;
  } else if (track.seen) {
    const double age = seconds_between(utime, track.last_seen_utime);
    if (obs.reason.empty()) obs.reason = "not seen for " + milliseconds_text(age);
    if (age <= options_.predict_s && age >= 0) {
      obs.status = TrackStatus::kPredicted;
      obs.X_CO = exp_twist(track.X_CS, track.v_m_s, track.w_rad_s, age);
    } else {
      obs.status = TrackStatus::kLost;
      obs.X_CO = track.X_CS;
      track.filter.reset();
    }
  } else if (obs.reason.empty()) {
    obs.reason = "never seen";
  }
  obs.last_seen_utime = track.seen ? track.last_seen_utime : 0;
  if (object.defines_world) {
    obs.world_valid = true;
    obs.X_WO = object.X_WO;
  } else if (result.camera_world_valid && track.seen) {
    obs.world_valid = true;
    obs.X_WO = result.X_WC * obs.X_CO;
  }
  return obs;
}

void ObjectTracker::pose_markers(TrackingResult& result, int64_t utime) {
  for (auto& obs : result.markers) {
    if (!obs.owner.empty()) {
      for (const auto& o : result.objects) {
        if (o.id == obs.owner) {
          const auto& r = o.rejected_marker_ids;
          obs.rejected = std::find(r.begin(), r.end(), obs.marker.id) != r.end();
        }
        if (o.id != obs.owner || o.status != TrackStatus::kTracked || obs.rejected) continue;
        for (const auto& m : model_.find(o.id)->markers) {
          if (m.id == obs.marker.id && m.family == obs.marker.family) {
            obs.has_pose = true;
            obs.X_CM = o.X_CO * m.X_OM;
          }
        }
      }
    }
    if (obs.size_m <= 0) continue;
    const MarkerPoseSolutions s = solve_marker_pose(obs.marker, obs.size_m, camera_);
    obs.ambiguity_ratio = s.ambiguity_ratio();
    if (obs.has_pose) {
      const auto corners = marker_corners_M(obs.size_m);
      std::vector<Eigen::Vector3d> p(corners.begin(), corners.end());
      std::vector<Eigen::Vector2d> uv(obs.marker.corners_px.begin(), obs.marker.corners_px.end());
      obs.rms_px = reprojection_rms_px(p, uv, obs.X_CM, camera_);
      continue;
    }
    const auto key = std::make_pair(obs.marker.family, obs.marker.id);
    std::optional<Pose> previous;
    const auto it = loose_markers_.find(key);
    if (it != loose_markers_.end() && seconds_between(utime, loose_seen_utime_[key]) <= options_.memory_s) {
      previous = it->second;
    }
    const int pick = choose_nearest(s, previous, options_.ambiguity_ratio_threshold);
    obs.has_pose = s.count > 0;
    obs.X_CM = s.X_CM[pick];
    obs.rms_px = s.rms_px[pick];
    loose_markers_[key] = obs.X_CM;
    loose_seen_utime_[key] = utime;
  }
}

TrackingResult ObjectTracker::update(const std::vector<DetectedMarker>& markers, int64_t capture_utime) {
  TrackingResult result;
  std::map<std::string, SeenMarkers> seen_by_object;
  SeenMarkers seen_world;
  assign_markers(markers, result, seen_by_object, seen_world);
  update_camera_world(seen_world, capture_utime, result);
  for (const auto& object : model_.objects) {
    const auto seen = seen_by_object.find(object.id);
    result.objects.push_back(
        observe_object(object, seen == seen_by_object.end() ? nullptr : &seen->second, capture_utime, result));
  }
  pose_markers(result, capture_utime);
  return result;
}

}  // namespace arphys::tracking
