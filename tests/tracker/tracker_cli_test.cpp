// The `tracker` executable's command-line contract on file sources: --help, JSON lines
// for an image folder and a video file, and clear refusals (exit code 2) for a missing
// source and a calibration that does not match the frames.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "arphys/image_t.hpp"
#include "configs/loader/camera_config.hpp"
#include "configs/loader/scene_config.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/image_message.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/spawn_process.hpp"
#include "tests/tracker/tracker_test_support.hpp"
#include "tracker/synthetic/marker_image_renderer.hpp"

namespace {

const std::string kTracker = std::string(ARPHYS_BINARY_DIR) + "/tracker/app/tracker";
const std::string kData = std::string(ARPHYS_SOURCE_DIR) + "/tests/data/";

using CliRun = arphys::testing::CommandRun;
CliRun run(const std::string& args) { return arphys::testing::run_command(kTracker + " " + args); }

std::vector<nlohmann::json> json_lines(const std::string& out) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '{') lines.push_back(nlohmann::json::parse(line));
  }
  return lines;
}

TEST(TrackerCli, HelpDocumentsTheContract) {
  const CliRun r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* option : {"--camera", "--source", "--scene", "--marker-size", "--impl", "--json", "--print", "--param",
                             "--filter", "--predict-s"}) {
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
  }
}

// The apriltag repository's photos as a folder, in the reference's detector configuration
// (decimation 1, no edge refinement inside apriltag): one JSON line per photo, named, with all
// 47 reference markers at their reference corners (within 1 px after refinement) and
// poses for the given marker size.
TEST(TrackerCli, JsonForAnImageFolder) {
  const CliRun r = run("--camera " + kData + "nominal_camera_799x533.yaml --source " + kData +
                    "apriltag_photos --marker-size 0.05 --param decimate=1 --param refine_edges=0 --json --no-lcm");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto lines = json_lines(r.out);
  ASSERT_EQ(lines.size(), 3u);
  int markers = 0, matched = 0;
  for (const auto& frame : lines) {
    const std::string name = frame.at("source");
    const auto refs = arphys::tracking::testing::read_reference_detections(
        kData + "apriltag_photos/" + name.substr(0, name.size() - 4) + ".txt");
    for (const auto& m : frame.at("markers")) {
      ++markers;
      EXPECT_EQ(m.at("family"), "tag36h11");
      EXPECT_EQ(m.at("position_m").size(), 3u);
      EXPECT_EQ(m.at("orientation_wxyz").size(), 4u);
      EXPECT_GT(m.at("position_m")[2].get<double>(), 0.0);  // in front of the camera
      for (const auto& ref : refs) {
        if (ref.id != m.at("id").get<int>()) continue;
        double worst = 0;
        for (int k = 0; k < 4; ++k) {
          worst = std::max(worst, std::hypot(m.at("corners")[k][0].get<double>() - ref.corners_px[k].x(),
                                             m.at("corners")[k][1].get<double>() - ref.corners_px[k].y()));
        }
        if (worst < 1.0) {
          ++matched;
          break;
        }
      }
    }
  }
  EXPECT_EQ(markers, 47);
  EXPECT_EQ(matched, 47);
}

// A video file of a moving marker (rendered at known poses): a line per frame, exit at
// the end, the marker found in every frame near its true position.
TEST(TrackerCli, JsonForAVideoFile) {
  const std::string camera_file = std::string(ARPHYS_SOURCE_DIR) + "/configs/cameras/synthetic_640x480.yaml";
  const auto camera = arphys::tracking::CameraModel::from_config(arphys::config::load_camera(camera_file));
  const std::string video = ::testing::TempDir() + "tracker_cli_test.avi";
  std::vector<Eigen::Vector3d> truth;
  {
    cv::VideoWriter writer(video, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 30, cv::Size(640, 480), false);
    ASSERT_TRUE(writer.isOpened());
    const cv::Mat background = arphys::tracking::clutter_background(640, 480, 4);
    for (int i = 0; i < 20; ++i) {
      const auto X = arphys::tracking::marker_pose_at(camera, 250 + 5 * i, 240, 0.5, 0.4, 0.1, 0.2);
      truth.push_back(X.translation());
      writer.write(arphys::tracking::render_markers(camera, {{"tag36h11", 8, 0.08, X}}, background));
    }
  }
  const CliRun r = run("--camera " + camera_file + " --source " + video + " --marker-size 0.08 --json --no-lcm");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto lines = json_lines(r.out);
  ASSERT_EQ(lines.size(), truth.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    ASSERT_EQ(lines[i].at("markers").size(), 1u) << "frame " << i;
    const auto& p = lines[i].at("markers")[0].at("position_m");
    const Eigen::Vector3d position(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    EXPECT_LT((position - truth[i]).norm(), 3e-3) << "frame " << i;  // JPEG-compressed frames
  }
  std::filesystem::remove(video);
}

// The paper's scene file: the table's corner markers and the box's face markers, rendered
// from a camera above the table; the JSON gives both objects TRACKED and the box where
// it was drawn (camera frame).
struct SceneRun {
  CliRun cli;
  arphys::geometry::Pose X_CB;  // the box in the camera, as rendered
};

// One frame of bunny_box_table.yaml's markers from above the table, run through
// `tracker --scene`; `moved_id`, if set, is rendered `shift_m` along the table's x from where
// the scene puts it (a marker stuck on in the wrong place).
SceneRun track_scene_frame(const std::string& folder_name, int moved_id = -1, double shift_m = 0) {
  const std::string scene_file = std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bunny_box_table.yaml";
  const auto scene = arphys::config::load_scene(scene_file);
  const auto camera = arphys::tracking::CameraModel::from_config(arphys::config::load_camera(scene.camera_file));
  arphys::geometry::Pose X_WC = arphys::geometry::Pose::Identity();
  X_WC.linear() = (Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(0.9, Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  X_WC.translation() = Eigen::Vector3d(0.1, -0.85, 0.75);
  std::vector<arphys::tracking::MarkerPlacement> placed;
  SceneRun run_result{{}, arphys::geometry::Pose::Identity()};
  for (const auto& o : scene.objects) {
    if (o.id == "box") run_result.X_CB = X_WC.inverse() * o.X_WO;
    for (const auto& m : o.markers) {
      arphys::geometry::Pose X_OM = m.X_OM;
      if (m.id == moved_id) X_OM.translation().x() += shift_m;
      placed.push_back({m.family, m.id, m.size_m, X_WC.inverse() * o.X_WO * X_OM});
    }
  }
  const std::string folder = ::testing::TempDir() + folder_name;
  std::filesystem::create_directories(folder);
  arphys::tracking::ImageEffects effects;
  effects.noise_sigma = 2;
  cv::imwrite(folder + "/frame_000.png",
              arphys::tracking::render_markers(camera, placed, arphys::tracking::clutter_background(640, 480, 6), effects));
  run_result.cli = run("--scene " + scene_file + " --source " + folder + " --json --no-lcm");
  if (!getenv("KEEP")) std::filesystem::remove_all(folder);
  return run_result;
}

std::map<std::string, nlohmann::json> objects_of_one_frame(const CliRun& r) {
  const auto lines = json_lines(r.out);
  EXPECT_EQ(lines.size(), 1u);
  std::map<std::string, nlohmann::json> objects;
  if (lines.empty()) return objects;
  for (const auto& o : lines[0].at("objects")) objects[o.at("id")] = o;
  return objects;
}

TEST(TrackerCli, ObjectsOfASceneFile) {
  const SceneRun r = track_scene_frame("tracker_scene_frames");
  ASSERT_EQ(r.cli.exit_code, 0) << r.cli.out;
  auto objects = objects_of_one_frame(r.cli);
  ASSERT_EQ(objects.count("table"), 1u);
  ASSERT_EQ(objects.count("box"), 1u);
  EXPECT_EQ(objects["table"].at("status"), "TRACKED");
  EXPECT_FALSE(objects["table"].contains("markers_rejected"));
  ASSERT_EQ(objects["box"].at("status"), "TRACKED");
  const auto& p = objects["box"].at("position_m");
  EXPECT_LT((Eigen::Vector3d(p[0], p[1], p[2]) - r.X_CB.translation()).norm(), 2e-3);
  EXPECT_GE(objects["box"].at("markers_used").size(), 2u);  // top and front faces
}

// A table marker 5 cm from where the scene puts it: the JSON names it under
// markers_rejected, the table stays TRACKED on the other two in view and the stderr summary counts it.
TEST(TrackerCli, AMarkerOffItsLayoutIsNamedAndLeftOut) {
  const SceneRun r = track_scene_frame("tracker_scene_moved_marker", 2, 0.05);
  ASSERT_EQ(r.cli.exit_code, 0) << r.cli.out;
  auto objects = objects_of_one_frame(r.cli);
  ASSERT_EQ(objects.count("table"), 1u);
  EXPECT_EQ(objects["table"].at("status"), "TRACKED");
  ASSERT_TRUE(objects["table"].contains("markers_rejected")) << objects["table"].dump();
  EXPECT_EQ(objects["table"].at("markers_rejected"), nlohmann::json::array({2}));
  EXPECT_EQ(objects["table"].at("markers_used"), nlohmann::json::array({1, 3}));  // marker 0 is out of view
  EXPECT_NE(r.cli.out.find("1 markers left out of fits"), std::string::npos) << r.cli.out;
}

// A folder played at its frame rate (--pace, --fps 10) and its frames republished on LCM
// for the renderer (--publish-images): every frame arrives, as a JPEG of the folder's
// picture size, stamped with its capture time, a tenth of a second apart as they are played.
TEST(TrackerCli, APacedFolderIsRepublishedFrameByFrame) {
  const std::string url = "udpm://239.255.76.67:7985?ttl=0";  // a port of its own
  if (!lcm::LCM(url).good()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  arphys::msg::Bus bus(url);
  std::vector<arphys::image_t> images;
  std::vector<std::chrono::steady_clock::time_point> arrivals;
  bus.subscribe<arphys::image_t>(arphys::config::SceneConfig().channels.camera_image,
                                 [&](const arphys::image_t& m, const lcm::ReceiveBuffer&, const std::string&) {
                                   images.push_back(m);
                                   arrivals.push_back(std::chrono::steady_clock::now());
                                 });
  const pid_t tracker = arphys::testing::spawn_process(
      {kTracker, "--camera", kData + "nominal_camera_799x533.yaml", "--source", kData + "apriltag_photos", "--marker-size",
       "0.05", "--fps", "10", "--pace", "--publish-images", "--lcm-url", url});
  ASSERT_GT(tracker, 0);
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (waitpid(tracker, &status, WNOHANG) == 0 && std::chrono::steady_clock::now() < deadline) bus.handle_timeout_ms(20);
  for (int k = 0; k < 10; ++k) bus.handle_timeout_ms(20);  // what is still on its way
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the tracker ends with the folder, status " << status;
  ASSERT_EQ(images.size(), 3u);  // the folder's three photos
  for (std::size_t k = 0; k < images.size(); ++k) {
    EXPECT_EQ(images[k].pixel_format, arphys::image_t::PIXEL_FORMAT_JPEG);
    const cv::Mat picture = arphys::msg::decode_image_message(images[k]);
    EXPECT_EQ(picture.cols, 799);
    EXPECT_EQ(picture.rows, 533);
    if (k > 0) {
      EXPECT_EQ(images[k].utime - images[k - 1].utime, 100'000);  // capture times at --fps 10
      EXPECT_EQ(images[k].seq, images[k - 1].seq + 1);
    }
  }
  // Played, not dumped: two frame intervals between the first and the last (a slower
  // machine only adds to it).
  EXPECT_GE(std::chrono::duration<double>(arrivals.back() - arrivals.front()).count(), 0.18);
}

TEST(TrackerCli, RefusesAMissingSourceAndAMismatchedCamera) {
  CliRun r = run("--source /nonexistent/video.mp4 --json --no-lcm");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("/nonexistent/video.mp4"), std::string::npos) << r.out;
  // A webcam that is not there (no camera on a CI machine: the device path is all it tests).
  r = run("--source /dev/video97 --json --no-lcm");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("cannot open camera /dev/video97"), std::string::npos) << r.out;
  r = run("--source " + kData + "apriltag_photos --json --no-lcm");  // default camera: 640x480
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("640x480"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("799x533"), std::string::npos) << r.out;
  r = run("--source " + kData + "apriltag_photos --impl vuforia");
  EXPECT_NE(r.exit_code, 0);
  r = run("--camera " + kData + "nominal_camera_799x533.yaml --source " + kData +
          "apriltag_photos --param decimate=zero --json --no-lcm");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("decimate"), std::string::npos) << r.out;
}

}  // namespace
