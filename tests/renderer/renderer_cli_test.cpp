// The `renderer` and `arphys-synthetic-camera` executables: the offline contract
// (pixels no virtual object covers keep the background exactly; refusals with exit code 2),
// and synthetic frames that the tracker turns back into the scripted poses.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tests/support/run_command.hpp"

namespace {

const std::string kBin = std::string(ARPHYS_BINARY_DIR);
const std::string kSrc = std::string(ARPHYS_SOURCE_DIR);

using CliRun = arphys::testing::CommandRun;
CliRun run(const std::string& command) { return arphys::testing::run_command(command); }

const std::string kRenderer = kBin + "/renderer/app/renderer";
const std::string kCamera = kSrc + "/configs/cameras/synthetic_640x480.yaml";

TEST(RendererCli, HelpDocumentsEveryOption) {
  const CliRun r = run(kRenderer + " --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* option : {"--camera", "--background", "--out", "--scene", "--mesh", "--pose", "--camera-pose",
                             "--match", "--wait-ms", "--video", "--png-dir", "--overlay-lcm", "--proxies"}) {
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
  }
  EXPECT_EQ(run(kBin + "/tools/synthetic_camera/arphys-synthetic-camera --help").exit_code, 0);
}

TEST(RendererCli, OfflineMeshKeepsUncoveredPixelsExactly) {
  const std::string dir = ::testing::TempDir() + "renderer_cli/";
  std::filesystem::create_directories(dir);
  cv::Mat background(480, 640, CV_8UC3);
  cv::randu(background, cv::Scalar::all(0), cv::Scalar::all(256));
  cv::imwrite(dir + "background.png", background);
  const CliRun r = run(kRenderer + " --camera " + kCamera + " --background " + dir + "background.png --mesh " + kSrc +
                       "/configs/models/stanford-bunny-5k.obj --pose \"0 0 0.4 0 1 0 0\" --out " + dir + "out.png");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const cv::Mat out = cv::imread(dir + "out.png", cv::IMREAD_COLOR);
  ASSERT_EQ(out.size(), background.size());
  cv::Mat difference;
  cv::absdiff(out, background, difference);
  std::vector<cv::Mat> channels;
  cv::split(difference, channels);
  const int covered = cv::countNonZero(cv::max(channels[0], cv::max(channels[1], channels[2])));
  // A 0.155 m bunny at 0.4 m covers a good part of the frame; everything else is untouched
  // (the random background makes an accidental match of a covered pixel unlikely).
  EXPECT_GT(covered, 20000);
  EXPECT_LT(covered, 640 * 480 / 2);
  std::filesystem::remove_all(dir);
}

TEST(RendererCli, RefusesBadInputWithExitCode2) {
  CliRun r = run(kRenderer + " --camera " + kCamera + " --background /nonexistent.png --out /tmp/x.png");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("/nonexistent.png"), std::string::npos) << r.out;
  const std::string small = ::testing::TempDir() + "small.png";
  cv::imwrite(small, cv::Mat(100, 100, CV_8UC3, cv::Scalar(1, 2, 3)));
  r = run(kRenderer + " --camera " + kCamera + " --background " + small + " --out /tmp/x.png");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("100x100"), std::string::npos) << r.out;
  r = run(kRenderer + " --camera " + kCamera + " --background " + small + " --mesh /nonexistent.obj --pose \"0 0 1 1 0 0 0\" --out /tmp/x.png");
  EXPECT_EQ(r.exit_code, 2);
  r = run(kRenderer + " --scene " + kSrc + "/configs/scenes/bunny_box_table.yaml --camera-pose \"0 0 1 2 0 0 0\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("--camera-pose"), std::string::npos) << r.out;
}

// A `simulate` CSV drawn offline at a time (--states, --time): the scene's bodies where the
// simulation had them; a malformed row is refused naming the file, the line and the column.
TEST(RendererCli, OfflineDrawsASimulateCsvAndNamesItsBadRows) {
  const std::string dir = ::testing::TempDir() + "renderer_cli_states/";
  std::filesystem::create_directories(dir);
  const std::string scene = kSrc + "/configs/scenes/bunny_box_table.yaml";
  const CliRun sim = run(kBin + "/simulator/simulate/simulate " + scene + " --duration 0.2 --csv " + dir + "states.csv");
  ASSERT_EQ(sim.exit_code, 0) << sim.out;
  cv::imwrite(dir + "background.png", cv::Mat(480, 640, CV_8UC3, cv::Scalar(40, 80, 120)));
  const std::string offline = kRenderer + " --scene " + scene + " --background " + dir + "background.png --out " + dir +
                              "out.png --states ";
  const auto changed_pixels = [](const cv::Mat& a, const cv::Mat& b) {
    cv::Mat difference;
    cv::absdiff(a, b, difference);
    cv::cvtColor(difference, difference, cv::COLOR_BGR2GRAY);
    return cv::countNonZero(difference);
  };
  // The bunny, thrown at 0.6 m/s, drawn where it is at 0 s and at 0.15 s (real objects
  // only hide what is behind them: the camera's picture shows them).
  const cv::Mat background(480, 640, CV_8UC3, cv::Scalar(40, 80, 120));
  std::vector<cv::Mat> frames;
  for (const char* time : {"0", "0.15"}) {
    const CliRun r = run(offline + dir + "states.csv --time " + time);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    frames.push_back(cv::imread(dir + "out.png", cv::IMREAD_COLOR));
    EXPECT_GT(changed_pixels(frames.back(), background), 1000) << "the bunny at " << time << " s";
  }
  EXPECT_GT(changed_pixels(frames[0], frames[1]), 1000) << "the bunny moved";
  const auto refused = [&](const std::string& rows, const std::string& expected) {
    std::ofstream(dir + "bad.csv") << "t,id,px,py,pz,qw,qx,qy,qz\n" << rows;
    const CliRun bad = run(offline + dir + "bad.csv");
    EXPECT_EQ(bad.exit_code, 2) << bad.out;
    EXPECT_NE(bad.out.find("states file " + dir + "bad.csv " + expected), std::string::npos) << bad.out;
  };
  refused("0,box,0.1,0,0.1,1,0,0,0\n0,bunny#0,abc,0,0.3,1,0,0,0\n", "line 3: px is 'abc', expected a finite number");
  refused("0,box,0.1,0\n", "line 2: 4 fields, expected at least 9");
  refused("0,box,0.1,0,0.1,2,0,0,0\n", "line 2: box: quaternion");
  refused("", "has no rows at or before t = 0");
  std::filesystem::remove_all(dir);
}

// The synthetic camera's frames of the box push, written to a folder, tracked: the box is
// where the script put it (it rests at (0.25, 0, 0.075) for the first second).
TEST(SyntheticCamera, FramesTrackBackToTheScript) {
  const std::string dir = ::testing::TempDir() + "synthetic_frames";
  std::filesystem::remove_all(dir);
  CliRun r = run(kBin + "/tools/synthetic_camera/arphys-synthetic-camera " + kSrc +
                 "/configs/synthetic/box_push.yaml --fast --no-lcm --frames 20 --folder " + dir);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  r = run(kBin + "/tracker/app/tracker --scene " + kSrc + "/configs/scenes/bunny_box_table.yaml --source " + dir +
          " --print --no-lcm");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const std::regex box_line(R"(box TRACKED W\[([-0-9.]+) ([-0-9.]+) ([-0-9.]+)\])");
  int frames = 0;
  for (auto it = std::sregex_iterator(r.out.begin(), r.out.end(), box_line); it != std::sregex_iterator(); ++it, ++frames) {
    EXPECT_NEAR(std::stod((*it)[1]), 0.25, 3e-3);
    EXPECT_NEAR(std::stod((*it)[2]), 0.0, 3e-3);
    EXPECT_NEAR(std::stod((*it)[3]), 0.075, 3e-3);
  }
  EXPECT_EQ(frames, 20) << r.out;
  std::filesystem::remove_all(dir);
}

}  // namespace
