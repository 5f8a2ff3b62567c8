// The renderer waiting for each frame's own world state (--renderer-wait-ms): application 2
// through the launcher with the tracked box extrapolated to each frame, once drawn at once
// (the renderer then has only an earlier frame's world state) and once waiting. Waiting,
// the overlay draws the box where the frame shows it, also while it moves.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "lcm/lcm-cpp.hpp"
#include "tests/support/launch_report.hpp"

namespace {

// The launcher's report of 6 s of application 2.
nlohmann::json run_application_two(const std::string& url, const std::string& wait_ms) {
  return arphys::testing::launch_report(std::string(ARPHYS_SOURCE_DIR) +
                                            "/configs/scenes/bunny_box_table.yaml --duration 6 --tracking-policy "
                                            "extrapolate --renderer-wait-ms " + wait_ms + " --lcm-url " + url,
                                        ::testing::TempDir() + "overlay_wait_test");
}

TEST(OverlayWait, TheWaitingRendererDrawsEachFramesOwnWorld) {
  const std::string url = "udpm://239.255.76.67:7995?ttl=0";
  if (!lcm::LCM(url).good()) GTEST_SKIP() << "no multicast route on this host (ip route add 224.0.0.0/4 dev lo)";
  const nlohmann::json at_once = run_application_two(url, "0");
  const nlohmann::json waiting = run_application_two(url, "40");
  for (const nlohmann::json* report : {&at_once, &waiting}) {
    const int captured = (*report)["frames"]["captured"];
    const char* run = report == &at_once ? "drawing at once" : "waiting";
    EXPECT_GE(captured, 150) << run;  // 6 s at 30 FPS
    // A renderer that falls behind keeps the newest frame (latency over completeness), so on a
    // machine busy beyond its cores a few frames go (5 of 181 under two busy loops on 2 cores).
    EXPECT_GE((*report)["frames"]["rendered"].get<int>(), captured - captured / 20) << run << ": waiting must not cost frames";
    ASSERT_GE((*report)["registration"]["count"].get<int>(), captured / 2) << run;
  }
  const int rendered = waiting["frames"]["rendered"];
  const int own = waiting["frames"]["rendered_with_own_world_state"];
  const int own_at_once = at_once["frames"]["rendered_with_own_world_state"];
  // Two frames within one 10 ms simulator step share the later one's state, so not
  // every frame has one of its own.
  EXPECT_GE(own, rendered * 8 / 10) << "of " << rendered;
  EXPECT_LE(own_at_once, at_once["frames"]["rendered"].get<int>() / 10) << "drawing at once should rarely find it";
  const double p95_waiting = waiting["registration"]["p95_px"], p95_at_once = at_once["registration"]["p95_px"];
  const double p50_waiting = waiting["registration"]["p50_px"];
  std::printf("registration p50 / p95: at once %.2f / %.2f px, waiting %.2f / %.2f px; capture -> overlay p50 %.1f -> "
              "%.1f ms; own-state frames %d -> %d\n",
              at_once["registration"]["p50_px"].get<double>(), p95_at_once, p50_waiting, p95_waiting,
              at_once["stages"]["capture_to_overlay"]["p50_ms"].get<double>(),
              waiting["stages"]["capture_to_overlay"]["p50_ms"].get<double>(), own_at_once, own);
  // While the box moves the frame's own state puts it where the frame shows it; an earlier
  // frame's is a frame's motion behind: a third of the error at the median (0.25 against 0.83
  // px). The tail is the frames the renderer drew without their own state (a simulator
  // starved of CPU past the 40 ms wait), allowed up to a fifth above: starved, 28 of 180 were
  // (p95 1.32 against 1.52 px, where 0.5-0.7 is usual), so at the tail waiting is only
  // required to be no worse.
  EXPECT_LT(p50_waiting, 0.5 * at_once["registration"]["p50_px"].get<double>());
  EXPECT_LT(p95_waiting, p95_at_once);
  EXPECT_LT(p50_waiting, 1.0);
}

}  // namespace
