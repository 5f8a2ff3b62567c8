// The pipeline's messages as Foxglove JSON: each body drawn as its scene shape where the
// world state puts it, contacts as arrows along their normals, images as JPEG, transforms
// and tracked objects, and the protocol's binary Message Data layout.
#include "tools/view/foxglove_messages.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <websocketpp/base64/base64.hpp>

#include "lcmtypes/msg/image_message.hpp"

namespace {

using arphys::view::SceneDrawing;

arphys::config::SceneConfig scene() {
  return arphys::config::load_scene(arphys::config::default_config_dir() + "/scenes/bunny_box_table.yaml");
}

arphys::body_state_t body(const std::string& id, const std::string& model, double z) {
  arphys::body_state_t b{};
  b.body_id = id, b.model = model;
  b.X_WB.position_m[2] = z;
  b.X_WB.orientation_wxyz[0] = std::sqrt(0.5), b.X_WB.orientation_wxyz[3] = std::sqrt(0.5);
  return b;
}

TEST(FoxgloveMessages, EachBodyIsItsSceneShapeWhereTheStatePutsIt) {
  const SceneDrawing drawing(scene(), "http://h:1/models/");
  arphys::world_state_t state{};
  state.utime = 2'500'000;
  state.bodies = {body("table", "table", -0.02), body("bunny#7", "bunny", 0.31), body("ghost", "unknown", 0)};
  state.num_bodies = 3;
  arphys::contact_t c{};
  c.n_W[1] = -1;
  state.contacts = {c};
  state.num_contacts = 1;
  const nlohmann::json update = drawing.scene_update(state);
  EXPECT_EQ(update["deletions"][0]["type"], 1);  // all, then this state's bodies
  const nlohmann::json& e = update["entities"];
  ASSERT_EQ(e.size(), 3u);  // table, bunny, contacts: a body of no scene model is not drawn
  EXPECT_EQ(e[0]["cubes"][0]["size"]["x"], 1.2);
  EXPECT_LT(e[0]["cubes"][0]["color"]["a"].get<double>(), 1.0);  // real: translucent
  EXPECT_EQ(e[0]["timestamp"]["sec"], 2);
  EXPECT_EQ(e[0]["timestamp"]["nsec"], 500'000'000);
  const nlohmann::json& bunny = e[1]["models"][0];
  EXPECT_EQ(e[1]["id"], "bunny#7");
  EXPECT_EQ(bunny["url"], "http://h:1/models/stanford-bunny-1k.obj");
  EXPECT_EQ(bunny["scale"]["x"], 0.8);
  EXPECT_EQ(bunny["pose"]["position"]["z"], 0.31);
  EXPECT_NEAR(bunny["pose"]["orientation"]["z"].get<double>(), std::sqrt(0.5), 1e-15);
  EXPECT_EQ(bunny["color"]["a"], 1.0);
  // The arrow's +x turned onto the normal -y: a quarter turn about -z.
  const nlohmann::json& q = e[2]["arrows"][0]["pose"]["orientation"];
  EXPECT_NEAR(q["z"].get<double>(), -std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(q["w"].get<double>(), std::sqrt(0.5), 1e-12);
  EXPECT_EQ(drawing.model_files().count("stanford-bunny-1k.obj"), 1u);
}

TEST(FoxgloveMessages, ImagesAreJpegsOfTheFrameAndBadOnesAreRefused) {
  const cv::Mat frame(48, 64, CV_8UC3, cv::Scalar(10, 200, 30));
  for (int quality : {0, 90}) {  // raw BGR, then JPEG
    const nlohmann::json image =
        arphys::view::compressed_image(arphys::msg::encode_image_message(frame, 7, 1, "cam", quality), "cam");
    EXPECT_EQ(image["format"], "jpeg");
    const std::string jpeg = websocketpp::base64_decode(image["data"].get<std::string>());
    ASSERT_GT(jpeg.size(), 4u);
    EXPECT_EQ(static_cast<unsigned char>(jpeg[0]), 0xff);
    EXPECT_EQ(static_cast<unsigned char>(jpeg[1]), 0xd8);
  }
  arphys::image_t broken = arphys::msg::encode_image_message(frame, 7, 1, "cam", 0);
  broken.size = 3;
  broken.data.resize(3);
  EXPECT_THROW(arphys::view::compressed_image(broken, "cam"), std::invalid_argument);
  arphys::image_t not_jpeg = arphys::msg::encode_image_message(frame, 7, 1, "cam", 90);
  not_jpeg.data[0] = 0;
  EXPECT_THROW(arphys::view::compressed_image(not_jpeg, "cam"), std::invalid_argument);
  not_jpeg.data[0] = 0xff;
  not_jpeg.size += 1;
  EXPECT_THROW(arphys::view::compressed_image(not_jpeg, "cam"), std::invalid_argument);
}

TEST(FoxgloveMessages, TransformsAndObjectsComeFromTheTrackedPoses) {
  arphys::object_poses_t poses{};
  poses.camera_id = "cam0", poses.camera_world_valid = true;
  poses.X_WC.position_m[2] = 1.5;
  arphys::object_pose_t seen{}, lost{};
  seen.object_id = "box", seen.world_valid = true, seen.X_WO.position_m[0] = 0.25, seen.num_markers_used = 3;
  seen.rejected_marker_ids = {12};
  seen.num_markers_rejected = 1;
  lost.object_id = "spoon", lost.status = arphys::object_pose_t::STATUS_LOST, lost.status_reason = "no marker";
  poses.objects = {seen, lost};
  poses.num_objects = 2;
  const nlohmann::json tf = arphys::view::frame_transforms(poses)["transforms"];
  ASSERT_EQ(tf.size(), 2u);  // the lost object has no world pose
  EXPECT_EQ(tf[0]["child_frame_id"], "cam0");
  EXPECT_EQ(tf[0]["translation"]["z"], 1.5);
  EXPECT_EQ(tf[1]["parent_frame_id"], "world");
  EXPECT_EQ(tf[1]["translation"]["x"], 0.25);
  const nlohmann::json objects = arphys::view::tracked_objects(poses)["objects"];
  EXPECT_EQ(objects[0]["status"], "TRACKED");
  EXPECT_EQ(objects[0]["markers_rejected"][0], 12);
  EXPECT_EQ(objects[1]["status"], "LOST");
  EXPECT_EQ(objects[1]["reason"], "no marker");
}

TEST(FoxgloveMessages, MessageDataIsOpcodeSubscriptionTimeThenPayload) {
  const std::string frame = arphys::view::message_data(0x01020304u, 0x1122334455667788ull, "{}");
  ASSERT_EQ(frame.size(), 15u);
  const std::string head("\x01\x04\x03\x02\x01\x88\x77\x66\x55\x44\x33\x22\x11", 13);
  EXPECT_EQ(frame.substr(0, 13), head);
  EXPECT_EQ(frame.substr(13), "{}");
  EXPECT_EQ(arphys::view::topics().size(), static_cast<std::size_t>(arphys::view::kTopicCount));
  EXPECT_EQ(arphys::view::topics()[arphys::view::kWorld].schema_name, "foxglove.SceneUpdate");
  EXPECT_TRUE(nlohmann::json::parse(arphys::view::topics()[arphys::view::kWorld].schema).contains("properties"));
}

}  // namespace
