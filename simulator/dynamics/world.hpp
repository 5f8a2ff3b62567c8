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
#include "simulator/dynamics/contact_solver.hpp"
#include "simulator/dynamics/disjoint_sets.hpp"
#include "simulator/dynamics/rigid_body.hpp"
#include "simulator/dynamics/worker_pool.hpp"

namespace arphys::dynamics {

struct WorldOptions {
  Eigen::Vector3d gravity_m_s2{0, 0, -9.81};
  // Feature pairs closer than this are constraints of the step.
  double contact_tolerance_m = 1e-3;
  // A resting pair (constraints of the step already) whose points move less than this
  // relative to each other over a step is held by its contacts and checked at the end of
  // its motion instead of swept by the CCD (World::earliest_impact). Capped per pair at a
  // quarter of the thinner body's thickness, so nothing passes through anything unswept;
  // pairs with a mesh (whose thinnest part is not known) or with restitution (what the
  // end check finds is held, not bounced) keep to contact_tolerance_m. Most of a settling
  // 1000-box pile's time was the CCD of such pairs and the cuts it found (10 mm: a third
  // of the time of 1 mm over the anchor's 2 s; docs/dynamics.md).
  double resting_unswept_motion_m = 10e-3;
  // No pair ends a step deeper inside each other than this, or than it started the
  // step (a tracked body pushed into a virtual one is undone at
  // max_depenetration_speed_m_s, not at once).
  double overlap_tolerance_m = 1e-6;
  // The gap resting contacts keep: surfaces never quite touch at rest, so the CCD of the
  // next step does not see them as impacts (no endless tiny events).
  double contact_gap_m = 1e-6;
  // Speed at which an overlap (a tracked body pushed into a virtual one faster than it
  // could move) is undone; bounded so nothing is launched.
  double max_depenetration_speed_m_s = 0.05;
  // Approach speeds below this do not bounce (resting contact under gravity).
  double restitution_threshold_m_s = 0.05;
  // A bounce that a solve brings about within the step (a struck body striking the next)
  // is met in turn, the step cut there and bounced from the velocities then, when the
  // pair's restitution is at least this. Below it the pair is held together by this step's
  // solve and pushed apart at the next step's start with the speed it missed: momentum and
  // the restitution's share of energy kept, one step late, and no cut, which re-solves and
  // re-sweeps the whole group (in a pile of bunnies, restitution 0.3-0.4, nearly every step).
  double sequential_bounce_restitution = 0.5;
  int max_events_per_step = 16;
  // Points of resting primitive pairs (boxes, spheres, planes) that the step's motion
  // leaves deeper than overlap_tolerance_m, with nothing meeting inside the step, are
  // lifted out by moving the end poses (post-stabilisation, position_projection.hpp)
  // instead of by a velocity constraint and another solve of the step. False: every
  // such point is a constraint of a re-solve (docs/decisions/0004).
  bool project_deep_points = true;
  // Launch guard (see World::solve and StepReport::launches_prevented): speed (of a
  // body's kinetic energy) a solve may add beyond twice the fastest body it couples and
  // the depenetration speed.
  double launch_guard_slack_m_s = 0.5;
  // No body point moves faster than this after a solve (metres per second).
  double max_body_speed_m_s = 60.0;
  // A body pair's contact set is reduced to at most this many points when larger (the
  // closest point per normal direction, then the extremes of each contact patch, which
  // keep its support polygon; see manifold_reduction.hpp).
  int max_contacts_per_pair = 16;
  // Deactivation ("sleeping"): a dynamic body whose points have all moved slower than
  // sleep_speed_m_s for sleep_after_s is stopped and held as if fixed, costing nothing,
  // until a moving body comes within reach of it over a step; that wakes it and, in turn,
  // the sleepers it touched when it fell asleep. 0: never (the default: the
  // benchmark scenes measure every body every step). A woken body starts from rest.
  double sleep_after_s = 0;
  double sleep_speed_m_s = 0.01;
  ContactSolverOptions solver;
  // Threads for the step's per-pair work (contact manifolds, sweeps and end checks of
  // depth-measured pairs: boxes, spheres, planes, convex pieces); mesh pairs, the solves
  // and the stepping stay on the calling thread. The result does not depend on it.
  int threads = 1;
  // CCD settings; its work budget bounds a step's cost when meshes have sunk into each
  // other (the step is then cut where the CCD stopped, never past a contact).
  collision::ContinuousOptions ccd = [] {
    collision::ContinuousOptions o;
    // A time of impact to a millionth of the step (a nanosecond at 1 ms) is never late
    // and early by less than the motion over that time; the CCD library's default
    // (1e-9, for measuring it) made near-parallel edges of resting boxes take 40 % more
    // of a 1000-box pile's time for no difference a simulation can show.
    o.time_tolerance = 1e-6;
    o.max_triangle_pairs = 2000;
    o.max_search_nodes = 200000;
    return o;
  }();
};

struct Contact {
  int body_a = -1, body_b = -1;  // indices into World::bodies()
  collision::ManifoldPoint feature;
  double impulse_N_s = 0;  // normal impulse of the last solve
  // A lower bound on the normal velocity beyond what the gap asks (see ImpactPoint).
  double min_normal_velocity_m_s = -std::numeric_limits<double>::infinity();
  // The pair pushed within contact_tolerance_m of this point in the previous step's last
  // solve (a warm-start hint for the solver, see ContactRow::pushed_before).
  bool pushed_before = false;
  // The force (normal and friction, world frame) within contact_tolerance_m of this point in
  // the previous step's first solve: the iterative solver's warm start (ContactRow).
  Eigen::Vector3d warm_force_W_N = Eigen::Vector3d::Zero();
  Eigen::Vector3d impulse_W_N_s = Eigen::Vector3d::Zero();  // the last solve's normal and friction impulse, world frame
};

struct StepReport {
  // Rounds of the step that had something to resolve: CCD meetings or end checks found too
  // deep, each re-solved or, for resting primitive pairs, lifted (`projections` of them).
  int impacts_resolved = 0;
  int projections = 0;          // rounds whose too-deep resting points were lifted by moving end poses
  int events = 0;               // times the step was cut at a time of impact (its busiest group's)
  bool events_capped = false;   // a group's step ended at an impact (time kept, motion dropped)
  int contacts = 0;             // constraints in the last solve of the step
  bool infeasible = false;      // a body squeezed between non-dynamic ones
  int iterative_islands = 0;    // contact islands too large for the exact solver (max_exact_rows)
  double kkt_residual_m_s = 0;  // worst over the step's solves
  // Deepest overlap among the step's resting contacts where they were gathered: the step's
  // start and each cut (0: none). A cut can catch a pair checked only at the end of its
  // motion inside mid-step, but no deeper than the rest of the step undoes at half
  // max_depenetration_speed_m_s (World::unswept_clear_fraction); every step ends within
  // the overlap tolerance (and its allowed creep).
  double max_penetration_m = 0;
  int solver_iterations = 0;
  int launches_prevented = 0;   // bodies the launch guard slowed (a solve that would launch them)
  int non_finite_held = 0;      // bodies a numerical failure would have made non-finite, held at rest
  int ccd_queries = 0;          // pair motions swept by the CCD (resting pairs are checked at the end instead)
  // Mesh pairs within reach tested for crossing at poses they were gathered at (those the
  // last step's end check or CCD proved apart there are not tested again).
  int mesh_crossing_tests = 0;
  int bodies_asleep = 0;        // after the step (WorldOptions::sleep_after_s)
};

// A meeting the CCD found inside a step: the point, fixed in each body, and A's normal
// there (body frames), for a constraint of the re-solved step.
struct ImpactPoint {
  Eigen::Vector3d point_A_B, point_B_B, normal_A_B;
  // A point where a pair touching at the start ends the step this deep inside (metres;
  // negative for a CCD meeting), and the normal velocity that lifts it out: the
  // linearised constraint let it in, so the bound is its velocity in the last solve
  // plus the depth (and the resting gap) over the step, a Newton step on the true
  // end-of-step depth.
  double end_depth_m = -1;
  double min_normal_velocity_m_s = -std::numeric_limits<double>::infinity();
};
using ImpactMap = std::map<std::pair<int, int>, std::vector<ImpactPoint>>;

class World {
 public:
  // Throws std::invalid_argument naming the option and its value when one is out of its
  // range (a NaN or negative tolerance, a zero event cap).
  explicit World(WorldOptions options = {});

  // Adds a body; a dynamic one needs a positive mass and an invertible inertia, and
  // every body a finite pose (std::invalid_argument naming the body otherwise).
  int add_body(RigidBody body);
  StepReport step(double dt_s);

  double time_s() const { return time_s_; }
  const std::vector<RigidBody>& bodies() const { return bodies_; }
  bool asleep(int index) const { return asleep_.at(index) != 0; }
  RigidBody& body(int index) { return bodies_.at(index); }
  // Moves a body to a pose (not along a motion: nothing is swept), as add_body places
  // one: its next step tests its pairs for crossing deeper than the contact tolerance
  // (see placed_crossing_). std::invalid_argument names the body for a non-finite pose.
  void place_body(int index, const geometry::Pose& X_WB);
  int find(const std::string& id) const;  // -1 when absent
  // Removes a body (indices after it shift down by one).
  void remove_body(int index);
  const std::vector<Contact>& contacts() const { return contacts_; }
  const WorldOptions& options() const { return options_; }

 private:
  // A pair's CCD answer for motions from the current poses to next_A, next_B.
  struct CachedImpact {
    bool valid = false;
    geometry::Pose next_A, next_B;
    collision::ContinuousResult result;
    std::vector<ImpactPoint> hits;  // the meeting, or the points a touching pair digs in at
    bool deepens = false;           // touching at the start, deeper than allowed at the end
    double allowed_depth_m = 0;     // for a touching pair: the deeper of overlap_tolerance_m and its start depth
    // A touching pair's deepest overlap at the start poses, kept when the pair is asked again
    // from the same start with other end poses (a re-solve moves every body of its island);
    // negative: not measured. (Measured again each time, it was half the box-box manifolds of
    // a 1000-box pile's step.)
    double start_depth_m = -1;
    bool swept = false;             // the CCD ran and timed the motion (not touching at the start)
    double free_until = 1;          // a touching mesh pair: the fraction of the motion before its surfaces cross
  };
  using ImpactCache = std::map<std::pair<int, int>, CachedImpact>;
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
  // Contacts within contact_tolerance_m at the current poses, among the participants.
  std::vector<Contact> gather_contacts(const std::vector<int>& participants) const;
  // A mesh pair's reduced manifold at the current poses, with the contact that pushes
  // crossed surfaces apart (mesh_crossing_depth); updates the pair's memos.
  std::vector<collision::ManifoldPoint> mesh_pair_features(int i, int j) const;
  // Contacts of pair (i, j) at these features, with their warm-start hints from the last step.
  void append_contacts(int i, int j, const std::vector<collision::ManifoldPoint>& features,
                       std::vector<Contact>& contacts) const;
  // The meetings the CCD found in the step, as contacts at the current poses.
  std::vector<Contact> impact_contacts(const ImpactMap& impacts) const;
  // What a solve needs before the impacts are known: the unknowns (the dynamic
  // participants), their inertia and unconstrained velocities, and the resting contacts'
  // rows. The same for every re-solve at the same poses (a group's rounds): built once
  // for them (rebuilt every round, the rows were a twentieth of a 1000-box pile's step).
  struct SolveSetup {
    double h = 0;
    // Rows start their iterative solve from their warm forces times this: h in a solve that
    // applies the step's forces, as the step's first solve did; 0 after a cut.
    double warm_h_s = 0;
    std::vector<int> unknown_of_slot, slot_of_unknown, body_of_unknown;
    std::vector<BodyInertia> inertia;
    std::vector<BodyVelocity> u_unconstrained;
    std::vector<ContactRow> resting_rows;
    double deepest_m = 0;  // deepest overlap among the resting contacts
  };
  // h: the time left in the step; force_h: the time over which gravity and the
  // gyroscopic term act in this solve (the whole step in its first solve, 0 after a cut).
  SolveSetup prepare_solve(double h, double force_h, const std::vector<int>& participants,
                           const std::vector<Contact>& resting) const;
  // A contact's constraint row for a solve over h (setup.h): its bounds from its gap, its
  // bounce and its own lower bound.
  ContactRow row_of(const Contact& contact, const SolveSetup& setup, const std::vector<int>& participants) const;
  // Solves the resting contacts (those the setup was built from) and the impact contacts
  // for the time left in the step, from the current velocities; returns the velocities
  // to move with, by participant, and the contacts solved (with their impulses) in
  // `solved`; `infeasible`: whether a body was squeezed (see StepReport::infeasible).
  std::vector<BodyVelocity> solve(const SolveSetup& setup, const std::vector<int>& participants,
                                  const std::vector<Contact>& resting, const ImpactMap& impacts,
                                  std::vector<Contact>& solved, StepReport& report, bool* infeasible,
                                  SolvedIslands* memo) const;
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
  // Box containing a body's bounding ball along its screw motion to `next`.
  Eigen::AlignedBox3d swept_box(int body, const geometry::Pose& next) const;
  // Earliest time of impact (fraction of h) of the participants' motions from their
  // current poses to `next` (by participant), or 1. `cache` (optional) answers pairs
  // whose motions it has seen since the poses last changed. `deepening`: set when a
  // pair touching at the start ends deeper than overlap_tolerance_m (its points are in
  // `meeting`, with no time of impact). resting_pairs: body pairs with contacts at the
  // current poses (sorted); those moving less than contact_tolerance_m relative to each
  // other are checked at the end of their motion, like touching ones, not swept.
  // swept_pairs: the participants' pairs (by slot) whose swept boxes overlap, if already known.
  double earliest_impact(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                         const std::vector<std::pair<int, int>>* resting_pairs, ImpactMap* meeting, ImpactCache* cache,
                         bool* deepening, StepReport& report,
                         const std::vector<std::pair<int, int>>* swept_pairs = nullptr) const;
  // One pair of earliest_impact: its slots, its cache entry, and how its motion is checked.
  struct PairSweep {
    int p = -1, q = -1;               // slots in the participants
    CachedImpact* query = nullptr;
    bool fresh = false;               // its motions changed since its entry was answered
    bool apart_at_start = false, resting_slowly = false, swept_by_ccd = false;
    double relative_motion_m = 0;
  };
  // earliest_impact's passes for a fresh pair: how it is checked (in order: reads the
  // memos); its CCD and, for a depth-measured pair, its end check (any thread); then in
  // order its counts, memos and, for a mesh pair, its end check.
  void classify_sweep(PairSweep& sweep, const std::vector<int>& participants, double relative_motion_m, double curve_m,
                      const std::vector<std::pair<int, int>>* resting_pairs) const;
  void answer_sweep(PairSweep& sweep, const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                    const geometry::ScrewMotion& motion_A, const geometry::ScrewMotion& motion_B) const;
  void finish_sweep(PairSweep& sweep, const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                    const geometry::ScrewMotion& motion_A, const geometry::ScrewMotion& motion_B,
                    StepReport& report) const;
  // How far any point of the body can be, over the step, from where it was on the motion to
  // swept_to when it moves on `now` instead (both from its pose at the step's start).
  double motion_change_m(int body, const geometry::Pose& swept_to, const geometry::ScrewMotion& now) const;
  // How deep bodies a and b are inside each other at these poses (0: apart).
  double deepest_overlap(int a, const geometry::Pose& X_WA, int b, const geometry::Pose& X_WB) const;
  // Two meshes whose surfaces cross at their current poses (`manifold`: theirs, within
  // the contact tolerance): a contact that pushes B out of A along the shortest of a few
  // ways that clear them, as deep as B must move that way (to a factor of two, up to
  // kDeepestCrossingMeasured_m). A mesh's own manifold does not measure crossings (its
  // distances are unsigned): a crossed pair stayed crossed for hundreds of steps.
  // (apart: set when the meshes were found not to cross at all; nearby: the pair's
  // triangle pairs near each other, for the intersection test at the current poses.)
  // A `placed` pair (see placed_crossing_) is tested with no feature within the tolerance
  // too, and its contact acts at the dynamic body's centre of mass (midway between two
  // dynamic ones'), so that it lifts a sunken body instead of turning it.
  std::optional<collision::ManifoldPoint> mesh_crossing_depth(const RigidBody& a, const RigidBody& b,
                                                              const std::vector<collision::ManifoldPoint>& manifold,
                                                              bool* apart = nullptr,
                                                              collision::NearbyTrianglePairs* nearby = nullptr,
                                                              bool placed = false) const;
  // Mesh crossings deeper than this are not measured.
  static constexpr double kDeepestCrossingMeasured_m = 0.01;
  // For a mesh pair the CCD found touching at the start, or one resting and moving less
  // than the contact tolerance (not swept): whether its surfaces cross at the end of the
  // motion; if so, the fraction of the motion before they do (query.free_until) and the
  // features touching there (query.hits). nearby: as for mesh_crossing_depth.
  void check_mesh_crossing(const RigidBody& a, const geometry::ScrewMotion& motion_a, const RigidBody& b,
                           const geometry::ScrewMotion& motion_b, double relative_motion_m, CachedImpact& query,
                           collision::NearbyTrianglePairs* nearby) const;
  // The relative motion under which a resting pair is checked at the end of its motion
  // instead of swept (WorldOptions::resting_unswept_motion_m, capped by the pair's shapes).
  double max_unswept_motion_m(const RigidBody& a, const RigidBody& b) const;
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
  // deeper than it may be (halving from 1): the pairs `meeting` names, as earliest_impact
  // left them in `cache`. (Every pair that deepens is in `meeting`; walking the whole
  // cache, every pair of the step's first sweep, was a few percent of a pile's step.)
  double shallow_fraction(const std::vector<int>& participants, const std::vector<geometry::Pose>& next,
                          const ImpactCache& cache, const ImpactMap& meeting) const;
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
  // Where each pair pushed in the previous step (contacts_ with an impulse), sorted by pair.
  struct PushedPoint {
    std::pair<int, int> bodies;
    Eigen::Vector3d point_W;
  };
  std::vector<PushedPoint> pushed_before_;
  // The forces of the previous step's first solve (every group solved over the whole step,
  // with gravity), sorted by pair: where an iterative solve starts from.
  struct PreviousForce {
    std::pair<int, int> bodies;
    Eigen::Vector3d point_W, force_W_N;
  };
  std::vector<PreviousForce> warm_forces_;
  // Bounces a step held back (WorldOptions::sequential_bounce_restitution): the pair's
  // contacts along that normal (A to B) separate at least that fast in the next step.
  // pending_bounces_ (sorted by pair) is read by this step's contacts, next_bounces_ written for the next.
  struct PendingBounce {
    std::pair<int, int> bodies;
    Eigen::Vector3d normal_W;
    double speed_m_s = 0;
  };
  std::vector<PendingBounce> pending_bounces_, next_bounces_;
  // Mesh pairs that gather_contacts found not crossing, at the poses it found them at:
  // the CCD of their motions from those poses skips its start test (the same test at
  // the same poses was a twelfth of the 100-bunny scene). A memo, so mutable; cleared
  // every step.
  struct ApartAt {
    geometry::Pose X_WA, X_WB;
  };
  mutable std::map<std::pair<int, int>, ApartAt> apart_at_;
  // Whether `known` holds pair (i, j) apart at exactly these poses (a fact about the
  // poses, so only an exact match counts).
  static bool known_apart(const std::map<std::pair<int, int>, ApartAt>& known, int i, int j, const geometry::Pose& X_WA,
                          const geometry::Pose& X_WB);
  // Mesh pairs proven apart at the end poses of a motion, by its end check
  // (check_mesh_crossing) or by a CCD sweep from apart that met nothing: if the step ends
  // with them there, the next step's contact pass has its own crossing test's answer at
  // those poses. While the box pushed the pile of the 20-bunny scene, the pile's pairs were
  // tested twice at the same poses, at either side of the step boundary: skipping the
  // second cut the simulator's CPU over the recorded 20 s main job from 8.0 s to 7.0 s (three
  // replays each), with the same world states (71,000 skipped tests, each checked against
  // the test: none differed).
  // Written during a step, read in the next.
  mutable std::map<std::pair<int, int>, ApartAt> apart_at_end_, apart_at_last_end_;
  mutable int crossing_tests_ = 0;  // this step's (mesh_crossing_depth's), for StepReport::mesh_crossing_tests
  // Mesh pairs' triangle pairs near each other (collision::NearbyTrianglePairs), kept
  // from step to step while the contact pass meets the pair (an entry a step did not use
  // is dropped at the next). A memo, so mutable.
  struct Nearby {
    collision::NearbyTrianglePairs pairs;
    bool used = false;
  };
  mutable std::map<std::pair<int, int>, Nearby> nearby_;
  // Mesh bodies can cross deeper than the contact tolerance only where nothing stepped
  // them there: a body added or placed (or every body, after a removal) since the last step.
  // Their pairs are tested for crossing with no feature within the tolerance, and a
  // pair found crossing stays in placed_crossing_ (tested so every step) until it is
  // apart: a crossing pair can turn out of the tolerance before it is out. (A pose set
  // through body() is not seen: add_body and place_body place.) (Only
  // the shallow crossings of stepped pairs were pushed out: a mesh cube placed 1.6 mm
  // into a box table had no feature within 1 mm and fell through it.) Pairs that
  // stepping left crossing are not placed ones: they are pushed out where they cross.
  std::vector<char> placed_since_step_;
  mutable std::set<std::pair<int, int>> placed_crossing_;
  collision::NearbyTrianglePairs* nearby_pairs(int i, int j) const;
  double time_s_ = 0;
};

}  // namespace arphys::dynamics
