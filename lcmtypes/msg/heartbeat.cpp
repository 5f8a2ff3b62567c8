#include "lcmtypes/msg/heartbeat.hpp"

#include <unistd.h>

#include <cstdio>

#include "lcmtypes/msg/clock.hpp"

namespace arphys::msg {

arphys::process_status_t heartbeat(const std::string& name, const std::string& implementation, double uptime_s,
                                   const Bus& bus) {
  arphys::process_status_t status{};
  status.utime = now_utime();
  status.name = name;
  status.implementation = implementation;
  char host[256] = "unknown";
  gethostname(host, sizeof host - 1);
  status.host = host;
  status.pid = getpid();
  status.uptime_s = uptime_s;
  status.received = bus.counters().received;
  status.decode_errors = bus.counters().decode_errors;
  status.rejected = bus.counters().rejected;
  // Resident memory, so a leak shows in any run's heartbeats (docs/ROBUSTNESS.md).
  long pages_total = 0, pages_resident = 0;
  if (FILE* statm = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(statm, "%ld %ld", &pages_total, &pages_resident) == 2) {
      add_figure(status, "rss_mb", static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1048576.0);
    }
    std::fclose(statm);
  }
  if (bus.counters().injected_losses) add_figure(status, "injected_losses", static_cast<double>(bus.counters().injected_losses));
  return status;
}

void add_figure(arphys::process_status_t& status, const std::string& name, double value) {
  status.figure_names.push_back(name);
  status.figure_values.push_back(value);
  status.num_figures = static_cast<int32_t>(status.figure_names.size());
}

std::optional<double> figure(const arphys::process_status_t& status, const std::string& name) {
  for (int i = 0; i < status.num_figures; ++i)
    if (status.figure_names[i] == name) return status.figure_values[i];
  return std::nullopt;
}

}  // namespace arphys::msg
