#pragma once
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "simulator/geometry/pose.hpp"

namespace arphys::config {

// What a scene *is* (loaded once, immutable); what changes per step lives in the
// processes' state (MuJoCo's model/data split).

enum class Role { kReal, kVirtual };
enum class Motion { kStatic, kKinematic, kDynamic };
enum class ShapeType { kPlane, kBox, kSphere, kMesh, kConvexSet };

const char* to_string(Role role);
const char* to_string(Motion motion);
const char* to_string(ShapeType type);

struct ShapeConfig {
  ShapeType type = ShapeType::kBox;
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();  // box: full side lengths
  double radius_m = 0;                               // sphere
  std::string mesh_path;                             // mesh: absolute path, checked to exist; convex_set: the
                                                     // mesh its mass properties come from (optional)
  std::string pieces_path;                           // convex_set: the convex-piece file, absolute, checked to exist
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();   // mesh, convex_set: applied to the file's vertices
  // plane: the half-space z <= 0 of the object frame (no parameters).
};

struct MarkerConfig {
  std::string family;  // "tag36h11", "tag25h9", ..., or an ArUco dictionary name
  int id = 0;
  double size_m = 0;  // side of the black square
  geometry::Pose X_OM = geometry::Pose::Identity();  // marker in object frame, z out of the face
};

struct SpawnConfig {
  geometry::Pose X_WB = geometry::Pose::Identity();
  Eigen::Vector3d v_WB_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WB_rad_s = Eigen::Vector3d::Zero();
};

// A tracked (or scripted) pose of a kinematic object at a time.
struct TimedPoseConfig {
  double t_s = 0;
  geometry::Pose X_WO = geometry::Pose::Identity();
};

struct ObjectConfig {
  std::string id;
  Role role = Role::kVirtual;
  Motion motion = Motion::kDynamic;
  ShapeConfig collision;
  ShapeConfig render;  // the collision shape unless the file gives one
  std::optional<double> mass_kg;        // at most one of mass and density;
  std::optional<double> density_kg_m3;  // neither: density of water for dynamic bodies
  double restitution = 0.0;             // coefficient of restitution in [0, 1]
  std::optional<double> friction;       // Coulomb coefficient; absent = frictionless
  geometry::Pose X_WO = geometry::Pose::Identity();  // initial (or fixed) pose in the world
  // Dynamic objects: initial velocity of the object frame's origin and angular velocity.
  Eigen::Vector3d v_WO_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_WO_rad_s = Eigen::Vector3d::Zero();
  // Kinematic objects driven by a script instead of tracking (headless runs, tests):
  // poses at strictly increasing times, screw-interpolated between them.
  std::vector<TimedPoseConfig> trajectory;
  std::vector<MarkerConfig> markers;    // real objects only
  // Virtual objects: instances created at start, and the cap on live instances.
  std::vector<SpawnConfig> spawn_at_start;
  int max_instances = 1;
};

// LCM channel names; every process reads them from the scene so one file rewires all.
struct ChannelNames {
  std::string camera_image = "ARPHYS_CAMERA_IMAGE";
  std::string camera_info = "ARPHYS_CAMERA_INFO";
  std::string marker_detections = "ARPHYS_MARKERS";
  std::string object_poses = "ARPHYS_OBJECT_POSES";
  std::string world_state = "ARPHYS_WORLD_STATE";
  std::string sim_command = "ARPHYS_SIM_COMMAND";
  std::string tracker_control = "ARPHYS_TRACKER_CONTROL";
  std::string render_status = "ARPHYS_RENDER_STATUS";
  std::string overlay_image = "ARPHYS_OVERLAY_IMAGE";
  std::string process_status = "ARPHYS_STATUS";
  std::string ground_truth = "ARPHYS_GROUND_TRUTH";
};

struct SceneConfig {
  std::string file;         // absolute path of the scene file
  std::string name;
  std::string camera_file;  // absolute path of the camera calibration file; empty for headless scenes
  std::string lcm_url = "udpm://239.255.76.67:7667?ttl=0";
  ChannelNames channels;
  Eigen::Vector3d gravity_m_s2{0, 0, -9.81};
  double time_step_s = 0.01;
  std::string solver = "exact";   // contact solver: "exact" (active set) or "iterative" (projected Gauss-Seidel)
  int solver_iterations = 50;     // iterative sweeps (and friction sweeps after an exact solve)
  // The gap resting contacts keep and the deepest any pair may end a step inside another
  // (dynamics::WorldOptions; unset: its defaults, 1 um each). A pile that allows 10 um of
  // each steps in 0.6x the time: resting pairs whose motion cannot close the gap are not swept.
  std::optional<double> contact_gap_m, overlap_tolerance_m;
  // Deactivation (dynamics::WorldOptions::sleep_after_s): a dynamic body whose points move
  // slower than sleep_speed_m_s for sleep_after_s is held at rest, costing nothing, until
  // something moving reaches it. 0: never (the default).
  double sleep_after_s = 0;
  double sleep_speed_m_s = 0.01;
  // How tracked poses drive kinematic bodies: "delay" (move one frame behind, along
  // the screw between the last two poses: smooth, adds one frame of latency) or
  // "extrapolate" (continue the last twist until the next pose arrives, then correct).
  std::string tracking_policy = "delay";
  std::vector<ObjectConfig> objects;

  const ObjectConfig* find_object(const std::string& id) const;
  // The real object carrying marker (family, id), or nullptr.
  const ObjectConfig* find_marker_owner(const std::string& family, int id) const;
};

// Loads and validates a scene file. Relative paths in it (camera, meshes) are
// relative to the scene file's directory. Throws ConfigError naming the file, line,
// key path, bad value and what was expected.
SceneConfig load_scene(const std::string& path);

// The directory holding scenes/, cameras/ and models/ of the source tree.
std::string default_config_dir();

}  // namespace arphys::config
