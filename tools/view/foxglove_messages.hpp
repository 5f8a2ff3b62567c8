#pragma once
// The pipeline's LCM messages as Foxglove messages (JSON encoding, the `foxglove.*` schemas),
// transport-free: what arphys-view sends on each topic of the Foxglove WebSocket protocol
// (docs/pipeline.md, "Watching a run").
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "arphys/image_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/world_state_t.hpp"
#include "configs/loader/scene_config.hpp"

namespace arphys::view {

// One advertised topic: its name, the foxglove schema it carries and that schema (JSON Schema).
struct Topic {
  std::string topic, schema_name, schema;
};
// The topics in channel-id order: /camera/image, /overlay, /world, /tf, /status, /latency, /objects.
enum TopicId { kCameraImage = 0, kOverlay, kWorld, kTf, kStatus, kLatency, kObjects, kTopicCount };
const std::vector<Topic>& topics();

// foxglove.CompressedImage of a JPEG frame (passed on as it is); a raw frame is encoded to JPEG
// first. Throws std::invalid_argument saying why for a raw frame that does not decode or a
// JPEG one whose size disagrees or that does not start as a JPEG.
nlohmann::json compressed_image(const arphys::image_t& image, const std::string& frame_id);
// A process heartbeat (name, state, counters, figures) for plots.
nlohmann::json status(const arphys::process_status_t& status);
// The renderer's per-frame stage times in milliseconds since capture, for plots.
nlohmann::json latency(const arphys::render_status_t& status);
// foxglove.FrameTransforms: world -> camera (when the tracker knows it) and world -> each
// tracked object with a world pose.
nlohmann::json frame_transforms(const arphys::object_poses_t& poses);
// The tracker's word on each object: status (TRACKED, PREDICTED, LOST) with its reason,
// reprojection error, and the markers used and rejected.
nlohmann::json tracked_objects(const arphys::object_poses_t& poses);

// The bodies of a scene as Foxglove scene entities. Meshes and convex pieces are served as
// OBJ files under url_prefix (sent once, then referenced by each update).
class SceneDrawing {
 public:
  // url_prefix: where model_files() are served ("http://127.0.0.1:8765/models/").
  SceneDrawing(const config::SceneConfig& scene, const std::string& url_prefix);
  // foxglove.SceneUpdate: one entity per body (id = body id, frame "world"), real bodies
  // translucent, and an entity "contacts" with an arrow along each contact normal.
  nlohmann::json scene_update(const arphys::world_state_t& state) const;
  // The files served: name under url_prefix -> absolute path.
  const std::map<std::string, std::string>& model_files() const { return files_; }

 private:
  struct Look {
    config::ShapeType type = config::ShapeType::kBox;
    config::ShapeConfig shape;
    std::string url;  // meshes and convex pieces
    bool real = false;
  };
  nlohmann::json entity(const arphys::body_state_t& body, const Look& look, const nlohmann::json& stamp) const;
  std::map<std::string, Look> looks_;  // by model (the scene object id)
  std::map<std::string, std::string> files_;
};

// A Message Data frame of the protocol: opcode 1, subscription id and receive time
// (little-endian), then the payload.
std::string message_data(uint32_t subscription_id, uint64_t time_ns, const std::string& payload);

}  // namespace arphys::view
