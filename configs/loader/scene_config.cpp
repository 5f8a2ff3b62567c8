#include "configs/loader/scene_config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "configs/loader/config_error.hpp"
#include "configs/loader/yaml_reader.hpp"

namespace arphys::config {

const char* to_string(Role role) { return role == Role::kReal ? "real" : "virtual"; }

const char* to_string(Motion motion) {
  switch (motion) {
    case Motion::kStatic: return "static";
    case Motion::kKinematic: return "kinematic";
    case Motion::kDynamic: return "dynamic";
  }
  return "?";
}

const char* to_string(ShapeType type) {
  switch (type) {
    case ShapeType::kPlane: return "plane";
    case ShapeType::kBox: return "box";
    case ShapeType::kSphere: return "sphere";
    case ShapeType::kMesh: return "mesh";
    case ShapeType::kConvexSet: return "convex_set";
  }
  return "?";
}

const ObjectConfig* SceneConfig::find_object(const std::string& id) const {
  for (const auto& object : objects)
    if (object.id == id) return &object;
  return nullptr;
}

const ObjectConfig* SceneConfig::find_marker_owner(const std::string& family, int id) const {
  for (const auto& object : objects)
    for (const auto& marker : object.markers)
      if (marker.family == family && marker.id == id) return &object;
  return nullptr;
}

std::string default_config_dir() { return ARPHYS_DEFAULT_CONFIG_DIR; }

namespace {

namespace fs = std::filesystem;


Role parse_role(const Reader& r, const YAML::Node& node, const std::string& key) {
  const std::string value = r.string(node, key);
  if (value == "real") return Role::kReal;
  if (value == "virtual") return Role::kVirtual;
  r.fail(node, key, "got '" + value + "', expected 'real' or 'virtual'");
}

Motion parse_motion(const Reader& r, const YAML::Node& node, const std::string& key) {
  const std::string value = r.string(node, key);
  if (value == "static") return Motion::kStatic;
  if (value == "kinematic") return Motion::kKinematic;
  if (value == "dynamic") return Motion::kDynamic;
  r.fail(node, key, "got '" + value + "', expected 'static', 'kinematic' or 'dynamic'");
}

// A kinematic object's trajectory: samples {t_s, pose} in increasing time.
void parse_trajectory(const Reader& r, const YAML::Node& trajectory, const std::string& tkey, ObjectConfig& object) {
  if (!trajectory.IsDefined()) return;
  if (object.motion != Motion::kKinematic) r.fail(trajectory, tkey, "only a kinematic object follows a trajectory");
  if (!trajectory.IsSequence() || trajectory.size() == 0)
    r.fail(trajectory, tkey, "got " + Reader::shown(trajectory) + ", expected a non-empty list of {t_s, pose}");
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const std::string ikey = tkey + "[" + std::to_string(i) + "]";
    r.only_keys(trajectory[i], ikey, {"t_s", "pose"});
    TimedPoseConfig sample;
    sample.t_s = r.number(r.required(trajectory[i], ikey, "t_s"), ikey + ".t_s", "a time in seconds");
    if (!object.trajectory.empty() && !(sample.t_s > object.trajectory.back().t_s)) {
      r.fail(trajectory[i]["t_s"], ikey + ".t_s",
             "got " + trajectory[i]["t_s"].Scalar() + ", expected a time after the previous one (" +
                 std::to_string(object.trajectory.back().t_s) + " s)");
    }
    sample.X_WO = r.pose(r.required(trajectory[i], ikey, "pose"), ikey + ".pose");
    object.trajectory.push_back(sample);
  }
}

// A real object's markers: family, id, side length and pose on the object.
void parse_markers(const Reader& r, const YAML::Node& markers, const std::string& mkeys, ObjectConfig& object) {
  if (!markers.IsDefined()) return;
  if (object.role != Role::kReal) {
    r.fail(markers, mkeys, "a virtual object carries no markers, expected markers only on real objects");
  }
  if (!markers.IsSequence()) r.fail(markers, mkeys, "got " + Reader::shown(markers) + ", expected a list");
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const std::string mkey = mkeys + "[" + std::to_string(i) + "]";
    const YAML::Node m = markers[i];
    r.only_keys(m, mkey, {"family", "id", "size_m", "pose"});
    MarkerConfig marker;
    marker.family = r.string(r.required(m, mkey, "family"), mkey + ".family");
    marker.id = r.integer(r.required(m, mkey, "id"), mkey + ".id", "a marker id (integer >= 0)");
    if (marker.id < 0) r.fail(m["id"], mkey + ".id", "got " + m["id"].Scalar() + ", expected a marker id >= 0");
    marker.size_m = r.positive(r.required(m, mkey, "size_m"), mkey + ".size_m", "a positive side length in metres");
    marker.X_OM = r.pose(r.required(m, mkey, "pose"), mkey + ".pose");
    object.markers.push_back(marker);
  }
}

// A spawnable object's instance limit and the instances present at the start.
void parse_spawn(const Reader& r, const YAML::Node& spawn, const std::string& skey, ObjectConfig& object) {
  if (!spawn.IsDefined()) return;
  if (object.role != Role::kVirtual || object.motion != Motion::kDynamic) {
    r.fail(spawn, skey, "only virtual dynamic objects can be spawned");
  }
  r.only_keys(spawn, skey, {"max_instances", "at_start"});
  if (spawn["max_instances"].IsDefined()) {
    object.max_instances = r.integer(spawn["max_instances"], skey + ".max_instances", "a count >= 1");
    if (object.max_instances < 1 || object.max_instances > 10000) {
      r.fail(spawn["max_instances"], skey + ".max_instances",
             "got " + spawn["max_instances"].Scalar() + ", expected 1 to 10000");
    }
  }
  const YAML::Node at_start = spawn["at_start"];
  if (at_start.IsDefined()) {
    if (!at_start.IsSequence()) r.fail(at_start, skey + ".at_start", "expected a list");
    for (std::size_t i = 0; i < at_start.size(); ++i) {
      const std::string ikey = skey + ".at_start[" + std::to_string(i) + "]";
      r.only_keys(at_start[i], ikey, {"pose", "velocity_m_s", "angular_velocity_rad_s"});
      SpawnConfig s;
      s.X_WB = r.pose(r.required(at_start[i], ikey, "pose"), ikey + ".pose");
      if (at_start[i]["velocity_m_s"].IsDefined())
        s.v_WB_m_s = r.vector(at_start[i]["velocity_m_s"], ikey + ".velocity_m_s", 3, "m/s");
      if (at_start[i]["angular_velocity_rad_s"].IsDefined())
        s.w_WB_rad_s = r.vector(at_start[i]["angular_velocity_rad_s"], ikey + ".angular_velocity_rad_s", 3, "rad/s");
      object.spawn_at_start.push_back(s);
    }
    if (static_cast<int>(object.spawn_at_start.size()) > object.max_instances) {
      r.fail(at_start, skey + ".at_start",
             std::to_string(object.spawn_at_start.size()) +
                 " instances, more than max_instances = " + std::to_string(object.max_instances));
    }
  }
}

ObjectConfig parse_object(const Reader& r, const YAML::Node& node, const std::string& key) {
  r.only_keys(node, key,
              {"id", "role", "motion", "collision", "render", "mass_kg", "density_kg_m3", "restitution", "friction",
               "pose", "velocity_m_s", "angular_velocity_rad_s", "trajectory", "markers", "spawn"});
  ObjectConfig object;
  object.id = r.string(r.required(node, key, "id"), key + ".id");
  object.role = parse_role(r, r.required(node, key, "role"), key + ".role");
  object.motion = parse_motion(r, r.required(node, key, "motion"), key + ".motion");
  if (object.role == Role::kReal && object.motion == Motion::kDynamic) {
    r.fail(node["motion"], key + ".motion",
           "got 'dynamic' for a real object, expected 'static' or 'kinematic' (real objects are driven by tracking)");
  }
  object.collision = r.shape(r.required(node, key, "collision"), key + ".collision");
  object.render = node["render"].IsDefined() ? r.shape(node["render"], key + ".render") : object.collision;
  if (object.motion == Motion::kDynamic && object.collision.type == ShapeType::kPlane) {
    r.fail(node["collision"], key + ".collision.shape", "a plane cannot be dynamic (it has no mass), expected box, sphere, mesh or convex_set");
  }
  if (node["mass_kg"].IsDefined() && node["density_kg_m3"].IsDefined()) {
    r.fail(node["density_kg_m3"], key + ".density_kg_m3", "given together with mass_kg, expected at most one of them");
  }
  if (node["mass_kg"].IsDefined())
    object.mass_kg = r.positive(node["mass_kg"], key + ".mass_kg", "a positive mass in kilograms");
  if (node["density_kg_m3"].IsDefined())
    object.density_kg_m3 = r.positive(node["density_kg_m3"], key + ".density_kg_m3", "a positive density in kg/m^3");
  if (node["restitution"].IsDefined()) {
    object.restitution = r.number(node["restitution"], key + ".restitution", "a coefficient of restitution in [0, 1]");
    if (object.restitution < 0 || object.restitution > 1) {
      r.fail(node["restitution"], key + ".restitution",
             "got " + node["restitution"].Scalar() + ", expected a coefficient of restitution in [0, 1]");
    }
  }
  if (node["friction"].IsDefined()) {
    object.friction = r.number(node["friction"], key + ".friction", "a Coulomb friction coefficient >= 0");
    if (*object.friction < 0) {
      r.fail(node["friction"], key + ".friction", "got " + node["friction"].Scalar() + ", expected a Coulomb friction coefficient >= 0");
    }
  }
  if (node["pose"].IsDefined()) object.X_WO = r.pose(node["pose"], key + ".pose");
  for (const char* name : {"velocity_m_s", "angular_velocity_rad_s"}) {
    if (!node[name].IsDefined()) continue;
    if (object.motion != Motion::kDynamic)
      r.fail(node[name], key + "." + name, "only a dynamic object has an initial velocity (a kinematic one follows its trajectory)");
    const bool linear = std::string(name) == "velocity_m_s";
    (linear ? object.v_WO_m_s : object.w_WO_rad_s) = r.vector(node[name], key + "." + name, 3, linear ? "m/s" : "rad/s");
  }
  parse_trajectory(r, node["trajectory"], key + ".trajectory", object);
  parse_markers(r, node["markers"], key + ".markers", object);
  parse_spawn(r, node["spawn"], key + ".spawn", object);
  return object;
}

}  // namespace

namespace {
SceneConfig load_scene_checked(const std::string& path_in);
}  // namespace

SceneConfig load_scene(const std::string& path_in) {
  try {
    return load_scene_checked(path_in);
  } catch (const YAML::Exception& e) {
    // Every expected problem is reported by the Reader; this is the net under it.
    throw ConfigError(path_in, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", std::string("unreadable YAML: ") + e.msg);
  }
}

namespace {

// The scene's LCM channel names (channels:), each a string.
void parse_channels(const Reader& r, const YAML::Node& ch, SceneConfig& scene) {
  std::map<std::string, std::string*> fields = {{"camera_image", &scene.channels.camera_image},
                                                {"camera_info", &scene.channels.camera_info},
                                                {"marker_detections", &scene.channels.marker_detections},
                                                {"object_poses", &scene.channels.object_poses},
                                                {"world_state", &scene.channels.world_state},
                                                {"sim_command", &scene.channels.sim_command},
                                                {"tracker_control", &scene.channels.tracker_control},
                                                {"render_status", &scene.channels.render_status},
                                                {"overlay_image", &scene.channels.overlay_image},
                                                {"process_status", &scene.channels.process_status},
                                                {"ground_truth", &scene.channels.ground_truth}};
  r.only_keys(ch, "channels",
              {"camera_image", "camera_info", "marker_detections", "object_poses", "world_state", "sim_command",
               "tracker_control", "render_status", "overlay_image", "process_status", "ground_truth"});
  for (const auto& entry : ch) {
    const std::string name = r.key_name(entry.first, "channels");
    *fields.at(name) = r.string(entry.second, "channels." + name);
  }
}

// The physics: block (gravity, time step, solver, tolerances, sleep), each key checked.
void parse_physics(const Reader& r, const YAML::Node& ph, SceneConfig& scene) {
  r.only_keys(ph, "physics",
              {"gravity_m_s2", "time_step_s", "solver", "solver_iterations", "tracking_policy", "contact_gap_m",
               "overlap_tolerance_m", "sleep_after_s", "sleep_speed_m_s"});
  // Below 0.1 mm: well inside the 1 mm within which contacts are gathered (a gap near
  // that would lose its contacts), and an overlap beyond that is no tolerance.
  for (const auto& [key, field] :
       {std::pair<const char*, std::optional<double>*>{"contact_gap_m", &scene.contact_gap_m},
        {"overlap_tolerance_m", &scene.overlap_tolerance_m}}) {
    if (!ph[key].IsDefined()) continue;
    const std::string name = std::string("physics.") + key, expected = "a positive length below 1e-4 m";
    *field = r.positive(ph[key], name, expected);
    if (**field >= 1e-4) r.fail(ph[key], name, "got " + ph[key].Scalar() + ", expected " + expected);
  }
  if (ph["solver"].IsDefined()) {
    scene.solver = r.string(ph["solver"], "physics.solver");
    if (scene.solver != "exact" && scene.solver != "iterative")
      r.fail(ph["solver"], "physics.solver", "got '" + scene.solver + "', expected 'exact' or 'iterative'");
  }
  if (ph["solver_iterations"].IsDefined()) {
    scene.solver_iterations = r.integer(ph["solver_iterations"], "physics.solver_iterations", "a count of sweeps");
    if (scene.solver_iterations < 1 || scene.solver_iterations > 100000)
      r.fail(ph["solver_iterations"], "physics.solver_iterations",
             "got " + ph["solver_iterations"].Scalar() + ", expected 1 to 100000 sweeps");
  }
  if (ph["tracking_policy"].IsDefined()) {
    scene.tracking_policy = r.string(ph["tracking_policy"], "physics.tracking_policy");
    if (scene.tracking_policy != "delay" && scene.tracking_policy != "extrapolate")
      r.fail(ph["tracking_policy"], "physics.tracking_policy",
             "got '" + scene.tracking_policy + "', expected 'delay' or 'extrapolate'");
  }
  if (ph["sleep_after_s"].IsDefined()) {
    scene.sleep_after_s = r.number(ph["sleep_after_s"], "physics.sleep_after_s", "a time in seconds (0: never sleep)");
    if (!(scene.sleep_after_s >= 0) || scene.sleep_after_s > 3600)
      r.fail(ph["sleep_after_s"], "physics.sleep_after_s",
             "got " + ph["sleep_after_s"].Scalar() + ", expected 0 (never sleep) to 3600 s");
  }
  if (ph["sleep_speed_m_s"].IsDefined()) {
    scene.sleep_speed_m_s = r.positive(ph["sleep_speed_m_s"], "physics.sleep_speed_m_s", "a positive speed in m/s");
    if (scene.sleep_speed_m_s > 1)
      r.fail(ph["sleep_speed_m_s"], "physics.sleep_speed_m_s",
             "got " + ph["sleep_speed_m_s"].Scalar() + ", expected a speed of at most 1 m/s");
  }
  if (ph["gravity_m_s2"].IsDefined())
    scene.gravity_m_s2 = r.vector(ph["gravity_m_s2"], "physics.gravity_m_s2", 3, "m/s^2");
  if (ph["time_step_s"].IsDefined()) {
    scene.time_step_s = r.positive(ph["time_step_s"], "physics.time_step_s", "a positive time step in seconds");
    if (scene.time_step_s > 0.1) {
      r.fail(ph["time_step_s"], "physics.time_step_s",
             "got " + ph["time_step_s"].Scalar() + ", expected a time step of at most 0.1 s");
    }
  }
}

// The objects: list, with ids and markers unique across the scene.
void parse_objects(const Reader& r, const YAML::Node& root, SceneConfig& scene) {
  const YAML::Node objects = r.required(root, "", "objects");
  if (!objects.IsSequence() || objects.size() == 0) {
    r.fail(objects, "objects", "got " + Reader::shown(objects) + ", expected a non-empty list of objects");
  }
  std::map<std::string, std::string> object_keys;                      // id -> key path
  std::map<std::pair<std::string, int>, std::string> marker_keys;      // (family, id) -> key path
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const std::string key = "objects[" + std::to_string(i) + "]";
    ObjectConfig object = parse_object(r, objects[i], key);
    if (object_keys.count(object.id)) {
      r.fail(objects[i]["id"], key + ".id",
             "duplicate object id '" + object.id + "' (also " + object_keys[object.id] + "), expected unique ids");
    }
    object_keys[object.id] = key;
    for (std::size_t m = 0; m < object.markers.size(); ++m) {
      const auto marker_key = std::make_pair(object.markers[m].family, object.markers[m].id);
      const std::string this_key = key + ".markers[" + std::to_string(m) + "]";
      if (marker_keys.count(marker_key)) {
        r.fail(objects[i]["markers"][m]["id"], this_key + ".id",
               "duplicate marker " + marker_key.first + " id " + std::to_string(marker_key.second) + " (also at " +
                   marker_keys[marker_key] + "), expected each marker on one object only");
      }
      marker_keys[marker_key] = this_key;
    }
    scene.objects.push_back(std::move(object));
  }
}

SceneConfig load_scene_checked(const std::string& path_in) {
  const fs::path path = fs::absolute(path_in).lexically_normal();
  std::error_code fs_error;
  if (!fs::is_regular_file(path, fs_error)) throw ConfigError(path_in, 0, "", "scene file does not exist");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path.string());
  } catch (const YAML::Exception& e) {
    throw ConfigError(path.string(), e.mark.line >= 0 ? e.mark.line + 1 : 0, "", "not valid YAML: " + e.msg);
  }
  Reader r(path.string(), path.parent_path());
  r.only_keys(root, "", {"name", "camera", "lcm", "channels", "physics", "objects"});

  SceneConfig scene;
  scene.file = path.string();
  scene.name = r.string(r.required(root, "", "name"), "name");
  if (root["camera"].IsDefined()) scene.camera_file = r.path(root["camera"], "camera", "camera file");

  if (root["lcm"].IsDefined()) {
    r.only_keys(root["lcm"], "lcm", {"url"});
    if (root["lcm"]["url"].IsDefined()) scene.lcm_url = r.string(root["lcm"]["url"], "lcm.url");
  }
  if (root["channels"].IsDefined()) parse_channels(r, root["channels"], scene);
  if (root["physics"].IsDefined()) parse_physics(r, root["physics"], scene);
  parse_objects(r, root, scene);
  return scene;
}

}  // namespace

}  // namespace arphys::config
