#pragma once
// Runs a shell command to its end, for tests of what an executable prints and returns.
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace arphys::testing {

struct CommandRun {
  int exit_code = -1;  // -1: it could not be started, or did not exit normally
  std::string out;     // standard output and standard error, interleaved
};

inline CommandRun run_command(const std::string& command) {
  CommandRun r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  while (fgets(buffer, sizeof buffer, pipe)) r.out += buffer;
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace arphys::testing
