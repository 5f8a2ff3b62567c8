// Every LCM message type the processes receive, decoded from arbitrary bytes and put
// through the same checks the processes apply (pose validation, image decoding). A
// decoder that reads out of bounds, a check that crashes or throws anything but the
// documented std::invalid_argument is a finding.
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "arphys/image_t.hpp"
#include "arphys/marker_detections_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/sim_command_t.hpp"
#include "arphys/tracker_control_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/image_message.hpp"
#include "lcmtypes/msg/pose_conversions.hpp"

namespace {

void check_pose(const arphys::pose_t& pose) {
  if (!arphys::msg::pose_problem(pose).empty()) return;
  arphys::msg::from_message(pose, "fuzzed pose");  // accepted poses must convert
}

template <class Message>
bool decode(const uint8_t* data, size_t size, Message& message) {
  return message.decode(data, 0, static_cast<int>(size)) >= 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t kind = data[0] % 8;
  ++data;
  --size;
  switch (kind) {
    case 0: {
      arphys::image_t m;
      if (!decode(data, size, m)) return 0;
      try {
        arphys::msg::decode_image_message(m);
      } catch (const std::invalid_argument&) {
      }
      break;
    }
    case 1: {
      arphys::object_poses_t m;
      if (!decode(data, size, m)) return 0;
      check_pose(m.X_WC);
      for (const auto& o : m.objects) {
        check_pose(o.X_CO);
        check_pose(o.X_WO);
      }
      break;
    }
    case 2: {
      arphys::world_state_t m;
      if (!decode(data, size, m)) return 0;
      for (const auto& b : m.bodies) check_pose(b.X_WB);
      break;
    }
    case 3: {
      arphys::sim_command_t m;
      if (decode(data, size, m)) check_pose(m.X_WB);
      break;
    }
    case 4: {
      arphys::tracker_control_t m;
      decode(data, size, m);
      break;
    }
    case 5: {
      arphys::marker_detections_t m;
      if (!decode(data, size, m)) return 0;
      for (const auto& d : m.markers) check_pose(d.X_CM);
      break;
    }
    case 6: {
      arphys::render_status_t m;
      decode(data, size, m);
      break;
    }
    default: {
      arphys::process_status_t m;
      decode(data, size, m);
    }
  }
  return 0;
}
