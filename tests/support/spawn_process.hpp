#pragma once
// Starting a real process from a test (posix_spawn, PATH lookup), for the integration tests.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <sys/types.h>

#include <string>
#include <vector>

extern char** environ;

namespace arphys::testing {

// Returns the child's pid, or -1 when it could not be started.
inline pid_t spawn_process(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  return pid;
}

// Asks a spawned process to stop (SIGTERM), waits for it and returns its wait status.
inline int stop_process(pid_t pid) {
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

}  // namespace arphys::testing
