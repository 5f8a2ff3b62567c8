#pragma once
// What a World carries from one step to the next: each body's state, the clock, sleep, the
// last step's contacts and what they leave the next step.
#include <vector>

#include "simulator/dynamics/contact.hpp"
#include "simulator/dynamics/rigid_body.hpp"
#include "simulator/dynamics/step_contacts.hpp"

namespace arphys::dynamics {

// Deactivation (WorldOptions::sleep_after_s), by body.
struct SleepState {
  std::vector<double> quiet_s;             // how long each body has moved slower than sleep_speed_m_s
  std::vector<std::vector<int>> touching;  // a sleeper's dynamic contact partners when it fell asleep
  // Moved by World::place_body since the last step: each wakes the sleepers its new pose
  // reaches (held as fixed bodies, they would not meet a placed kinematic body at all).
  std::vector<char> placed_to_wake;
};

struct WorldState {
  std::vector<BodyState> bodies;  // indexed like WorldModel::bodies
  double time_s = 0;
  SleepState sleep;
  std::vector<Contact> contacts;  // of the last step's last solves
  ContactHints hints;             // what the last step left this one's contacts
  // Bounces this step holds back for the next (unsorted; hints.pending_bounces at its start).
  std::vector<ContactHints::Bounce> held_back_bounces;
  MeshCrossingMemo mesh;
};

}  // namespace arphys::dynamics
