#pragma once
// The simulated world: bodies, and the time stepping of docs/method.md section 2 driven by
// the CCD of section 1. One step of dt:
//   1. contacts: every feature pair closer than contact_tolerance_m;
//   2. unconstrained velocities: gravity and gyroscopic terms over the time left;
//   3. Gauss's principle at the velocity level (contact_solver.hpp): resting contacts
//      may close to contact_gap_m but not further, approaching ones bounce with their
//      restitution;
//   4. the bodies' screw motions to their candidate poses are checked by CCD; the point
//      where a pair meets inside the step (fixed in both bodies, with its normal)
//      joins the constraints and 3 is solved again, up to five rounds, so the impact
//      (with its restitution) happens in this step; the point is kept out by where
//      it ends the motion (a Newton step on its depth: a turning body's linearised
//      constraint alone misses by micrometres); if the CCD still finds a meeting, or
//      a bounce that this step's solve brought about (a struck body striking the
//      next), the step stops at that time of impact and continues from it, at most
//      max_events_per_step times.
// Steps 1-3 are done for all bodies at once, and the CCD of 4 sweeps every pair once.
// Then bodies that may meet within the step (in contact, or with overlapping sweeps)
// form groups; a group where nothing meets just moves, the others go through 4 on their
// own, so a time of impact cuts only its own group's step. A group whose new motion
// reaches another group's sweep is merged with it and both are stepped again.
// A pair touching at the start of a step (which the CCD cannot time), or resting (in
// contact) and moving less than resting_unswept_motion_m relative to each other, is
// checked at the end of its motion instead: if it ends deeper than overlap_tolerance_m,
// a primitive pair is lifted out by moving the end poses (project_deep_points: velocities
// unchanged), otherwise its deepest points join the constraints (see ImpactPoint), and
// failing that the step is cut; a step cut mid-motion is cut early enough that no such
// pair is left deeper there than the rest of the step undoes.
// Kinematic bodies follow their trajectories (tracked poses, screw-interpolated) and
// push dynamic ones through the same contacts. Nothing ever passes through anything:
// surfaces only meet at a CCD time of impact, where they touch.
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "simulator/dynamics/contact.hpp"
#include "simulator/dynamics/contact_solver.hpp"
#include "simulator/dynamics/disjoint_sets.hpp"
#include "simulator/dynamics/rigid_body.hpp"
#include "simulator/dynamics/step_contacts.hpp"
#include "simulator/dynamics/step_solve.hpp"
#include "simulator/dynamics/step_sweep.hpp"
#include "simulator/dynamics/worker_pool.hpp"
#include "simulator/dynamics/world_options.hpp"

namespace arphys::dynamics {

class World {
 public:
  // Throws std::invalid_argument as check_world_options does.
  explicit World(WorldOptions options = {});

  // Adds a body; a dynamic one needs a positive mass and an invertible inertia, and
  // every body a finite pose (std::invalid_argument naming the body otherwise).
  int add_body(RigidBody body);
  StepReport step(double dt_s);

  double time_s() const { return time_s_; }
  const std::vector<RigidBody>& bodies() const { return bodies_; }
  bool asleep(int index) const { return asleep_.at(index) != 0; }
  // A body's shape, mass and material are fixed once it is added; its state changes by
  // stepping and by the calls below, each of which throws std::invalid_argument naming the
  // body for a value it cannot take.
  const RigidBody& body(int index) const { return bodies_.at(index); }
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
  const std::vector<Contact>& contacts() const { return contacts_; }
  const WorldOptions& options() const { return options_; }

 private:
  // A dynamic body's state moves through a step in its group (see step()); a group's
  // participants are its dynamic bodies and every non-dynamic body, in body order.
  // What the step's first solve (all bodies at once) gave a group, by participant.
  struct FirstSolve {
    std::vector<BodyVelocity> u;
    std::vector<Contact> resting, solved;
    SolvedIslands& islands;  // the islands solved at the step's start poses, shared by every group
  };
  struct GroupOutcome {
    std::vector<Contact> contacts;            // of the group's last solve
    std::vector<Eigen::AlignedBox3d> swept;   // box each participant swept over the step
    bool capped = false;
  };
  // Keeps the end pose next_before of each dynamic body whose velocity u is u_before
  // (static bodies: always); returns which, by participant.
  std::vector<char> keep_motions(const std::vector<int>& participants, const std::vector<BodyVelocity>& u_before,
                                 const std::vector<geometry::Pose>& next_before, const std::vector<BodyVelocity>& u,
                                 std::vector<geometry::Pose>& next) const;
  // A cut of a group's step at a time of impact: the motion it cut (participants'
  // velocities and end poses), where, and the CCD answers for that motion.
  struct Cut {
    std::vector<BodyVelocity> u;
    std::vector<geometry::Pose> next;
    double tau = 1;
    ImpactCache answers;
  };
  // The CCD answers of the cut motion that hold for the motion after it; sets the end
  // pose of each body that goes on as before back to the one the cut motion had.
  ImpactCache carry_over_cut(const std::vector<int>& participants, const std::vector<BodyVelocity>& u,
                             std::vector<geometry::Pose>& next, Cut& cut) const;
  // The step's first pass over every body at once: contacts, one solve, the motions it
  // gives, their swept boxes and CCD, and the groups those form.
  struct FirstPass {
    std::vector<Contact> resting, solved;
    SolvedIslands islands;
    std::vector<BodyVelocity> u;             // by body
    std::vector<geometry::Pose> next;        // by body
    std::vector<Eigen::AlignedBox3d> swept;  // by body, over its motion to next
    ImpactCache ccd;
    DisjointSets groups{0};
    std::set<int> eventful;  // roots of the groups whose CCD met something or ended too deep
  };
  FirstPass first_pass(double dt_s, const std::vector<int>& everyone, StepReport& report);
  // Clears the memos of the last step and takes up the bounces it held back.
  void begin_step_memos();
  struct GroupStepping;  // (world.cpp)
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
  // What every solve of one part of a group's step shares (a part: from the step's start or
  // a cut to the step's end or the next cut): the time left, the time its force acts over,
  // the resting contacts at its start poses and the islands solved there.
  struct PartSolve {
    double elapsed = 0, h = 0, force_h = 0;
    const std::vector<Contact>& resting;
    std::vector<std::pair<int, int>> resting_pairs;
    SolvedIslands& islands;
    std::optional<SolveSetup> setup;  // built when a solve needs it
  };
  // A part's motion: velocities and end poses by participant, and the fraction of it taken
  // (1: to the end of the step; less: cut at a time of impact).
  struct PartMotion {
    std::vector<BodyVelocity> u;
    std::vector<geometry::Pose> next;
    double tau = 1;
    bool squeezed = false;  // the last solve could not keep a body out of fixed ones
  };
  // Rounds of CCD and re-solve of a part's motion, each meeting a constraint of the next
  // solve, until nothing meets inside it (tau 1) or it must be cut (tau < 1). `contacts`:
  // the last solve's; cut_at_start: the last cut was at the start of its motion.
  void resolve_rounds(const std::vector<int>& participants, PartSolve& part, ImpactCache& cache, bool cut_at_start,
                      PartMotion& motion, std::vector<Contact>& contacts, StepReport& report);
  // Where the last round stops a motion that still meets or digs in (tau: the earliest
  // meeting; deepening: a touching pair ends too deep).
  double last_round_fraction(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                             const ImpactCache& cache, const ImpactMap& meeting, double tau, bool deepening,
                             bool cut_at_start) const;
  // Adds the meetings' points to `impacts`, each with the normal velocity that lifts it out
  // of where the motion leaves it; a bounce the solve brought about below
  // sequential_bounce_restitution is held back to the next step (next_bounces_). True when
  // one is to be met in turn (the part is cut at it).
  bool add_impact_points(const std::vector<int>& participants, const PartMotion& motion, const PartSolve& part,
                         ImpactMap& meeting, ImpactMap& impacts);
  // Moves the group's dynamic bodies along the part's motion to its fraction tau (a body
  // a numerical failure made non-finite stays where it was, at rest).
  void commit_part(const std::vector<int>& participants, const PartMotion& motion, GroupOutcome& outcome,
                   StepReport& report);
  // Where the participants would be after h from now (elapsed into the step) with
  // velocities u (by participant).
  std::vector<geometry::Pose> candidate_poses(const std::vector<int>& participants, const std::vector<BodyVelocity>& u,
                                              double elapsed, double h) const;
  // The fraction tau of the motion to next (over h_s), or less (halved), at which no
  // unswept pair whose depth is measured (see CachedImpact::swept; not a mesh pair)
  // overlaps deeper than allowed or than the rest of the step can undo: a step cut at tau
  // must not leave such a pair where its motion only passes through (a box clipping
  // another's corner, out again by the motion's end).
  double unswept_clear_fraction(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                                const ImpactCache& cache, double tau, double h_s) const;
  // `fraction` of the pair's motions, halved (at most max_halvings times) until the pair
  // overlaps there by no more than allowed_depth_m(fraction).
  double halved_until_within(const std::pair<int, int>& pair, const geometry::ScrewMotion& motion_a,
                             const geometry::ScrewMotion& motion_b, double fraction, int max_halvings,
                             const std::function<double(double)>& allowed_depth_m) const;
  // Lifts the pairs of `meeting` that end too deep (resting primitive pairs) out by moving
  // the end poses `next`, with the resting pairs the lift deepens; CCD meetings are left
  // for the re-solve. False (next unchanged) when a mesh pair ends too deep or the lift does
  // not converge (a body squeezed between fixed ones).
  bool project_deep_points(const std::vector<int>& participants, std::vector<geometry::Pose>& next,
                           const ImpactMap& meeting, const ImpactCache& cache,
                           const std::vector<std::pair<int, int>>& resting_pairs) const;
  // The fraction of the motions to `next` at which no touching pair that deepens is
  // deeper than it may be (halving from 1): the pairs `meeting` names, as sweep_motions
  // left them in `cache`. (Every pair that deepens is in `meeting`; walking the whole
  // cache, every pair of the step's first sweep, was a few percent of a pile's step.)
  double shallow_fraction(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                          const ImpactCache& cache, const ImpactMap& meeting) const;
  // What the sweep stage reads of this world.
  SweepWorld sweep_world() { return {bodies_, radius_m_, options_, mesh_memo_, pool_}; }
  // Kinematic participants to their trajectory pose at t_s, moving as they will over
  // the next h_s (h_s = 0: their instantaneous twist).
  void set_kinematic_state(const std::vector<int>& participants, double t_s, double h_s);
  // Wakes the sleepers a moving body can reach over dt_s (in turn, the sleepers they
  // touched when they fell asleep), and holds the others fixed for the step (their motion made static);
  // returns those, for end_sleep_step to restore and to put more bodies to sleep.
  std::vector<int> hold_sleepers(double dt_s);
  void end_sleep_step(const std::vector<int>& held, double dt_s, StepReport& report);
  // Wakes these bodies (their quiet time restarts) and, in turn, the sleepers they touched.
  void wake(std::vector<int> bodies);
  // |v| + |w| r: a bound on how fast any point of the body moves (r its bounding radius).
  double point_speed_m_s(int index) const;

  WorldOptions options_;
  WorkerPool pool_;
  std::vector<RigidBody> bodies_;
  std::vector<double> radius_m_;  // bounding radius about each body origin
  // Sleeping (WorldOptions::sleep_after_s): how long each body has been quiet, and whether it sleeps.
  std::vector<double> quiet_s_;
  std::vector<char> asleep_;
  // Bodies moved by place_body since the last step: each wakes the sleepers its new pose
  // reaches (held as fixed bodies, they would meet a placed kinematic body as two
  // non-dynamic bodies do: not at all).
  std::vector<char> placed_to_wake_;
  std::vector<std::vector<int>> touching_;  // a sleeper's dynamic contact partners when it fell asleep
  std::vector<Contact> contacts_;
  ContactHints hints_;                              // what the last step left this one's contacts
  std::vector<ContactHints::Bounce> next_bounces_;  // what this step leaves the next (unsorted)
  MeshCrossingMemo mesh_memo_;
  double time_s_ = 0;
};

}  // namespace arphys::dynamics
