// Swapping the tracker while the pipeline runs: the synthetic camera plays the box push;
// tracker A (apriltag) is switched to ArUco by a control message, then replaced by tracker
// B started on the same channels before A stops. Every frame keeps a tracked box pose
// (gap <= 2 frames) and the pose stays within the trackers' own error of the truth.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <algorithm>
#include <map>
#include <thread>

#include <Eigen/Core>

#include "arphys/ground_truth_t.hpp"
#include "arphys/object_poses_t.hpp"
#include "arphys/tracker_control_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "lcmtypes/msg/clock.hpp"
#include "tests/support/spawn_process.hpp"

namespace {

const std::string kUrl = "udpm://239.255.76.67:7999?ttl=0";
const std::string kBin = ARPHYS_BINARY_DIR;
const std::string kSrc = ARPHYS_SOURCE_DIR;

pid_t start_tracker(const std::string& name, const std::string& impl) {
  return arphys::testing::spawn_process({kBin + "/tracker/app/tracker", "--scene", kSrc + "/configs/scenes/bunny_box_table.yaml",
                                         "--lcm-url", kUrl, "--impl", impl, "--name", name, "--duration", "30"});
}

TEST(TrackerSwap, LiveSwitchAndProcessHandoverKeepTheBoxTracked) {
  {
    lcm::LCM probe(kUrl);
    if (!probe.good()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  }
  arphys::msg::Bus bus(kUrl);
  struct Seen {
    bool tracked = false;
    std::string implementation;
    Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  };
  std::map<int64_t, Seen> by_seq;             // frame seq -> a tracked box pose of it
  std::map<std::string, std::map<int64_t, Eigen::Vector3d>> by_implementation;  // implementation -> seq -> pose
  std::map<int64_t, Eigen::Vector3d> truth;   // frame seq -> true box position
  bus.subscribe<arphys::object_poses_t>("ARPHYS_OBJECT_POSES", [&](const arphys::object_poses_t& m,
                                                                   const lcm::ReceiveBuffer&, const std::string&) {
    for (const auto& o : m.objects) {
      if (o.object_id != "box" || o.status != arphys::object_pose_t::STATUS_TRACKED || !o.world_valid) continue;
      const Eigen::Vector3d p(o.X_WO.position_m[0], o.X_WO.position_m[1], o.X_WO.position_m[2]);
      by_seq[m.seq] = {true, m.tracker_implementation, p};
      by_implementation[m.tracker_implementation.substr(0, m.tracker_implementation.find(' '))][m.seq] = p;
    }
  });
  bus.subscribe<arphys::ground_truth_t>("ARPHYS_GROUND_TRUTH", [&](const arphys::ground_truth_t& m,
                                                                   const lcm::ReceiveBuffer&, const std::string&) {
    for (int i = 0; i < m.num_objects; ++i) {
      if (m.object_ids[i] == "box") truth[m.seq] = Eigen::Vector3d(m.X_WO[i].position_m[0], m.X_WO[i].position_m[1], m.X_WO[i].position_m[2]);
    }
  });
  auto pump = [&](double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) bus.handle_timeout_ms(10);
  };

  pid_t a = start_tracker("tracker-a", "apriltag");
  pump(1.0);
  const pid_t camera = arphys::testing::spawn_process({kBin + "/tools/synthetic_camera/arphys-synthetic-camera",
                                                      kSrc + "/configs/synthetic/box_push.yaml", "--lcm-url", kUrl,
                                                      "--duration", "6"});
  pump(2.0);
  arphys::tracker_control_t control{};
  control.utime = arphys::msg::now_utime();
  control.target = "tracker-a";
  control.implementation = "aruco";
  bus.publish("ARPHYS_TRACKER_CONTROL", control);
  pump(1.5);
  const pid_t b = start_tracker("tracker-b", "apriltag");  // hot standby on the same channels
  pump(1.0);
  arphys::testing::stop_process(a);
  pump(2.5);
  arphys::testing::stop_process(b);
  int status = 0;
  waitpid(camera, &status, 0);

  ASSERT_GE(truth.size(), 150u);
  int longest_gap = 0, gap = 0, aruco = 0, apriltag_after = 0;
  bool seen_aruco = false;
  std::vector<int64_t> transitions;                // first frame of each new implementation
  std::string previous;
  for (const auto& [seq, p_true] : truth) {
    if (seq < 15) continue;  // the first frames: trackers waiting for the table
    const auto it = by_seq.find(seq);
    if (it == by_seq.end()) {
      longest_gap = std::max(longest_gap, ++gap);
      continue;
    }
    gap = 0;
    const std::string implementation = it->second.implementation.substr(0, it->second.implementation.find(' '));
    if (!previous.empty() && implementation != previous) transitions.push_back(seq);
    previous = implementation;
    if (it->second.implementation.rfind("aruco", 0) == 0) {
      ++aruco;
      seen_aruco = true;
    } else if (seen_aruco) {
      ++apriltag_after;
    }
  }
  EXPECT_GT(aruco, 20);           // the switch happened
  EXPECT_GT(apriltag_after, 20);  // and tracker B took over
  EXPECT_LE(longest_gap, 2);
  // No jump across a transition: the step from the old implementation's last pose to the
  // new one's first, less the box's true motion between those frames, is within four
  // times the two trackers' median errors (apriltag ~1 mm, ArUco ~2.5 mm here) + 1 mm.
  ASSERT_GE(transitions.size(), 2u);
  const auto median_error = [&](const std::string& implementation) {
    std::vector<double> e;
    for (const auto& [seq, p] : by_implementation[implementation]) {
      if (truth.count(seq)) e.push_back((p - truth[seq]).norm());
    }
    std::sort(e.begin(), e.end());
    return e.empty() ? 1.0 : e[e.size() / 2];
  };
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"apriltag", "aruco"}, {"aruco", "apriltag"}}) {
    const auto& old_poses = by_implementation[from];
    const auto& new_poses = by_implementation[to];
    // The new implementation's first frame after the old one was in use.
    auto first_new = new_poses.end();
    for (auto it = new_poses.begin(); it != new_poses.end(); ++it) {
      if (old_poses.begin() != old_poses.end() && it->first > old_poses.begin()->first) {
        first_new = it;
        break;
      }
    }
    ASSERT_NE(first_new, new_poses.end()) << from << " -> " << to;
    auto last_old = old_poses.lower_bound(first_new->first);
    ASSERT_NE(last_old, old_poses.begin());
    --last_old;
    ASSERT_TRUE(truth.count(first_new->first) && truth.count(last_old->first));
    const Eigen::Vector3d jump =
        (first_new->second - last_old->second) - (truth[first_new->first] - truth[last_old->first]);
    EXPECT_LT(jump.norm(), 4 * (median_error(from) + median_error(to)) + 1e-3)
        << from << " frame " << last_old->first << " -> " << to << " frame " << first_new->first;
  }
}

}  // namespace
