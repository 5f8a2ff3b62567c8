#pragma once
// Runs tools/arphys-launch to its end with these arguments (and --out OUT), and returns the
// latency report it wrote (OUT/latency.json), removing OUT afterwards. A launch that fails
// is a test failure, with the launcher's output.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/run_command.hpp"

namespace arphys::testing {

inline nlohmann::json launch_report(const std::string& args, const std::string& out) {
  std::filesystem::remove_all(out);
  const CommandRun run = run_command(std::string("ARPHYS_BUILD_DIR=") + ARPHYS_BINARY_DIR + " " + ARPHYS_SOURCE_DIR +
                                     "/tools/arphys-launch " + args + " --out " + out);
  EXPECT_EQ(run.exit_code, 0) << run.out;
  nlohmann::json report;
  std::ifstream(out + "/latency.json") >> report;
  std::filesystem::remove_all(out);
  return report;
}

}  // namespace arphys::testing
