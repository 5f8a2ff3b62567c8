#pragma once
#include <optional>
#include <string>

#include "arphys/process_status_t.hpp"
#include "lcmtypes/msg/bus.hpp"

namespace arphys::msg {

// The part of a 1 Hz process_status_t every process fills the same way: publish time,
// name, implementation, host, pid, uptime, and the bus's received / undecodable /
// rejected counts (a process adds its own refusals, rates and figures).
arphys::process_status_t heartbeat(const std::string& name, const std::string& implementation, double uptime_s,
                                   const Bus& bus);

// Appends a named figure (keeps num_figures in step).
void add_figure(arphys::process_status_t& status, const std::string& name, double value);
// The named figure of a heartbeat, if it has one.
std::optional<double> figure(const arphys::process_status_t& status, const std::string& name);

}  // namespace arphys::msg
