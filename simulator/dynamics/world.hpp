#pragma once
// The simulated world, as a model that is fixed once a body is added (world_model.hpp) and a
// state that stepping changes (world_state.hpp), and the time stepping of docs/method.md
// section 2 driven by the CCD of section 1 (docs/dynamics.md, "The step"). A step finds the
// contacts (step_contacts.hpp), solves for the velocities by Gauss's principle (step_solve.hpp) and
// sweeps the motions that gives (step_sweep.hpp), all bodies at once; bodies that may meet
// within the step form groups, and a group whose motion meets something, or leaves a touching
// pair too deep, is re-solved with those meetings as constraints, lifted (step_cut.hpp) or cut
// at the time of impact, part by part (world_group.cpp). Kinematic bodies follow their
// trajectories and push dynamic ones through the same contacts. Surfaces only meet at a CCD
// time of impact, where they touch: nothing passes through anything.
#include <string>
#include <vector>

#include "simulator/dynamics/contact.hpp"
#include "simulator/dynamics/contact_solver.hpp"
#include "simulator/dynamics/rigid_body.hpp"
#include "simulator/dynamics/step_commit.hpp"
#include "simulator/dynamics/step_contacts.hpp"
#include "simulator/dynamics/step_cut.hpp"
#include "simulator/dynamics/step_rounds.hpp"
#include "simulator/dynamics/step_solve.hpp"
#include "simulator/dynamics/step_sweep.hpp"
#include "simulator/dynamics/worker_pool.hpp"
#include "simulator/dynamics/world_model.hpp"
#include "simulator/dynamics/world_options.hpp"
#include "simulator/dynamics/world_state.hpp"

namespace arphys::dynamics {

class World {
 public:
  // Throws std::invalid_argument as check_world_options does.
  explicit World(WorldOptions options = {});

  // Adds a body; a dynamic one needs a positive mass and an invertible inertia, and
  // every body a finite pose (std::invalid_argument naming the body otherwise).
  int add_body(RigidBody body);
  StepReport step(double dt_s);

  double time_s() const { return state_.time_s; }
  int body_count() const { return static_cast<int>(model_.bodies.size()); }
  // What the world is made of: options and each body's shape, mass, material and motion,
  // fixed once the body is added.
  const WorldModel& model() const { return model_; }
  // Everything the next step starts from: each body's pose, velocity, trajectory and sleep,
  // the clock, the last contacts and their hints. It changes by stepping and by the setters
  // and place_body below, each of which throws std::invalid_argument naming the body for a
  // value it cannot take.
  const WorldState& state() const { return state_; }
  const BodyModel& body_model(int index) const { return model_.bodies.at(index); }
  const BodyState& body_state(int index) const { return state_.bodies.at(index); }
  bool asleep(int index) const { return state_.bodies.at(index).asleep; }
  // A body's model and state together, as add_body takes it, and all of them: copies, for
  // reports and checks (the step reads model() and state()).
  RigidBody body_copy(int index) const { return {model_.bodies.at(index), state_.bodies.at(index)}; }
  std::vector<RigidBody> body_copies() const;
  // A dynamic body's velocity (of its centre of mass; world frame), finite. Wakes it.
  void set_velocity(int index, const Eigen::Vector3d& v_WBcm_m_s, const Eigen::Vector3d& w_WB_rad_s);
  // The same from the velocity of the body frame's origin, as scene files and world states give it.
  void set_origin_velocity(int index, const Eigen::Vector3d& v_WBo_m_s, const Eigen::Vector3d& w_WB_rad_s);
  // Where a kinematic body is driven (tracked poses; KinematicTrajectory::add checks them).
  void set_trajectory(int index, KinematicTrajectory trajectory);
  // Moves a body to a pose (not along a motion: nothing is swept), as add_body places
  // one: its next step tests its pairs for crossing deeper than the contact tolerance
  // (see MeshCrossingMemo::placed_since_step). std::invalid_argument names the body for a non-finite pose.
  void place_body(int index, const geometry::Pose& X_WB);
  int find(const std::string& id) const;  // -1 when absent
  // Removes a body (indices after it shift down by one).
  void remove_body(int index);
  const std::vector<Contact>& contacts() const { return state_.contacts; }
  const WorldOptions& options() const { return model_.options; }

 private:
  // The step's working data (world_internal.hpp): a group's share of the first solve, its
  // outcome, the first pass over all bodies, the groups' stepping.
  struct FirstSolve;
  struct GroupOutcome;
  struct FirstPass;
  struct GroupStepping;
  FirstPass first_pass(double dt_s, const std::vector<int>& everyone, StepReport& report);
  // Clears the memos of the last step and takes up the bounces it held back.
  void begin_step_memos();
  // Steps the pending groups (roots, sorted) that meet something on their own and moves the
  // others along the first pass's motion; a group stepped before starts again.
  void step_pending_groups(double dt_s, FirstPass& pass, const std::vector<int>& pending,
                           const std::vector<int>& dynamic, const std::vector<int>& fixed, GroupStepping& g,
                           StepReport& report);
  // Joins each stepped group with the groups its motion reached into; returns their roots
  // (to step again from the step's start), none when nothing reached.
  std::vector<int> reaching_groups(FirstPass& pass, const std::vector<int>& dynamic, GroupStepping& g);
  // The step's contacts (each group's last solve), and the hints the next step starts from.
  void keep_step_contacts(FirstPass& pass, const std::vector<int>& dynamic, const GroupStepping& g, double dt_s,
                          StepReport& report);
  // Steps one group through dt_s: CCD, re-solves with the impacts, cuts at times of
  // impact (at most max_events_per_step). first_ccd: the step's first sweep of all pairs.
  GroupOutcome advance_group(double dt_s, const std::vector<int>& participants, const FirstSolve& first,
                             ImpactCache& first_ccd, StepReport& report);
  // What the sweep stage reads of this world.
  SweepWorld sweep_world() { return {model_, state_.bodies, state_.mesh, pool_}; }
  // What a part's rounds read and write of this world.
  RoundsWorld rounds_world() { return {sweep_world(), state_.time_s, state_.held_back_bounces}; }
  // Kinematic participants to their trajectory pose at t_s, moving as they will over
  // the next h_s (h_s = 0: their instantaneous twist).
  void set_kinematic_state(const std::vector<int>& participants, double t_s, double h_s);
  // Wakes the sleepers a moving body can reach over dt_s (in turn, the sleepers they
  // touched when they fell asleep); the others stay asleep, held fixed through the step.
  void wake_reachable_sleepers(double dt_s);
  // Counts each awake body's quiet time and puts quiet islands to sleep.
  void end_sleep_step(double dt_s, StepReport& report);
  // Wakes these bodies (their quiet time restarts) and, in turn, the sleepers they touched.
  void wake(std::vector<int> bodies);
  // |v| + |w| r: a bound on how fast any point of the body moves (r its bounding radius).
  double point_speed_m_s(int index) const;
  // The physics moves the body in this step: dynamic and awake.
  bool moving(int index) const { return moves(model_.bodies[index], state_.bodies[index]); }

  WorldModel model_;
  WorkerPool pool_;
  WorldState state_;
};

}  // namespace arphys::dynamics
