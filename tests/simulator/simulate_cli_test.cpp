// The simulate command as a process: its CSV contract and its errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "tests/support/csv_table.hpp"

namespace {

std::string run(const std::string& args, int* exit_code) {
  // One file per test process: ctest runs the cases of this file in parallel.
  const std::string err = ::testing::TempDir() + "simulate_cli_err_" + std::to_string(getpid()) + ".txt";
  const std::string command = std::string(ARPHYS_BINARY_DIR) + "/simulator/simulate/simulate " + args + " 2> " + err;
  *exit_code = WEXITSTATUS(std::system(command.c_str()));
  std::stringstream text;
  text << std::ifstream(err).rdbuf();
  std::remove(err.c_str());  // per-process name: it would otherwise pile up in TempDir
  return text.str();
}

TEST(SimulateCli, InclineCsvHasTheContractAndTheExactAcceleration) {
  const std::string csv = ::testing::TempDir() + "incline.csv";
  int code = 0;
  const std::string summary = run(std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/incline.yaml --duration 0.5 --csv " + csv, &code);
  ASSERT_EQ(code, 0) << summary;
  EXPECT_NE(summary.find("500 steps"), std::string::npos) << summary;
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "t,id,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
  const auto rows = arphys::testing::read_csv(csv);
  EXPECT_EQ(rows.size(), 2u * 501);  // two bodies, t = 0 and 500 steps
  const auto box = arphys::testing::rows_where(rows, "id", "box");
  ASSERT_FALSE(box.empty());
  using arphys::testing::number;
  EXPECT_DOUBLE_EQ(number(box.back(), "t"), 0.5);
  // Down the slope at g sin 30 for 0.5 s: 2.4525 m/s along (-cos 30, 0, -sin 30).
  EXPECT_NEAR(-number(box.back(), "vx") * std::cos(M_PI / 6) - number(box.back(), "vz") * std::sin(M_PI / 6),
              9.81 * 0.5 * 0.5, 1e-9);
}

std::string file_text(const std::string& path) {
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  return text.str();
}

// --step-times: one row per step with its time, rounds and contacts (a ball dropped 1 m
// onto the ground has its first contact as it lands).
TEST(SimulateCli, StepTimesHaveARowPerStepAndTheLandingsContact) {
  const std::string csv = ::testing::TempDir() + "bounce_states.csv";
  const std::string times = ::testing::TempDir() + "bounce_step_times.csv";
  int code = 0;
  const std::string summary = run(std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bounce.yaml --duration 0.5 --csv " +
                                      csv + " --step-times " + times,
                                  &code);
  ASSERT_EQ(code, 0) << summary;
  std::ifstream in(times);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "t_s,step_ms,resolves,lifts,cuts,contacts,deepest_overlap_m");
  const auto rows = arphys::testing::read_csv(times);
  ASSERT_FALSE(rows.empty());
  using arphys::testing::number;
  const double dt = number(rows.front(), "t_s");
  EXPECT_EQ(static_cast<double>(rows.size()), std::round(0.5 / dt));
  // In the air the ball has no contact; it meets the ground once, after 0.45 s.
  double first_contact_s = -1;
  for (const auto& row : rows) {
    EXPECT_GT(number(row, "step_ms"), 0.0);
    if (first_contact_s < 0 && number(row, "contacts") > 0) first_contact_s = number(row, "t_s");
  }
  EXPECT_NEAR(first_contact_s, std::sqrt(2 * 1.0 / 9.81), 0.01);
  std::remove(csv.c_str());
  std::remove(times.c_str());
  EXPECT_NE(run(std::string(ARPHYS_SOURCE_DIR) +
                    "/configs/scenes/bounce.yaml --duration 0.1 --csv - --step-times /nonexistent/dir/t.csv",
                &code)
                .find("cannot write /nonexistent/dir/t.csv"),
            std::string::npos);
  EXPECT_EQ(code, 2);
}

// The bunnies land and pile up within the second; the CSV must not depend on --threads.
TEST(SimulateCli, TheCsvIsTheSameForOneTwoAndFourThreads) {
  std::string first;
  for (int threads : {1, 2, 4}) {
    const std::string csv = ::testing::TempDir() + "bunnies20_threads" + std::to_string(threads) + ".csv";
    int code = 0;
    const std::string summary = run(std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bunnies20.yaml --duration 0.6 --csv " +
                                        csv + " --threads " + std::to_string(threads),
                                    &code);
    ASSERT_EQ(code, 0) << summary;
    EXPECT_NE(summary.find(std::to_string(threads) + (threads == 1 ? " thread;" : " threads;")), std::string::npos) << summary;
    const std::string text = file_text(csv);
    std::remove(csv.c_str());
    ASSERT_GT(text.size(), 10000u);
    if (threads == 1) {
      first = text;
    } else {
      EXPECT_TRUE(text == first) << threads << " threads wrote another CSV than 1 thread";
    }
  }
  int code = 0;
  const std::string error = run(std::string(ARPHYS_SOURCE_DIR) + "/configs/scenes/bunnies20.yaml --duration 0.1 --csv - --threads 0", &code);
  EXPECT_NE(code, 0);
  EXPECT_NE(error.find("--threads"), std::string::npos) << error;
}

TEST(SimulateCli, BadSceneNamesTheFileAndFails) {
  const std::string bad = ::testing::TempDir() + "bad_scene.yaml";
  std::ofstream(bad) << "name: bad\nobjects:\n  - id: ball\n    role: virtual\n    motion: dynamic\n"
                        "    collision: {shape: sphere, radius_m: -1}\n";
  int code = 0;
  const std::string error = run(bad + " --duration 1 --csv -", &code);
  EXPECT_EQ(code, 2);
  EXPECT_NE(error.find(bad), std::string::npos) << error;
  EXPECT_NE(error.find("radius_m"), std::string::npos) << error;
  run("/nonexistent.yaml --duration 1 --csv -", &code);
  EXPECT_NE(code, 0);
}

}  // namespace
