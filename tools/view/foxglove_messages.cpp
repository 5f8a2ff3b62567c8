#include "tools/view/foxglove_messages.hpp"

#include <Eigen/Geometry>
#include <filesystem>
#include <stdexcept>
#include <websocketpp/base64/base64.hpp>

#include "lcmtypes/msg/image_message.hpp"

namespace arphys::view {
namespace {

using nlohmann::json;

json stamp(int64_t utime) {
  const int64_t sec = utime >= 0 ? utime / 1000000 : 0;
  return {{"sec", sec}, {"nsec", (utime >= 0 ? utime % 1000000 : 0) * 1000}};
}

json vec3(const double* v) { return {{"x", v[0]}, {"y", v[1]}, {"z", v[2]}}; }
json quat(const double* wxyz) { return {{"x", wxyz[1]}, {"y", wxyz[2]}, {"z", wxyz[3]}, {"w", wxyz[0]}}; }
json pose(const arphys::pose_t& p) {
  return {{"position", vec3(p.position_m)}, {"orientation", quat(p.orientation_wxyz)}};
}
json rgba(double r, double g, double b, double a) { return {{"r", r}, {"g", g}, {"b", b}, {"a", a}}; }

// JSON Schemas of the foxglove types as far as arphys fills them.
json object_of(json properties) { return {{"type", "object"}, {"properties", std::move(properties)}}; }
const json kNumber = {{"type", "number"}};
const json kString = {{"type", "string"}};
json time_schema() { return object_of({{"sec", {{"type", "integer"}}}, {"nsec", {{"type", "integer"}}}}); }
json xyz_schema() { return object_of({{"x", kNumber}, {"y", kNumber}, {"z", kNumber}}); }
json quaternion_schema() { return object_of({{"x", kNumber}, {"y", kNumber}, {"z", kNumber}, {"w", kNumber}}); }
json pose_schema() { return object_of({{"position", xyz_schema()}, {"orientation", quaternion_schema()}}); }
json array_of(json items) { return {{"type", "array"}, {"items", std::move(items)}}; }

std::string image_schema() {
  return object_of({{"timestamp", time_schema()},
                    {"frame_id", kString},
                    {"data", {{"type", "string"}, {"contentEncoding", "base64"}}},
                    {"format", kString}})
      .dump();
}

std::string scene_update_schema() {
  const json color = object_of({{"r", kNumber}, {"g", kNumber}, {"b", kNumber}, {"a", kNumber}});
  const json sized = object_of({{"pose", pose_schema()}, {"size", xyz_schema()}, {"color", color}});
  const json arrow = object_of({{"pose", pose_schema()},
                                {"shaft_length", kNumber},
                                {"shaft_diameter", kNumber},
                                {"head_length", kNumber},
                                {"head_diameter", kNumber},
                                {"color", color}});
  const json model = object_of({{"pose", pose_schema()},
                                {"scale", xyz_schema()},
                                {"color", color},
                                {"override_color", {{"type", "boolean"}}},
                                {"url", kString},
                                {"media_type", kString},
                                {"data", {{"type", "string"}, {"contentEncoding", "base64"}}}});
  const json entity = object_of({{"timestamp", time_schema()},
                                 {"frame_id", kString},
                                 {"id", kString},
                                 {"lifetime", time_schema()},
                                 {"frame_locked", {{"type", "boolean"}}},
                                 {"cubes", array_of(sized)},
                                 {"spheres", array_of(sized)},
                                 {"arrows", array_of(arrow)},
                                 {"models", array_of(model)}});
  return object_of(
             {{"deletions",
               array_of(object_of({{"timestamp", time_schema()}, {"type", {{"type", "integer"}}}, {"id", kString}}))},
              {"entities", array_of(entity)}})
      .dump();
}

std::string transforms_schema() {
  const json transform = object_of({{"timestamp", time_schema()},
                                    {"parent_frame_id", kString},
                                    {"child_frame_id", kString},
                                    {"translation", xyz_schema()},
                                    {"rotation", quaternion_schema()}});
  return object_of({{"transforms", array_of(transform)}}).dump();
}

// The rotation taking +x (a foxglove arrow's direction) to the unit vector n.
json arrow_orientation(const double* n) {
  const Eigen::Quaterniond q =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), Eigen::Vector3d(n[0], n[1], n[2]));
  return {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}};
}

}  // namespace

const std::vector<Topic>& topics() {
  static const std::vector<Topic> all = {
      {"/camera/image", "foxglove.CompressedImage", image_schema()},
      {"/overlay", "foxglove.CompressedImage", image_schema()},
      {"/world", "foxglove.SceneUpdate", scene_update_schema()},
      {"/tf", "foxglove.FrameTransforms", transforms_schema()},
      {"/status", "arphys.ProcessStatus", object_of({{"name", kString}, {"state", kString}}).dump()},
      {"/latency", "arphys.FrameLatency", object_of({{"capture_to_publish_ms", kNumber}}).dump()},
      {"/objects", "arphys.TrackedObjects",
       object_of({{"objects", array_of(object_of({{"id", kString}, {"status", kString}}))}}).dump()},
  };
  return all;
}

json compressed_image(const arphys::image_t& image, const std::string& frame_id) {
  std::string bytes;
  if (image.pixel_format == arphys::image_t::PIXEL_FORMAT_JPEG) {
    // Passed on as it is, checked only for its size and JPEG's start-of-image marker: decoding
    // each frame to check it was most of the view's CPU (the client decodes it anyway).
    if (image.size != static_cast<int32_t>(image.data.size()) || image.data.size() < 4 || image.data[0] != 0xff ||
        image.data[1] != 0xd8)
      throw std::invalid_argument("a JPEG image_t whose size disagrees with its bytes or that is no JPEG");
    bytes.assign(image.data.begin(), image.data.end());
  } else {
    const arphys::image_t jpeg =
        msg::encode_image_message(msg::decode_image_message(image), image.utime, image.seq, image.camera_id, 85);
    bytes.assign(jpeg.data.begin(), jpeg.data.end());
  }
  return {{"timestamp", stamp(image.utime)},
          {"frame_id", frame_id},
          {"data", websocketpp::base64_encode(reinterpret_cast<const unsigned char*>(bytes.data()),
                                              static_cast<unsigned int>(bytes.size()))},
          {"format", "jpeg"}};
}

json status(const arphys::process_status_t& s) {
  json figures = json::object();
  for (int k = 0; k < s.num_figures; ++k) figures[s.figure_names[k]] = s.figure_values[k];
  return {{"timestamp", stamp(s.utime)},
          {"name", s.name},
          {"implementation", s.implementation},
          {"state", s.state},
          {"rate_hz", s.rate_hz},
          {"stage_duration_ms", s.stage_duration_ms},
          {"received", s.received},
          {"published", s.published},
          {"dropped", s.dropped},
          {"rejected", s.rejected},
          {"figures", figures}};
}

json latency(const arphys::render_status_t& s) {
  const auto ms_since_capture = [&](int64_t utime) { return utime > 0 ? (utime - s.utime) / 1000.0 : 0.0; };
  return {{"timestamp", stamp(s.utime)},
          {"seq", s.seq},
          {"world_state_match", s.world_state_match},
          {"render_start_ms", ms_since_capture(s.render_start_utime)},
          {"render_end_ms", ms_since_capture(s.render_end_utime)},
          {"capture_to_publish_ms", ms_since_capture(s.publish_utime)}};
}

json frame_transforms(const arphys::object_poses_t& poses) {
  json transforms = json::array();
  const auto add = [&](const std::string& child, const arphys::pose_t& X_WB) {
    transforms.push_back({{"timestamp", stamp(poses.utime)},
                          {"parent_frame_id", "world"},
                          {"child_frame_id", child},
                          {"translation", vec3(X_WB.position_m)},
                          {"rotation", quat(X_WB.orientation_wxyz)}});
  };
  if (poses.camera_world_valid) add(poses.camera_id.empty() ? "camera" : poses.camera_id, poses.X_WC);
  for (const arphys::object_pose_t& object : poses.objects)
    if (object.world_valid) add(object.object_id, object.X_WO);
  return {{"transforms", transforms}};
}

json tracked_objects(const arphys::object_poses_t& poses) {
  static const char* const kStatus[] = {"TRACKED", "PREDICTED", "LOST"};
  json objects = json::array();
  for (const arphys::object_pose_t& o : poses.objects)
    objects.push_back({{"id", o.object_id},
                       {"status", o.status >= 0 && o.status <= 2 ? kStatus[o.status] : "UNKNOWN"},
                       {"reason", o.status_reason},
                       {"reprojection_error_px", o.reprojection_error_px},
                       {"markers_used", o.num_markers_used},
                       {"markers_rejected", o.rejected_marker_ids}});
  return {{"timestamp", stamp(poses.utime)}, {"tracker", poses.tracker_implementation}, {"objects", objects}};
}

SceneDrawing::SceneDrawing(const config::SceneConfig& scene, const std::string& url_prefix) {
  for (const config::ObjectConfig& object : scene.objects) {
    Look look;
    look.shape = object.render;
    look.type = object.render.type;
    look.real = object.role == config::Role::kReal;
    const std::string& file =
        look.type == config::ShapeType::kConvexSet ? look.shape.pieces_path : look.shape.mesh_path;
    if (look.type == config::ShapeType::kMesh || look.type == config::ShapeType::kConvexSet) {
      const std::string name = std::filesystem::path(file).filename().string();
      files_[name] = file;
      look.url = url_prefix + name;
    }
    looks_[object.id] = look;
  }
}

json SceneDrawing::entity(const arphys::body_state_t& body, const Look& look, const json& when) const {
  json e = {{"timestamp", when},     {"frame_id", "world"},    {"id", body.body_id},       {"lifetime", stamp(0)},
            {"frame_locked", false}, {"cubes", json::array()}, {"spheres", json::array()}, {"models", json::array()}};
  const json color = look.real ? rgba(0.3, 0.6, 1.0, 0.35) : rgba(0.85, 0.75, 0.6, 1.0);
  const json X = pose(body.X_WB);
  switch (look.type) {
    case config::ShapeType::kBox: {
      const Eigen::Vector3d& s = look.shape.size_m;
      e["cubes"].push_back({{"pose", X}, {"size", {{"x", s.x()}, {"y", s.y()}, {"z", s.z()}}}, {"color", color}});
      break;
    }
    case config::ShapeType::kSphere: {
      const double d = 2 * look.shape.radius_m;
      e["spheres"].push_back({{"pose", X}, {"size", {{"x", d}, {"y", d}, {"z", d}}}, {"color", color}});
      break;
    }
    case config::ShapeType::kPlane: {  // the half space z <= 0 of the body: a 4 m square, 1 mm thick, its top at z = 0
      const Eigen::Quaterniond q(body.X_WB.orientation_wxyz[0], body.X_WB.orientation_wxyz[1],
                                 body.X_WB.orientation_wxyz[2], body.X_WB.orientation_wxyz[3]);
      const Eigen::Vector3d centre =
          Eigen::Vector3d(body.X_WB.position_m[0], body.X_WB.position_m[1], body.X_WB.position_m[2]) +
          q.normalized() * Eigen::Vector3d(0, 0, -5e-4);
      json at = X;
      at["position"] = {{"x", centre.x()}, {"y", centre.y()}, {"z", centre.z()}};
      e["cubes"].push_back(
          {{"pose", at}, {"size", {{"x", 4.0}, {"y", 4.0}, {"z", 1e-3}}}, {"color", rgba(0.5, 0.5, 0.5, 0.3)}});
      break;
    }
    default: {
      const Eigen::Vector3d& s = look.shape.scale;
      e["models"].push_back({{"pose", X},
                             {"scale", {{"x", s.x()}, {"y", s.y()}, {"z", s.z()}}},
                             {"color", color},
                             {"override_color", true},
                             {"url", look.url},
                             {"media_type", "model/obj"}});
    }
  }
  return e;
}

json SceneDrawing::scene_update(const arphys::world_state_t& state) const {
  const json when = stamp(state.utime);
  json entities = json::array();
  for (const arphys::body_state_t& body : state.bodies) {
    const auto it = looks_.find(body.model);
    if (it != looks_.end()) entities.push_back(entity(body, it->second, when));
  }
  json arrows = json::array();
  for (const arphys::contact_t& c : state.contacts)
    arrows.push_back({{"pose", {{"position", vec3(c.p_W_m)}, {"orientation", arrow_orientation(c.n_W)}}},
                      {"shaft_length", 0.02},
                      {"shaft_diameter", 0.002},
                      {"head_length", 0.006},
                      {"head_diameter", 0.005},
                      {"color", rgba(1.0, 0.2, 0.2, 1.0)}});
  entities.push_back({{"timestamp", when},
                      {"frame_id", "world"},
                      {"id", "contacts"},
                      {"lifetime", stamp(0)},
                      {"frame_locked", false},
                      {"arrows", arrows}});
  // Everything drawn before goes first (deletion type 1: all), so a removed body disappears.
  return {{"deletions", json::array({{{"timestamp", when}, {"type", 1}, {"id", ""}}})}, {"entities", entities}};
}

std::string message_data(uint32_t subscription_id, uint64_t time_ns, const std::string& payload) {
  std::string frame(1 + 4 + 8, '\0');
  frame[0] = 0x01;
  for (int k = 0; k < 4; ++k) frame[1 + k] = static_cast<char>((subscription_id >> (8 * k)) & 0xff);
  for (int k = 0; k < 8; ++k) frame[5 + k] = static_cast<char>((time_ns >> (8 * k)) & 0xff);
  return frame + payload;
}

}  // namespace arphys::view
