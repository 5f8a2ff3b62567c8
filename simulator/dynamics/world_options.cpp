#include "simulator/dynamics/world_options.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace arphys::dynamics {

// The options' preconditions, each named with its value when it fails: a NaN tolerance
// compares false with everything, and would quietly turn checks off (a NaN overlap
// tolerance lets every pair sink), a zero event cap would end every step at its first
// impact.
void check_world_options(const WorldOptions& o) {
  const auto fail = [](const std::string& name, double value, const std::string& expected) {
    std::ostringstream message;
    message << "World: option " << name << " is " << value << ", expected " << expected;
    throw std::invalid_argument(message.str());
  };
  const auto positive = [&](const char* name, double value) {
    if (!(value > 0) || !std::isfinite(value)) fail(name, value, "a positive finite number");
  };
  const auto non_negative = [&](const char* name, double value) {
    if (!(value >= 0) || !std::isfinite(value)) fail(name, value, "a finite number >= 0");
  };
  const auto at_least = [&](const char* name, long value, long least) {
    if (value < least) fail(name, static_cast<double>(value), "an integer >= " + std::to_string(least));
  };
  if (!o.gravity_m_s2.allFinite()) fail("gravity_m_s2 (its norm)", o.gravity_m_s2.norm(), "a finite vector");
  positive("contact_tolerance_m", o.contact_tolerance_m);
  non_negative("resting_unswept_motion_m", o.resting_unswept_motion_m);
  positive("overlap_tolerance_m", o.overlap_tolerance_m);
  non_negative("contact_gap_m", o.contact_gap_m);
  if (!(o.contact_gap_m < o.contact_tolerance_m))
    fail("contact_gap_m", o.contact_gap_m,
         "less than contact_tolerance_m (" + std::to_string(o.contact_tolerance_m) + " m)");
  positive("max_depenetration_speed_m_s", o.max_depenetration_speed_m_s);
  non_negative("restitution_threshold_m_s", o.restitution_threshold_m_s);
  at_least("max_events_per_step", o.max_events_per_step, 1);
  non_negative("launch_guard_slack_m_s", o.launch_guard_slack_m_s);
  if (!(o.max_body_speed_m_s > 0))
    fail("max_body_speed_m_s", o.max_body_speed_m_s, "a positive number (may be infinite)");
  at_least("max_contacts_per_pair", o.max_contacts_per_pair, 1);
  at_least("threads", o.threads, 1);
  if (o.threads > 256) fail("threads", o.threads, "at most 256");
  non_negative("sleep_after_s", o.sleep_after_s);
  non_negative("sleep_speed_m_s", o.sleep_speed_m_s);
  at_least("solver.iterations", o.solver.iterations, 1);
  at_least("solver.provisional_friction_sweeps", o.solver.provisional_friction_sweeps, 1);
  non_negative("solver.sweep_tolerance_m_s", o.solver.sweep_tolerance_m_s);
  at_least("solver.max_exact_rows", o.solver.max_exact_rows, 0);
  positive("ccd.time_tolerance", o.ccd.time_tolerance);
  positive("ccd.min_culling_interval", o.ccd.min_culling_interval);
  positive("ccd.time_split_ratio", o.ccd.time_split_ratio);
  at_least("ccd.max_triangle_pairs", o.ccd.max_triangle_pairs, 0);
  at_least("ccd.max_search_nodes", o.ccd.max_search_nodes, 0);
}

}  // namespace arphys::dynamics
