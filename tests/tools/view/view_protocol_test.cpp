// arphys-view as a process, read by the official Foxglove WebSocket client (npm
// @foxglove/ws-protocol under node): every topic is advertised, subscribed and decoded, and
// what it carries is what the bus carried (bodies and poses, image sizes, transforms,
// statuses, latencies) at the rates sent; junk on the socket and a client without the
// subprotocol are refused and counted while the view goes on serving.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <thread>

#include "arphys/object_poses_t.hpp"
#include "arphys/process_status_t.hpp"
#include "arphys/render_status_t.hpp"
#include "arphys/replay_control_t.hpp"
#include "arphys/sim_command_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/heartbeat.hpp"
#include "lcmtypes/msg/image_message.hpp"
#include "tests/support/spawn_process.hpp"

namespace {

using nlohmann::json;
// A port of its own for each test (ctest runs them side by side).
const std::string kUrl = "udpm://239.255.76.67:7983?ttl=0";
const std::string kLoadUrl = "udpm://239.255.76.67:7981?ttl=0";
const std::string kSpawnUrl = "udpm://239.255.76.67:7980?ttl=0";
const std::string kReplayUrl = "udpm://239.255.76.67:7979?ttl=0";
constexpr int kPort = 18766;

arphys::pose_t pose_of(double x, double y, double z) {
  arphys::pose_t p{};
  p.position_m[0] = x, p.position_m[1] = y, p.position_m[2] = z;
  p.orientation_wxyz[0] = 1;
  return p;
}

arphys::world_state_t world_state(int k) {
  arphys::world_state_t s{};
  s.utime = 1'000'000 + k * 33'333;
  s.seq = k;
  s.scene_name = "bunny_box_table";
  const auto body = [](const std::string& id, const std::string& model, int8_t role, arphys::pose_t X) {
    arphys::body_state_t b{};
    b.body_id = id, b.model = model, b.role = role, b.X_WB = X;
    return b;
  };
  s.bodies = {body("table", "table", arphys::body_state_t::ROLE_REAL, pose_of(0, 0, -0.02)),
              body("box", "box", arphys::body_state_t::ROLE_REAL, pose_of(0.1, 0, 0.075)),
              body("bunny#1", "bunny", arphys::body_state_t::ROLE_VIRTUAL, pose_of(0.2, 0.05, 0.3 - 0.001 * k))};
  s.num_bodies = 3;
  arphys::contact_t c{};
  c.body_a = "table", c.body_b = "bunny#1", c.n_W[2] = 1, c.p_W_m[0] = 0.2;
  s.contacts = {c};
  s.num_contacts = 1;
  return s;
}

// Sends bytes that are not HTTP, then a WebSocket upgrade without the foxglove subprotocol.
void junk_clients() {
  for (const std::string& request :
       {std::string("\x16\x03\x01 not http at all\r\n\r\n"),
        std::string("GET / HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Key: "
                    "dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Protocol: chat\r\n\r\n")}) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(kPort);
    inet_pton(AF_INET, "127.0.0.1", &address.sin_addr);
    if (connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0) {
      (void)!write(fd, request.data(), request.size());
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    close(fd);
  }
}

// Keeps the view's newest heartbeat in `status`.
void keep_view_status(arphys::msg::Bus& bus, std::optional<arphys::process_status_t>& status) {
  bus.subscribe<arphys::process_status_t>(
      "ARPHYS_STATUS", [&status](const arphys::process_status_t& s, const lcm::ReceiveBuffer&, const std::string&) {
        if (s.name == "view") status = s;
      });
}

// Stops a spawned process however the test ends (ctest waits for every child of a test).
struct Stopped {
  pid_t pid;
  ~Stopped() {
    if (pid > 0) arphys::testing::stop_process(pid);
  }
};

TEST(ViewProtocol, TheOfficialClientDecodesWhatTheBusCarried) {
  arphys::msg::Bus bus(kUrl);
  const std::string bin = ARPHYS_BINARY_DIR, src = ARPHYS_SOURCE_DIR;
  const pid_t view =
      arphys::testing::spawn_process({bin + "/tools/view/arphys-view", src + "/configs/scenes/bunny_box_table.yaml",
                                      "--lcm-url", kUrl, "--port", std::to_string(kPort), "--image-rate-hz", "10"});
  ASSERT_GT(view, 0);
  Stopped view_guard{view};
  std::optional<arphys::process_status_t> view_status;
  keep_view_status(bus, view_status);
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  junk_clients();
  const std::string out = ::testing::TempDir() + "view_protocol_" + std::to_string(getpid()) + ".json";
  const pid_t client = arphys::testing::spawn_process(
      {"node", src + "/tools/view/web/record_client.mjs", "ws://127.0.0.1:" + std::to_string(kPort), "3", out});
  ASSERT_GT(client, 0);
  Stopped client_guard{client};
  std::this_thread::sleep_for(std::chrono::milliseconds(800));  // connected and subscribed
  const cv::Mat frame(240, 320, CV_8UC3, cv::Scalar(30, 120, 200));
  const auto start = std::chrono::steady_clock::now();
  int sent = 0;
  for (; std::chrono::steady_clock::now() - start < std::chrono::milliseconds(1800); ++sent) {
    bus.publish("ARPHYS_WORLD_STATE", world_state(sent));
    bus.publish("ARPHYS_CAMERA_IMAGE", arphys::msg::encode_image_message(frame, 1000 + sent, sent, "cam", 80));
    arphys::object_poses_t poses{};
    poses.utime = 1000 + sent, poses.camera_id = "cam", poses.camera_world_valid = true, poses.X_WC = pose_of(0, -1, 1);
    arphys::object_pose_t box{};
    box.object_id = "box", box.world_valid = true, box.X_WO = pose_of(0.1, 0, 0.075);
    poses.objects = {box};
    poses.num_objects = 1;
    bus.publish("ARPHYS_OBJECT_POSES", poses);
    arphys::render_status_t latency{};
    latency.utime = 5'000'000, latency.seq = sent, latency.publish_utime = 5'012'500;
    bus.publish("ARPHYS_RENDER_STATUS", latency);
    bus.handle_pending();
    std::this_thread::sleep_for(std::chrono::milliseconds(33));
  }
  int client_status = 0;
  waitpid(client, &client_status, 0);
  client_guard.pid = -1;
  ASSERT_TRUE(WIFEXITED(client_status) && WEXITSTATUS(client_status) == 0) << "node client failed: " << client_status;
  for (int k = 0; k < 30 && !view_status; ++k) bus.handle_timeout_ms(100);
  EXPECT_EQ(waitpid(view, nullptr, WNOHANG), 0) << "arphys-view died";
  const int view_exit = arphys::testing::stop_process(view);
  view_guard.pid = -1;
  EXPECT_TRUE(WIFEXITED(view_exit) && WEXITSTATUS(view_exit) == 0) << view_exit;

  std::ifstream in(out);
  ASSERT_TRUE(in) << out;
  const json record = json::parse(in);
  EXPECT_EQ(record["serverInfo"]["name"], "arphys-view");
  ASSERT_EQ(record["channels"].size(), 7u);
  EXPECT_EQ(record["channels"][2]["topic"], "/world");
  EXPECT_EQ(record["channels"][2]["schemaName"], "foxglove.SceneUpdate");
  // World: every update decoded, the last one's bunny where the last state put it.
  const json& world = record["topics"]["/world"];
  EXPECT_GE(world["count"].get<int>(), sent * 8 / 10) << "of " << sent;
  const json& last = world["messages"].back();
  // The last update is one of the last states sent (loopback multicast may lose a datagram), to the bit.
  const json& bunny_pose = last["entities"][2]["models"][0]["pose"];
  const int k = static_cast<int>(std::lround((0.3 - bunny_pose["position"]["z"].get<double>()) / 0.001));
  EXPECT_GE(k, sent - 3) << "of " << sent;
  EXPECT_LT(k, sent);
  EXPECT_EQ(bunny_pose["position"]["z"].get<double>(), 0.3 - 0.001 * k);
  EXPECT_EQ(bunny_pose["position"]["x"].get<double>(), 0.2);
  EXPECT_EQ(last["entities"][2]["id"], "bunny#1");
  EXPECT_EQ(last["entities"][0]["cubes"][0]["size"]["x"], 1.2);               // the table, a box
  EXPECT_LT(last["entities"][1]["cubes"][0]["color"]["a"].get<double>(), 1);  // real: translucent
  EXPECT_EQ(last["entities"][3]["id"], "contacts");
  EXPECT_NEAR(last["entities"][3]["arrows"][0]["pose"]["orientation"]["y"].get<double>(), -std::sqrt(0.5),
              1e-9);  // +x to +z
  ASSERT_EQ(record["models"].size(), 1u);
  EXPECT_GT(record["models"].begin().value().get<int>(), 20000) << record["models"].dump();  // the bunny OBJ, over HTTP
  // Images: JPEGs of the frame's size, at the view's rate limit (10 Hz) rather than all 30.
  const json& images = record["topics"]["/camera/image"];
  EXPECT_EQ(images["messages"][0]["data"]["jpeg"]["width"], 320);
  EXPECT_EQ(images["messages"][0]["data"]["jpeg"]["height"], 240);
  EXPECT_GE(images["count"].get<int>(), 10);
  EXPECT_LE(images["count"].get<int>(), 22);
  // Transforms and latency.
  const json& tf = record["topics"]["/tf"]["messages"].back()["transforms"];
  ASSERT_EQ(tf.size(), 2u);
  EXPECT_EQ(tf[0]["child_frame_id"], "cam");
  EXPECT_EQ(tf[1]["child_frame_id"], "box");
  EXPECT_EQ(tf[1]["translation"]["x"], 0.1);
  EXPECT_EQ(record["topics"]["/latency"]["messages"][0]["capture_to_publish_ms"], 12.5);
  const json& objects = record["topics"]["/objects"]["messages"].back()["objects"];
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(objects[0]["id"], "box");
  EXPECT_EQ(objects[0]["status"], "TRACKED");
  // The junk was refused and counted.
  ASSERT_TRUE(view_status);
  EXPECT_GE(view_status->rejected, 1);
  EXPECT_EQ(arphys::msg::figure(*view_status, "clients_total").value_or(0), 1);
}

// A hundred clients that come and go and one that stops reading, while 640x480 frames of
// noise (large JPEGs) flow at 30 Hz: the stalled client's messages are dropped and counted,
// the client that reads throughout gets nearly every world state, the view keeps serving.
TEST(ViewProtocol, AHundredClientsComingAndGoingAndAStalledOneLeaveTheViewServing) {
  arphys::msg::Bus bus(kLoadUrl);
  const std::string bin = ARPHYS_BINARY_DIR, src = ARPHYS_SOURCE_DIR, port = std::to_string(kPort + 1);
  const pid_t view = arphys::testing::spawn_process(
      {bin + "/tools/view/arphys-view", src + "/configs/scenes/bunny_box_table.yaml", "--lcm-url", kLoadUrl, "--port",
       port, "--image-rate-hz", "30", "--max-backlog-mb", "1"});
  ASSERT_GT(view, 0);
  Stopped view_guard{view};
  std::optional<arphys::process_status_t> view_status;
  keep_view_status(bus, view_status);
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  const std::string out = ::testing::TempDir() + "view_load_" + std::to_string(getpid()) + ".json";
  const pid_t load = arphys::testing::spawn_process(
      {"node", src + "/tools/view/web/load_clients.mjs", "ws://127.0.0.1:" + port, "100", "2", "1", "4"});
  const pid_t reader = arphys::testing::spawn_process(
      {"node", src + "/tools/view/web/record_client.mjs", "ws://127.0.0.1:" + port, "4", out});
  ASSERT_GT(load, 0);
  ASSERT_GT(reader, 0);
  Stopped load_guard{load}, reader_guard{reader};
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  cv::Mat noise(480, 640, CV_8UC3);
  int sent = 0;
  for (const auto start = std::chrono::steady_clock::now();
       std::chrono::steady_clock::now() - start < std::chrono::milliseconds(2800); ++sent) {
    cv::randu(noise, 0, 255);
    bus.publish("ARPHYS_WORLD_STATE", world_state(sent));
    bus.publish("ARPHYS_CAMERA_IMAGE", arphys::msg::encode_image_message(noise, 1000 + sent, sent, "cam", 90));
    bus.handle_pending();
    std::this_thread::sleep_for(std::chrono::milliseconds(33));
  }
  for (pid_t* p : {&load_guard.pid, &reader_guard.pid}) {
    int status = 0;
    waitpid(*p, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "node client failed: " << status;
    *p = -1;
  }
  for (int k = 0; k < 30 && !(view_status && arphys::msg::figure(*view_status, "clients_total") >= 102); ++k)
    bus.handle_timeout_ms(100);
  EXPECT_EQ(waitpid(view, nullptr, WNOHANG), 0) << "arphys-view died";
  std::ifstream in(out);
  ASSERT_TRUE(in) << out;
  const json record = json::parse(in);
  EXPECT_GE(record["topics"]["/world"]["count"].get<int>(), sent * 8 / 10) << "of " << sent;
  ASSERT_TRUE(view_status);
  EXPECT_GE(arphys::msg::figure(*view_status, "clients_total").value_or(0), 102);
  EXPECT_GT(arphys::msg::figure(*view_status, "dropped_slow_clients").value_or(0), 0)
      << "the stalled client's backlog was not dropped";
}

// What a command prints (run through the shell).
std::string output_of(const std::string& command) {
  std::string out;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[4096];
    for (std::size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
    pclose(pipe);
  }
  return out;
}

// With --allow-spawn a client may publish spawns of the scene's dynamic models within its
// limits, and nothing else: one good spawn and a later one reach the simulator's channel as
// commands; another topic (and the message sent on it), an unknown model, a spawn 1 km away and
// one over the rate are refused with a status each. Without the flag, the view is read-only.
TEST(ViewProtocol, SpawnsWithinTheScenesLimitsAndOnlyWithAllowSpawn) {
  arphys::msg::Bus bus(kSpawnUrl);
  const std::string bin = ARPHYS_BINARY_DIR, src = ARPHYS_SOURCE_DIR;
  std::vector<arphys::sim_command_t> commands;
  bus.subscribe<arphys::sim_command_t>(
      "ARPHYS_SIM_COMMAND",
      [&](const arphys::sim_command_t& c, const lcm::ReceiveBuffer&, const std::string&) { commands.push_back(c); });
  for (const bool allowed : {true, false}) {
    const std::string port = std::to_string(kPort + (allowed ? 2 : 3));
    std::vector<std::string> args{bin + "/tools/view/arphys-view",
                                  src + "/configs/scenes/bunny_box_table.yaml",
                                  "--lcm-url",
                                  kSpawnUrl,
                                  "--port",
                                  port};
    if (allowed) args.push_back("--allow-spawn");
    const pid_t view = arphys::testing::spawn_process(args);
    ASSERT_GT(view, 0);
    Stopped view_guard{view};
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    const std::string spawn = "'/spawn={\"model\":\"bunny\",\"position\":{\"x\":";
    std::string printed;
    std::thread client([&] {
      printed = output_of("node " + src + "/tools/view/web/publish_client.mjs ws://127.0.0.1:" + port +
                          " '/other={\"anything\":1}' " + spawn +
                          "0.1,\"y\":0,\"z\":0.3},\"velocity\":{\"x\":0,\"y\":0,\"z\":-1}}' "
                          "'/spawn={\"model\":\"no-such-model\",\"position\":{\"x\":0,\"y\":0,\"z\":0.3}}' " +
                          spawn + "1000,\"y\":0,\"z\":0.3}}' " + spawn + "0.2,\"y\":0,\"z\":0.3}}' wait=150 " + spawn +
                          "0.3,\"y\":0,\"z\":0.3}}'");
    });
    for (int k = 0; k < 20; ++k) bus.handle_timeout_ms(100);
    client.join();
    const json reply = json::parse(printed.substr(printed.find('{')));
    const std::string statuses = reply["statuses"].dump();
    if (allowed) {
      EXPECT_EQ(reply["capabilities"][0], "clientPublish");
      EXPECT_EQ(reply["metadata"]["spawn_models"], "bunny");
      ASSERT_EQ(commands.size(), 2u) << statuses;
      EXPECT_EQ(commands[0].command, arphys::sim_command_t::COMMAND_SPAWN);
      EXPECT_EQ(commands[0].model, "bunny");
      EXPECT_EQ(commands[0].X_WB.position_m[0], 0.1);
      EXPECT_EQ(commands[0].v_WB_m_s[2], -1.0);
      EXPECT_EQ(commands[1].X_WB.position_m[0], 0.3);
      EXPECT_GT(commands[1].seq, commands[0].seq);
      EXPECT_EQ(reply["statuses"].size(), 5u) << statuses;
      EXPECT_NE(statuses.find("'/other' is not allowed"), std::string::npos) << statuses;
      EXPECT_NE(statuses.find("not advertised"), std::string::npos) << statuses;  // the message sent on it
      EXPECT_NE(statuses.find("not a dynamic virtual model"), std::string::npos) << statuses;
      EXPECT_NE(statuses.find("beyond 10 m"), std::string::npos) << statuses;
      EXPECT_NE(statuses.find("more than 10 spawns a second"), std::string::npos) << statuses;
    } else {
      EXPECT_TRUE(reply["capabilities"].empty());
      EXPECT_EQ(commands.size(), 2u) << "a read-only view published";
      EXPECT_NE(statuses.find("'/spawn' is not allowed (read-only)"), std::string::npos) << statuses;
    }
  }
}

// With --allow-replay-control a client drives arphys-replay: its commands reach the control
// channel as replay_control_t, an unknown one is refused with a status.
TEST(ViewProtocol, ReplayControlsReachTheReplayOnlyWhenAllowed) {
  arphys::msg::Bus bus(kReplayUrl);
  const std::string bin = ARPHYS_BINARY_DIR, src = ARPHYS_SOURCE_DIR, port = std::to_string(kPort + 4);
  std::vector<arphys::replay_control_t> controls;
  bus.subscribe<arphys::replay_control_t>("CONTROL", [&](const arphys::replay_control_t& c, const lcm::ReceiveBuffer&,
                                                         const std::string&) { controls.push_back(c); });
  const pid_t view = arphys::testing::spawn_process(
      {bin + "/tools/view/arphys-view", src + "/configs/scenes/bunny_box_table.yaml", "--lcm-url", kReplayUrl, "--port",
       port, "--allow-replay-control", "--replay-control-channel", "CONTROL"});
  ASSERT_GT(view, 0);
  Stopped view_guard{view};
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  std::string printed;
  std::thread client([&] {
    printed = output_of("node " + src + "/tools/view/web/publish_client.mjs ws://127.0.0.1:" + port +
                        " '/replay_control={\"command\":\"seek\",\"value\":2.5}'"
                        " '/replay_control={\"command\":\"jump\"}' '/spawn={\"model\":\"bunny\"}'"
                        " '/replay_control={\"command\":\"pause\"}'");
  });
  for (int k = 0; k < 15; ++k) bus.handle_timeout_ms(100);
  client.join();
  const json reply = json::parse(printed.substr(printed.find('{')));
  EXPECT_EQ(reply["metadata"]["replay_control"], "CONTROL");
  ASSERT_EQ(controls.size(), 2u) << printed;
  EXPECT_EQ(controls[0].command, "seek");
  EXPECT_EQ(controls[0].value, 2.5);
  EXPECT_EQ(controls[1].command, "pause");
  EXPECT_EQ(controls[1].seq, controls[0].seq + 1);
  const std::string statuses = reply["statuses"].dump();
  EXPECT_NE(statuses.find("unknown command 'jump'"), std::string::npos) << statuses;
  EXPECT_NE(statuses.find("'/spawn' is not allowed"), std::string::npos) << statuses;  // no --allow-spawn
}

}  // namespace
