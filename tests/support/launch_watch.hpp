#pragma once
// The pipeline tests' side of a run of tools/arphys-launch: the launcher in a thread with
// its output in OUT.log, and a bus that keeps each process's last heartbeat and watches
// the world states (WorldWatch).
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <thread>

#include "arphys/process_status_t.hpp"
#include "arphys/world_state_t.hpp"
#include "lcmtypes/msg/bus.hpp"
#include "tests/support/world_watch.hpp"

namespace arphys::testing {

// False when this host has no multicast route (the test should skip).
inline bool multicast_works(const std::string& url) { return lcm::LCM(url).good(); }

struct LaunchWatch {
  explicit LaunchWatch(const std::string& lcm_url) : url(lcm_url), bus(lcm_url) {
    bus.subscribe<arphys::process_status_t>("ARPHYS_STATUS", [this](const arphys::process_status_t& m,
                                                                    const lcm::ReceiveBuffer&,
                                                                    const std::string&) { last[m.name] = m; });
    bus.subscribe<arphys::world_state_t>("ARPHYS_WORLD_STATE", [this](const arphys::world_state_t& m,
                                                                      const lcm::ReceiveBuffer&,
                                                                      const std::string&) { world.on_world_state(m); });
  }
  ~LaunchWatch() {
    if (launcher.joinable()) launcher.join();
  }

  // Starts application 2 through the launcher for duration_s with extra arguments;
  // out: its output folder (emptied first). wait() gives the launcher's exit status.
  void start(double duration_s, const std::string& extra_args, const std::string& out_dir) {
    out = out_dir;
    std::filesystem::remove_all(out);
    const std::string command = std::string("ARPHYS_BUILD_DIR=") + ARPHYS_BINARY_DIR + " " + ARPHYS_SOURCE_DIR +
                                "/tools/arphys-launch " + ARPHYS_SOURCE_DIR + "/configs/scenes/bunny_box_table.yaml --duration " +
                                std::to_string(duration_s) + " --lcm-url " + url + " --out " + out + " " + extra_args +
                                " > " + out + ".log 2>&1";
    launcher = std::thread([this, command] { status = std::system(command.c_str()); });
  }
  void pump_for(double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) bus.handle_timeout_ms(10);
  }
  // True when the launcher exited 0 (no process died).
  bool wait() {
    launcher.join();
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
  }

  std::string url, out;
  msg::Bus bus;
  std::map<std::string, arphys::process_status_t> last;
  WorldWatch world;
  std::thread launcher;
  int status = -1;
};

}  // namespace arphys::testing
