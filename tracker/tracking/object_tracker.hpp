#pragma once
#include <cstdint>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "configs/loader/scene_config.hpp"
#include "tracker/detection/marker_detector.hpp"
#include "tracker/pose/camera_model.hpp"
#include "tracker/pose/marker_consensus.hpp"
#include "tracker/pose/marker_pose.hpp"
#include "tracker/pose/pose_filter.hpp"

namespace arphys::tracking {

// What the tracker knows of the scene: its real objects and their markers.
struct MarkerModel {
  std::string family;
  int id = 0;
  double size_m = 0;
  Pose X_OM = Pose::Identity();
};

struct ObjectModel {
  std::string id;
  std::vector<MarkerModel> markers;
  // A static real object fixes the world frame: seeing it gives the camera's pose.
  bool defines_world = false;
  Pose X_WO = Pose::Identity();
};

struct TrackerModel {
  std::vector<ObjectModel> objects;
  // Side length for markers no object declares (so photos can be processed without a
  // scene); 0: such markers get no pose.
  double default_marker_size_m = 0;

  // Real objects with markers from the scene. Throws std::invalid_argument when two
  // objects claim the same marker.
  static TrackerModel from_scene(const config::SceneConfig& scene, double default_marker_size_m);
  const ObjectModel* find(const std::string& object_id) const;
};

enum class TrackStatus { kTracked, kPredicted, kLost };
const char* to_string(TrackStatus status);

struct MarkerObservation {
  DetectedMarker marker;
  std::string owner;  // object id, empty for a marker no object declares
  double size_m = 0;
  bool has_pose = false;
  Pose X_CM = Pose::Identity();
  double rms_px = 0;
  double ambiguity_ratio = 0;
  bool rejected = false;  // owned, but left out of its object's fit: it disagrees with the others
};

struct ObjectObservation {
  std::string id;
  TrackStatus status = TrackStatus::kLost;
  Pose X_CO = Pose::Identity();  // LOST: the last known pose, not a measurement
  bool world_valid = false;
  Pose X_WO = Pose::Identity();
  std::vector<int> marker_ids;           // markers the pose was fitted to
  std::vector<int> rejected_marker_ids;  // seen, but disagreeing with the others: left out
  std::string reason;                    // why it is not TRACKED (empty when it is)
  double rms_px = 0;
  double position_sigma_m = 0;
  double rotation_sigma_rad = 0;
  int64_t last_seen_utime = 0;  // 0: never seen
};

struct TrackingResult {
  std::vector<MarkerObservation> markers;
  std::vector<ObjectObservation> objects;  // every object of the model, in model order
  bool camera_world_valid = false;
  Pose X_WC = Pose::Identity();
  int unknown_markers = 0;  // markers of this frame no object declares
  int rejected_poses = 0;   // fits of this frame the pose filter dropped as outliers (PREDICTED instead)
  int rejected_markers = 0; // owned markers left out of their object's (or the world's) fit
  int poor_fits = 0;        // object or camera fits above max_fit_rms_px (not TRACKED)
};

struct TrackerOptions {
  // A loose marker's two pose solutions are told apart by their reprojection errors
  // alone when the second is this many times worse, else by its last pose. For an
  // object seen through one marker both branches are followed
  // over frames (each new solution joins the branch it continues) and the branch whose
  // corners have fitted better over the recent frames wins: near frontal one frame's
  // errors hardly differ, and a prediction from an ambiguous frame can lock onto the
  // mirror branch; the evidence of several frames does neither.
  double ambiguity_ratio_threshold = 4.0;
  // Per-frame decay of the evidence each branch has gathered (0: none kept).
  double branch_evidence_decay = 0.8;
  // Solutions closer than this are one branch (near-frontal views).
  double branch_merge_rad = 0.2;
  // An object not seen is PREDICTED (constant-velocity extrapolation) for this long,
  // then LOST. 0: straight to LOST.
  double predict_s = 0.1;
  // How long a last pose is trusted as the reference for ambiguity decisions.
  double memory_s = 0.5;
  // Filter on object and camera poses (none by default: the raw fit).
  PoseFilterSpec filter;
  // Which markers of a multi-marker object agree with the others (marker_consensus.hpp).
  ConsensusOptions consensus;
  // An object (or the camera, from the world's markers) whose fit misses its corners by
  // more than this RMS is not TRACKED: a wrong layout, a misprinted or moved marker.
  double max_fit_rms_px = 2.0;
};

// Turns one frame's detected markers into marker and object poses: per-marker IPPE,
// joint PnP + Levenberg-Marquardt over every visible corner of an object, ambiguity
// resolution, optional filtering, TRACKED / PREDICTED / LOST bookkeeping, and the
// camera's pose in the world when a world-fixing object is seen.
class ObjectTracker {
 public:
  ObjectTracker(TrackerModel model, CameraModel camera, TrackerOptions options = {});

  TrackingResult update(const std::vector<DetectedMarker>& markers, int64_t capture_utime);
  // Forgets every track (a new, unrelated picture).
  void reset();

  const TrackerModel& model() const { return model_; }
  const CameraModel& camera() const { return camera_; }
  const TrackerOptions& options() const { return options_; }

 private:
  // A rigid set S followed over frames: an object (S = O), or the world's markers
  // (S = W: X_CS is X_CW).
  struct Track {
    bool seen = false;
    int64_t last_seen_utime = 0;
    Pose X_CS = Pose::Identity();
    // Twist of S in C from the last two measurements (for prediction).
    Eigen::Vector3d v_m_s = Eigen::Vector3d::Zero();
    Eigen::Vector3d w_rad_s = Eigen::Vector3d::Zero();
    PoseFilter filter;
    // A single marker's two pose branches, followed frame to frame, each with its
    // decayed sum of squared corner residuals (px^2).
    bool branches_valid = false;
    int64_t branches_utime = 0;
    std::array<Pose, 2> branch_X_CO;
    std::array<double, 2> branch_cost{0, 0};
  };
  struct Fit {
    bool ok = false;
    PoseFit pose;
    std::vector<int> marker_ids;
    std::vector<int> rejected_ids;
  };
  // Fits the pose of a rigid set of markers (an object, or the world) from the visible ones.
  Fit fit_rigid_set(const std::vector<MarkerModel>& set, const std::vector<const DetectedMarker*>& seen, Track& track,
                    int64_t utime);
  // Which of a single marker's two solutions (as object poses) to take.
  int choose_branch(Track& track, const std::array<Pose, 2>& X_CO, const MarkerPoseSolutions& solutions, int64_t utime);
  std::optional<Pose> predicted(const Track& track, int64_t utime) const;
  void record(Track& track, const Pose& X_CO, int64_t utime);
  // The detections by owning object (and those of world-fixing objects), each listed in
  // result.markers; unknown ones counted.
  using SeenMarkers = std::vector<const DetectedMarker*>;
  void assign_markers(const std::vector<DetectedMarker>& markers, TrackingResult& result,
                      std::map<std::string, SeenMarkers>& seen_by_object, SeenMarkers& seen_world) const;
  // The camera in the world from every world-fixing marker at once.
  void update_camera_world(const SeenMarkers& seen_world, int64_t utime, TrackingResult& result);
  // One object's observation this frame: tracked, predicted or lost, with the reason.
  ObjectObservation observe_object(const ObjectModel& object, const SeenMarkers* seen, int64_t utime,
                                   TrackingResult& result);
  // Each marker's pose: an owned marker's from its object's fit, a loose one's from its own
  // solutions, disambiguated against its last pose.
  void pose_markers(TrackingResult& result, int64_t utime);

  TrackerModel model_;
  CameraModel camera_;
  TrackerOptions options_;
  std::vector<MarkerModel> world_markers_;  // markers of world-fixing objects, X_OM = X_WM
  std::map<std::string, Track> tracks_;     // by object id
  Track world_track_;                       // S = W
  std::map<std::pair<std::string, int>, Pose> loose_markers_;  // last X_CM of markers no object declares
  std::map<std::pair<std::string, int>, int64_t> loose_seen_utime_;
};

}  // namespace arphys::tracking
