// Several machines, emulated: three network namespaces joined by a bridge (iproute2),
// multicast routed on each, LCM with ttl=1. Camera + tracker run in the first, the
// simulator in the second, the renderer in the third; the third's launcher sees every
// stage's messages cross and writes the overlay video. Skips, saying why, where
// namespaces cannot be created (no CAP_NET_ADMIN, no iproute2).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

namespace {

const std::string kUrl = "udpm://239.255.76.67:7665?ttl=1";

int sh(const std::string& command) {
  const int status = std::system((command + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct Namespaces {
  bool ok = false;
  std::string why;
  Namespaces() {
    cleanup();
    if (sh("ip netns add arphys_ns_a") != 0) {
      why = "cannot create network namespaces here (needs root / CAP_NET_ADMIN and iproute2)";
      return;
    }
    ok = sh("ip netns add arphys_ns_b") == 0 && sh("ip netns add arphys_ns_c") == 0 &&
         sh("ip link add arphys_br type bridge mcast_snooping 0") == 0 && sh("ip link set arphys_br up") == 0;
    int i = 1;
    for (const char* n : {"a", "b", "c"}) {
      const std::string ns = std::string("arphys_ns_") + n, veth = std::string("arphys_v") + n;
      ok = ok && sh("ip link add " + veth + " type veth peer name eth0 netns " + ns) == 0 &&
           sh("ip link set " + veth + " master arphys_br up") == 0 &&
           sh("ip -n " + ns + " addr add 10.77.0." + std::to_string(i++) + "/24 dev eth0") == 0 &&
           sh("ip -n " + ns + " link set eth0 up") == 0 && sh("ip -n " + ns + " link set lo up") == 0 &&
           sh("ip -n " + ns + " route add 224.0.0.0/4 dev eth0") == 0;
    }
    if (!ok) why = "namespaces created, but the bridge or its links could not be set up";
  }
  ~Namespaces() { cleanup(); }
  static void cleanup() {
    for (const char* n : {"a", "b", "c"}) sh(std::string("ip netns del arphys_ns_") + n);
    sh("ip link del arphys_br");
  }
};

TEST(Namespaces, PipelineAcrossThreeNamespaces) {
  Namespaces net;
  if (!net.ok) GTEST_SKIP() << net.why;
  const std::string launch = std::string("ARPHYS_BUILD_DIR=") + ARPHYS_BINARY_DIR + " " + ARPHYS_SOURCE_DIR +
                             "/tools/arphys-launch " + ARPHYS_SOURCE_DIR + "/configs/scenes/bunny_box_table.yaml " +
                             "--lcm-url '" + kUrl + "' --duration 6 ";
  const std::string out = ::testing::TempDir() + "namespaces_test";
  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out);
  // Renderer and simulator first (they wait for frames), then the camera's machine.
  std::thread renderer([&] { sh("ip netns exec arphys_ns_c env " + launch + "--only renderer --out " + out + "/c"); });
  std::thread simulator([&] { sh("ip netns exec arphys_ns_b env " + launch + "--only simulator --out " + out + "/b"); });
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const int camera = sh("ip netns exec arphys_ns_a env " + launch + "--only camera,tracker --out " + out + "/a");
  renderer.join();
  simulator.join();
  EXPECT_EQ(camera, 0);
  ASSERT_TRUE(std::filesystem::exists(out + "/c/latency.json"));
  nlohmann::json report;
  std::ifstream(out + "/c/latency.json") >> report;
  // Seen from the renderer's namespace: frames from A, poses from A, world states from B.
  EXPECT_GE(report["frames"]["captured"].get<int>(), 100);
  EXPECT_GE(report["frames"]["tracked"].get<int>(), 100);
  EXPECT_GE(report["stages"]["pose_to_world_state"]["count"].get<int>(), 100);
  EXPECT_GE(report["frames"]["rendered"].get<int>(), 100);
  EXPECT_GT(std::filesystem::file_size(out + "/c/overlay.avi"), 100000u);
  std::filesystem::remove_all(out);
}

}  // namespace
