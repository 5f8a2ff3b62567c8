#include "configs/loader/camera_script.hpp"

#include "configs/loader/yaml_reader.hpp"

namespace arphys::config {

namespace {

// The camera pose either as a pose or as eye and target points (z up in the world).
geometry::Pose camera_pose(const Reader& r, const YAML::Node& node, const std::string& key) {
  if (node["look_at"].IsDefined()) {
    const YAML::Node look = node["look_at"];
    const std::string k = key + ".look_at";
    r.only_keys(look, k, {"eye_m", "target_m"});
    const Eigen::Vector3d eye = r.vector(r.required(look, k, "eye_m"), k + ".eye_m", 3, "metres");
    const Eigen::Vector3d target = r.vector(r.required(look, k, "target_m"), k + ".target_m", 3, "metres");
    const Eigen::Vector3d z = (target - eye).normalized();
    if (!((target - eye).norm() > 1e-6) || std::abs(z.z()) > 0.999) {
      r.fail(look, k, "eye and target must differ and not be vertically aligned");
    }
    return geometry::look_at(eye, target);
  }
  return r.pose(r.required(node, key, "pose"), key + ".pose");
}

}  // namespace

namespace {
CameraScriptConfig load_camera_script_checked(const std::string& path);
}  // namespace

CameraScriptConfig load_camera_script(const std::string& path) {
  try {
    return load_camera_script_checked(path);
  } catch (const YAML::Exception& e) {
    throw ConfigError(path, e.mark.line >= 0 ? e.mark.line + 1 : 0, "", std::string("unreadable YAML: ") + e.msg);
  }
}

namespace {

CameraScriptConfig load_camera_script_checked(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code fs_error;
  if (!fs::exists(path, fs_error)) throw ConfigError(path, 0, "", "file does not exist");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw ConfigError(path, e.mark.line + 1, "", std::string("not valid YAML: ") + e.msg);
  }
  const std::string file = fs::absolute(path).string();
  Reader r(file, fs::path(file).parent_path());
  r.only_keys(root, "", {"scene", "camera", "frame_rate_hz", "duration_s", "effects", "trajectories"});
  CameraScriptConfig script;
  script.file = file;
  script.scene = load_scene(r.path(r.required(root, "", "scene"), "scene", "scene file"));
  const YAML::Node camera = r.required(root, "", "camera");
  r.only_keys(camera, "camera", {"pose", "look_at"});
  script.X_WC = camera_pose(r, camera, "camera");
  if (root["frame_rate_hz"].IsDefined()) {
    script.frame_rate_hz = r.number(root["frame_rate_hz"], "frame_rate_hz", "a frame rate in [5, 60] Hz");
    if (script.frame_rate_hz < 5 || script.frame_rate_hz > 60) {
      r.fail(root["frame_rate_hz"], "frame_rate_hz", "got " + root["frame_rate_hz"].Scalar() + ", expected 5 to 60 Hz");
    }
  }
  if (root["duration_s"].IsDefined()) script.duration_s = r.positive(root["duration_s"], "duration_s", "a positive duration in seconds");
  if (root["effects"].IsDefined()) {
    const YAML::Node e = root["effects"];
    r.only_keys(e, "effects", {"noise_sigma", "motion_blur_px", "exposure_jitter", "drop_rate", "delay_ms", "seed"});
    auto& fx = script.effects;
    auto non_negative = [&](const char* name, double* out, double max_value) {
      if (!e[name].IsDefined()) return;
      *out = r.number(e[name], std::string("effects.") + name, "a number >= 0");
      if (*out < 0 || *out > max_value) {
        r.fail(e[name], std::string("effects.") + name, "got " + e[name].Scalar() + ", expected 0 to " + std::to_string(max_value));
      }
    };
    non_negative("noise_sigma", &fx.noise_sigma, 100);
    non_negative("motion_blur_px", &fx.motion_blur_px, 100);
    non_negative("exposure_jitter", &fx.exposure_jitter, 1);
    non_negative("drop_rate", &fx.drop_rate, 0.99);
    non_negative("delay_ms", &fx.delay_ms, 10000);
    if (e["seed"].IsDefined()) fx.seed = static_cast<uint32_t>(r.integer(e["seed"], "effects.seed", "a non-negative integer"));
  }
  if (root["trajectories"].IsDefined()) {
    const YAML::Node t = root["trajectories"];
    if (!t.IsMap()) r.fail(t, "trajectories", "got " + Reader::shown(t) + ", expected a map from object id to keyframes");
    for (const auto& entry : t) {
      const std::string id = r.key_name(entry.first, "trajectories");
      const std::string key = "trajectories." + id;
      const ObjectConfig* object = script.scene.find_object(id);
      if (!object || object->role != Role::kReal) r.fail(entry.first, key, "no real object '" + id + "' in the scene");
      if (!entry.second.IsSequence() || entry.second.size() == 0) r.fail(entry.second, key, "expected a list of keyframes");
      std::vector<TimedPoseConfig> keys;
      for (std::size_t i = 0; i < entry.second.size(); ++i) {
        const YAML::Node k = entry.second[i];
        const std::string kk = key + "[" + std::to_string(i) + "]";
        r.only_keys(k, kk, {"t_s", "pose"});
        TimedPoseConfig sample;
        sample.t_s = r.number(r.required(k, kk, "t_s"), kk + ".t_s", "a time in seconds");
        if (!keys.empty() && sample.t_s <= keys.back().t_s) r.fail(k, kk + ".t_s", "times must increase");
        sample.X_WO = r.pose(r.required(k, kk, "pose"), kk + ".pose");
        keys.push_back(sample);
      }
      script.trajectories[id] = keys;
    }
  }
  return script;
}

}  // namespace

}  // namespace arphys::config
