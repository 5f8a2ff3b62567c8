#pragma once
// The working data of a World step, shared by world.cpp (the first pass, the groups) and
// world_group.cpp (a group's parts): not part of the library's interface. The stages' own
// helpers are in step_helpers.hpp.
#include <Eigen/Geometry>
#include <optional>
#include <set>
#include <vector>

#include "simulator/dynamics/disjoint_sets.hpp"
#include "simulator/dynamics/world.hpp"

namespace arphys::dynamics {

// A dynamic body's state moves through a step in its group (see step()); a group's
// participants are its dynamic bodies and every non-dynamic body, in body order.
// What the step's first solve (all bodies at once) gave a group, by participant.
struct World::FirstSolve {
  std::vector<BodyVelocity> u;
  std::vector<Contact> resting, solved;
  SolvedIslands& islands;  // the islands solved at the step's start poses, shared by every group
};

struct World::GroupOutcome {
  std::vector<Contact> contacts;           // of the group's last solve
  std::vector<Eigen::AlignedBox3d> swept;  // box each participant swept over the step
  bool capped = false;
};

// The step's first pass over every body at once: contacts, one solve, the motions it
// gives, their swept boxes and CCD, and the groups those form.
struct World::FirstPass {
  std::vector<Contact> resting, solved;
  SolvedIslands islands;
  std::vector<BodyVelocity> u;             // by body
  std::vector<geometry::Pose> next;        // by body
  std::vector<Eigen::AlignedBox3d> swept;  // by body, over its motion to next
  ImpactCache ccd;
  DisjointSets groups{0};
  std::set<int> eventful;  // roots of the groups whose CCD met something or ended too deep
};

// A group's stepping within a step, by body (dynamic bodies) or by group root.
struct World::GroupStepping {
  struct State {
    geometry::Pose X_WB;
    Eigen::Vector3d v, w;
  };
  std::vector<State> start;                       // each dynamic body at the step's start
  std::vector<Eigen::AlignedBox3d> moved;         // each dynamic body's swept box over the step
  std::vector<char> stepped;                      // by root: stepped on its own
  std::vector<std::vector<Contact>> contacts_of;  // by root: its last solve, when stepped
};

}  // namespace arphys::dynamics
