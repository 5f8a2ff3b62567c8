#include "tools/launch/process_commands.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace arphys::launch {
namespace {

config::SceneConfig box_scene() {
  return config::load_scene(config::default_config_dir() + "/scenes/bunny_box_table.yaml");
}

bool has(const std::vector<std::string>& args, const std::string& flag, const std::string& value) {
  const auto it = std::find(args.begin(), args.end(), flag);
  return it != args.end() && it + 1 != args.end() && *(it + 1) == value;
}

// Whether `flag` is among `args` (or a name among names).
bool has_flag(const std::vector<std::string>& args, const std::string& flag) {
  return std::find(args.begin(), args.end(), flag) != args.end();
}

std::vector<std::string> names_of(const std::vector<ProcessCommand>& commands) {
  std::vector<std::string> names;
  for (const auto& c : commands) names.push_back(c.name);
  return names;
}

// The shipped application-2 scene, its synthetic camera script (for runs that have one), and the
// build directory /b.
class ProcessCommands : public ::testing::Test {
 protected:
  const config::SceneConfig scene = box_scene();
  const config::CameraScriptConfig script = config::load_camera_script(default_script_for(scene));
  LaunchOptions o = [] {
    LaunchOptions options;
    options.build_dir = "/b";
    return options;
  }();
};

TEST_F(ProcessCommands, SyntheticRunStartsTheCameraLastWithTheScenesUrl) {
  o.sim_threads = 2;
  o.out_dir = "/out";
  o.record = true;
  const auto commands = process_commands(o, scene, &script, "/out/simulator.state");
  EXPECT_EQ(names_of(commands), (std::vector<std::string>{"recorder", "simulator", "renderer", "tracker", "camera"}));
  const auto& simulator = commands[1].args;
  EXPECT_EQ(simulator[0], "/b/simulator/app/arphys-simulator");
  EXPECT_TRUE(has(simulator, "--threads", "2"));
  EXPECT_TRUE(has(simulator, "--state-file", "/out/simulator.state"));
  EXPECT_TRUE(has(simulator, "--lcm-url", scene.lcm_url));
  EXPECT_TRUE(has(commands[2].args, "--video", "/out/overlay.avi"));
  EXPECT_TRUE(has_flag(commands[2].args, "--camera-pose"));
  EXPECT_EQ(commands[0].args.back(), "/out/run.lcmlog");
}

TEST_F(ProcessCommands, RealSourceGoesToTheTrackerAndOnlyPicksProcesses) {
  o.camera = "clip.mp4";
  o.only = "tracker,renderer";
  o.lcm_url = "udpm://239.255.76.67:7667?ttl=1";
  const auto commands = process_commands(o, scene, nullptr, "s.state");
  ASSERT_EQ(commands.size(), 2u);
  EXPECT_EQ(commands[0].name, "renderer");
  EXPECT_FALSE(has_flag(commands[0].args, "--camera-pose"));
  EXPECT_TRUE(has(commands[1].args, "--source", "clip.mp4"));
  EXPECT_TRUE(has(commands[1].args, "--lcm-url", o.lcm_url));
  EXPECT_TRUE(ends_by_itself("tracker", o));  // a video file ends
  o.camera = "/dev/video0";
  EXPECT_FALSE(ends_by_itself("tracker", o));  // a webcam does not
  EXPECT_TRUE(ends_by_itself("camera", o));
  EXPECT_FALSE(ends_by_itself("simulator", o));
}

// A replay takes the camera's place: the recorded frames into a fresh tracker, or the poses
// into the simulator alone; the simulator steps to the recorded capture times.
TEST_F(ProcessCommands, AReplayPlaysTheLogInTheCamerasPlace) {
  o.replay_log = "/logs/run.lcmlog";
  auto commands = process_commands(o, scene, &script, "s.state");
  EXPECT_EQ(names_of(commands), (std::vector<std::string>{"simulator", "renderer", "tracker", "camera"}));
  EXPECT_TRUE(has(commands[0].args, "--clock", "messages"));
  EXPECT_TRUE(has_flag(commands[1].args, "--wait-ms"));
  const auto& replay = commands.back().args;
  EXPECT_EQ(replay[0], "/b/tools/replay/arphys-replay");
  EXPECT_EQ(replay[1], "/logs/run.lcmlog");
  EXPECT_TRUE(has(replay, "--channels",
                  scene.channels.camera_image + "|" + scene.channels.camera_info + "|" + scene.channels.ground_truth));
  o.replay_what = "poses";
  commands = process_commands(o, scene, &script, "s.state");
  EXPECT_EQ(names_of(commands), (std::vector<std::string>{"simulator", "renderer", "camera"}));
  EXPECT_TRUE(has(commands.back().args, "--channels", scene.channels.object_poses));
  EXPECT_TRUE(ends_by_itself("camera", o));
}

// --view starts arphys-view on the port, before the camera, and has the renderer publish its overlay.
TEST_F(ProcessCommands, AViewServesTheRunAndGetsTheOverlay) {
  std::vector<ProcessCommand> commands = process_commands(o, scene, &script, "s.state");
  EXPECT_FALSE(has_flag(names_of(commands), "view"));
  EXPECT_FALSE(has_flag(commands[1].args, "--overlay-lcm"));
  o.view_port = 9001;
  commands = process_commands(o, scene, &script, "s.state");
  EXPECT_EQ(names_of(commands), (std::vector<std::string>{"simulator", "renderer", "view", "tracker", "camera"}));
  EXPECT_TRUE(has_flag(commands[1].args, "--overlay-lcm"));
  EXPECT_EQ(commands[2].args[0], "/b/tools/view/arphys-view");
  EXPECT_TRUE(has(commands[2].args, "--port", "9001"));
  EXPECT_TRUE(has(commands[2].args, "--lcm-url", scene.lcm_url));
  EXPECT_FALSE(ends_by_itself("view", o));
  EXPECT_FALSE(has_flag(commands[2].args, "--allow-spawn"));
  o.view_allow_spawn = true;
  EXPECT_EQ(process_commands(o, scene, &script, "s.state")[2].args.back(), "--allow-spawn");
  o.replay_log = "/logs/run.lcmlog";  // a replay: the page's buttons drive it
  EXPECT_EQ(process_commands(o, scene, &script, "s.state")[2].args.back(), "--allow-replay-control");
}

}  // namespace
}  // namespace arphys::launch
