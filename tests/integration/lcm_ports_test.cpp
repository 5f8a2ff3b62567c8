// The integration tests run side by side (ctest -j), each on real LCM multicast: two tests
// on one port would hear each other's messages. Every test's URL is written out once, in
// one place; the same port written twice is a test that will mix with another.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <regex>
#include <string>

#include "tests/support/read_file.hpp"

namespace {

TEST(LcmPorts, EveryTestUrlHasAPortOfItsOwn) {
  const std::regex url(R"(udpm://239\.255\.76\.67:(\d+))");
  std::map<std::string, std::string> first_seen;  // port -> file:line
  int urls = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(std::string(ARPHYS_SOURCE_DIR) + "/tests")) {
    const std::string path = entry.path().string();
    if (!entry.is_regular_file() || (entry.path().extension() != ".cpp" && entry.path().extension() != ".hpp")) continue;
    const std::string text = arphys::testing::read_file(path);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), url); it != std::sregex_iterator(); ++it) {
      ++urls;
      const std::string port = (*it)[1];
      const std::string where = entry.path().filename().string() + ":" +
                                std::to_string(1 + std::count(text.begin(), text.begin() + it->position(), '\n'));
      const auto [seen, fresh] = first_seen.emplace(port, where);
      EXPECT_TRUE(fresh) << "port " << port << " at " << where << " is also at " << seen->second;
    }
  }
  EXPECT_GE(urls, 15);  // the integration tests were found at all
}

}  // namespace
