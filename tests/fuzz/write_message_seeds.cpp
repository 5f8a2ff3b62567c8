// Writes one valid message of each kind fuzz_messages decodes, in its input format (a
// kind byte, then the LCM encoding), into the folder given. Built from the current
// message types, so a changed type never leaves the fuzzer with seeds it cannot decode.
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "arphys/image_t.hpp"
#include "arphys/marker_detections_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/sim_command_t.hpp"
#include "arphys/tracker_control_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"

namespace {

template <class Message>
bool write_seed(const std::string& folder, int kind, const Message& message) {
  std::vector<uint8_t> bytes(1 + message.getEncodedSize());
  bytes[0] = static_cast<uint8_t>(kind);
  if (message.encode(bytes.data() + 1, 0, static_cast<int>(bytes.size() - 1)) < 0) return false;
  const std::string path = folder + "/seed_kind" + std::to_string(kind);
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return static_cast<bool>(out);
}

arphys::pose_t a_pose() {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() << 0.1, -0.2, 0.5;
  return arphys::msg::to_message(X);
}

arphys::image_t an_image() {
  arphys::image_t m{};
  m.camera_id = "cam";
  m.width = 4;
  m.height = 2;
  m.row_stride = 4;
  m.pixel_format = arphys::image_t::PIXEL_FORMAT_GRAY8;
  m.data.assign(8, 128);
  m.size = static_cast<int32_t>(m.data.size());
  return m;
}

arphys::object_poses_t some_poses() {
  arphys::object_poses_t m{};
  m.camera_id = "cam";
  m.tracker_implementation = "apriltag";
  m.camera_world_valid = true;
  m.X_WC = a_pose();
  arphys::object_pose_t o{};
  o.object_id = "box";
  o.X_CO = a_pose();
  o.X_WO = a_pose();
  o.marker_ids = {1, 2};
  o.num_markers_used = 2;
  o.rejected_marker_ids = {3};
  o.num_markers_rejected = 1;
  o.status_reason = "";
  m.objects.push_back(o);
  m.num_objects = 1;
  return m;
}

arphys::world_state_t a_world() {
  arphys::world_state_t m{};
  m.scene_name = "scene";
  arphys::body_state_t b{};
  b.body_id = "bunny";
  b.model = "bunny.obj";
  b.role = arphys::body_state_t::ROLE_VIRTUAL;
  b.motion = arphys::body_state_t::MOTION_DYNAMIC;
  b.X_WB = a_pose();
  m.bodies.push_back(b);
  m.num_bodies = 1;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s FOLDER\n  writes one seed input per message kind of fuzz_messages into FOLDER\n",
                 argv[0]);
    return 2;
  }
  const std::string folder = argv[1];
  arphys::sim_command_t command{};
  command.X_WB = a_pose();
  arphys::marker_detections_t detections{};
  const bool ok = write_seed(folder, 0, an_image()) && write_seed(folder, 1, some_poses()) &&
                  write_seed(folder, 2, a_world()) && write_seed(folder, 3, command) &&
                  write_seed(folder, 4, arphys::tracker_control_t{}) && write_seed(folder, 5, detections) &&
                  write_seed(folder, 6, arphys::render_status_t{}) && write_seed(folder, 7, arphys::process_status_t{});
  if (!ok) std::fprintf(stderr, "write_message_seeds: cannot write into %s\n", folder.c_str());
  return ok ? 0 : 1;
}
