// arphys-dyn-bench: the dynamics scenes of ../shared/anchors/dyn.md on arphys and on
// its peers (Bullet, ODE, MuJoCo) in one run, with the same metrics for all:
//   stack     frictionless stacks of 5 and 10 boxes: topple? top-box drift, tilt
//   push      a 30 Hz tracked box pushing a box at 0.5 m/s (one frame late, piecewise
//             linear), with 0 and 1 mm noise: peak pushed speed / 0.5, overlap
//   drop      N = 10, 100, 1000 boxes dropped on a plane: ms per step, penetration
//   anchor-pile  the 1000-box drop over 2 s, the anchor's protocol for the target:
//             mean ms per step against ODE quickstep and Bullet (left out by --quick)
//   bunnies   the paper's scene (arphys only: the peers have no dynamic concave meshes
//             here): real-time factor
// Writes CSV per scene and prints tables. Times are wall clock of the stepping loop.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>

#include "configs/loader/scene_config.hpp"
#include "simulator/collision/broad_phase.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/dynamics/memory_policy.hpp"
#include "simulator/scene/scene_world.hpp"
#include "tools/dyn_bench/bunnies_peers.hpp"
#include "tools/dyn_bench/engine.hpp"
#include "tracker/pose/constant_velocity_filter.hpp"

namespace arphys::dyn_bench {

std::unique_ptr<Engine> make_arphys_engine(const std::string& variant);  // arphys, arphys-iterative, arphys-10um, arphys-resolve
std::unique_ptr<Engine> make_bullet_engine();
std::unique_ptr<Engine> make_ode_engine(bool quick);
std::unique_ptr<Engine> make_mujoco_engine(const std::string& solver);

std::unique_ptr<Engine> make_engine(const std::string& v) {
  if (v.rfind("arphys", 0) == 0) return make_arphys_engine(v);
  if (v == "bullet") return make_bullet_engine();
  if (v == "ode-step") return make_ode_engine(false);
  if (v == "ode-quick") return make_ode_engine(true);
  if (v.rfind("mujoco-", 0) == 0) return make_mujoco_engine(v.substr(7));
  throw std::invalid_argument("unknown engine '" + v + "'");
}

// The engines the 1000-box pile runs compare, run after run: ours at 1 um and at the
// issue's 10 um budget, and the target, ODE's quickstep.
const char* const kPileEngines[] = {"arphys", "arphys-10um", "ode-quick"};

std::vector<std::string> all_engines() {
  return {"arphys", "arphys-10um", "arphys-iterative", "arphys-resolve", "bullet", "ode-step", "ode-quick", "mujoco-newton", "mujoco-pgs", "mujoco-cg"};
}

}  // namespace arphys::dyn_bench

namespace {

using namespace arphys::dyn_bench;
using Clock = std::chrono::steady_clock;
// Longest wall time one engine may take on one scene variant; slower runs are cut and
// their CSV row says how much simulated time they covered.
constexpr double kWallCap_s = 180.0;

BenchBody plane(double friction = 0) {
  BenchBody b;
  b.shape = BenchBody::Shape::kPlane;
  b.motion = BenchBody::Motion::kStatic;
  b.friction = friction;
  return b;
}

BenchBody box_at(const Eigen::Vector3d& p, double friction = 0) {
  BenchBody b;
  b.X_WB.translation() = p;
  b.friction = friction;
  return b;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

// The chaotic scenes (the pile, the bunnies) run again with each body's start velocity
// along x changed by this, up to 8 um/s, seeded by the body and the run (0 for run 0).
double start_velocity_perturbation_m_s(int body, int run) {
  return run == 0 ? 0.0 : 1e-6 * ((body * 7919 + run * 104729) % 17 - 8);
}

// Deepest box corner below the plane z = 0, metres (0: none).
double corner_penetration(const Eigen::Isometry3d& X, const Eigen::Vector3d& h) {
  double deepest = 0;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d c(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
    deepest = std::max(deepest, -(X * c).z());
  }
  return deepest;
}

// Deepest overlap of any two boxes (half extents h), metres (0: none), by the same
// contact manifold (separating axes and clipping) for every engine's poses.
double box_overlap(const std::vector<Eigen::Isometry3d>& poses, const Eigen::Vector3d& h) {
  const arphys::collision::Shape box = arphys::collision::Shape::box(2 * h);
  std::vector<Eigen::AlignedBox3d> bounds;
  for (const auto& X : poses) bounds.emplace_back(X.translation().array() - h.norm(), X.translation().array() + h.norm());
  double deepest = 0;
  for (const auto& [i, j] : arphys::collision::overlapping_pairs(bounds))
    for (const auto& p : arphys::collision::contact_manifold(box, poses[i], box, poses[j], 0.0))
      deepest = std::max(deepest, -p.distance_m);
  return deepest;
}

struct Csv {
  std::ofstream out;
  Csv(const std::string& path, const std::string& header) : out(path) {
    // (A missing --out directory would otherwise write nothing, silently.)
    if (!out) throw std::runtime_error("cannot write " + path + " (does the --out directory exist?)");
    out << header << "\n";
  }
};

void run_stack(const std::vector<std::string>& engines, double duration, const std::vector<double>& dts, Csv& csv) {
  std::printf("\n== stack: frictionless, %g s\n%-18s %3s %6s %8s %9s %12s %10s %10s\n", duration, "engine", "n", "dt_ms",
              "toppled", "topple_s", "top_drift_mm", "tilt_deg", "ms/step");
  for (int n : {5, 10})
    for (double dt : dts)
      for (const std::string& e : engines) {
        BenchScene scene;
        scene.bodies.push_back(plane());
        for (int i = 0; i < n; ++i) scene.bodies.push_back(box_at({0, 0, 0.1 + 0.2 * i}));
        auto engine = make_engine(e);
        engine->build(scene, dt);
        const Eigen::Vector3d top0 = scene.bodies.back().X_WB.translation();
        double drift = 0, tilt = 0, topple_t = -1;
        const long steps = std::lround(duration / dt);
        const auto start = Clock::now();
        long done = 0;
        for (long k = 0; k < steps && std::chrono::duration<double>(Clock::now() - start).count() < kWallCap_s; ++k, ++done) {
          engine->step();
          drift = std::max(drift, (engine->pose(n).translation() - top0).norm());
          for (int i = 1; i <= n; ++i) {
            const Eigen::Isometry3d X = engine->pose(i);
            const Eigen::Vector3d d = X.translation() - scene.bodies[i].X_WB.translation();
            tilt = std::max(tilt, Eigen::AngleAxisd(X.linear()).angle());
            if (topple_t < 0 && (d.head<2>().norm() > 0.1 || std::abs(d.z()) > 0.1)) topple_t = (k + 1) * dt;
          }
          if (topple_t >= 0 && (k + 1) * dt > topple_t + 1.0) break;  // toppled: no need to watch the pile
        }
        const double ms = 1e3 * std::chrono::duration<double>(Clock::now() - start).count() / std::max(done, 1L);
        std::printf("%-18s %3d %6.0f %8s %9.3f %12.4f %10.4f %10.4f\n", e.c_str(), n, dt * 1e3, topple_t >= 0 ? "YES" : "no",
                    topple_t, 1e3 * drift, tilt * 180 / M_PI, ms);
        csv.out << e << "," << n << "," << dt << "," << (topple_t >= 0) << "," << topple_t << "," << 1e3 * drift << ","
                << tilt * 180 / M_PI << "," << ms << "," << done * dt << "\n";
        std::fflush(stdout);
      }
}

void run_push(const std::vector<std::string>& engines, Csv& csv) {
  std::printf("\n== push: 30 Hz tracked pusher, one frame late, 0.5 m/s for 3 s, floor friction 0.5\n"
              "%-18s %6s %8s %10s %8s %11s %10s\n", "engine", "dt_ms", "noise_mm", "peak/0.5", "at_s", "overlap_mm",
              "ms/step");
  // Noise variants: none, 1 mm, and 1 mm through the tracker's constant-velocity pose
  // filter (tracker --filter constant_velocity), the same filtered poses for every engine.
  struct Variant {
    double sigma;
    bool filtered;
  };
  for (double dt : {1e-3, 1e-2})
    for (const Variant variant : {Variant{0.0, false}, Variant{1e-3, false}, Variant{1e-3, true}})
      for (const std::string& e : engines) {
        const double sigma = variant.sigma;
        // Observations P_k at t_k = k / 30 (seed 777), as in the anchor.
        std::mt19937 rng(777);
        std::normal_distribution<double> noise(0, 1);
        std::vector<Eigen::Vector3d> P;
        arphys::tracking::ConstantVelocityPoseFilter filter;
        for (int k = 0; k * (1.0 / 30) <= 4.1; ++k) {
          const double t = k / 30.0;
          P.emplace_back(0.5 * std::min(t, 3.0) + (k ? sigma * noise(rng) : 0.0), k ? sigma * noise(rng) : 0.0, 0.102);
          if (variant.filtered) P.back() = filter.filter(arphys::geometry::translation_pose(P.back()), t).translation();
        }
        BenchScene scene;
        scene.bodies.push_back(plane(0.5));
        BenchBody pusher = box_at({0, 0, 0.102}, 0.5);
        pusher.motion = BenchBody::Motion::kKinematic;
        scene.bodies.push_back(pusher);
        scene.bodies.push_back(box_at({0.3, 0, 0.1}, 0.5));
        auto engine = make_engine(e);
        engine->build(scene, dt);
        double peak = 0, peak_t = 0, overlap = 0;
        const long steps = std::lround(4.0 / dt);
        const auto start = Clock::now();
        for (long s = 0; s < steps; ++s) {
          const double t = s * dt;
          const int k = std::max(1, static_cast<int>(t * 30));
          const Eigen::Vector3d v = 30.0 * (P[k] - P[k - 1]);
          Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
          X.translation() = P[k - 1] + (t - k / 30.0) * v;  // mode L: one frame late, linear
          engine->set_kinematic(1, X, v);
          engine->step();
          if (engine->velocity(2).norm() > peak) {
            peak = engine->velocity(2).norm();
            peak_t = (s + 1) * dt;
          }
          overlap = std::max(overlap, engine->pose(1).translation().x() + 0.2 - engine->pose(2).translation().x());
        }
        const double ms = 1e3 * std::chrono::duration<double>(Clock::now() - start).count() / steps;
        std::printf("%-18s %6.0f %8.0f%s %10.3f %8.3f %11.3f %10.4f\n", e.c_str(), dt * 1e3, sigma * 1e3,
                    variant.filtered ? "f" : " ", peak / 0.5, peak_t, 1e3 * overlap, ms);
        csv.out << e << "," << dt << "," << sigma << "," << peak / 0.5 << "," << 1e3 * overlap << "," << ms << ","
                << variant.filtered << "," << peak_t << "\n";
        std::fflush(stdout);
      }
}

// One run of the drop scene on one engine. Run 0 is the seeded grid as it is; a further
// run perturbs the boxes' start velocities by up to 8 um/s (seeded by the run).
struct DropRun {
  std::string error;  // the engine could not build the scene
  double median_ms = 0, mean_ms = 0, deepest_m = 0, final_penetration_m = 0, overlap_m = 0;
  long steps = 0, done = 0;
};

DropRun drop_once(const std::string& e, int n, double mu, double duration, int run) {
  BenchScene scene;
  scene.bodies.push_back(plane(mu));
  // splitmix64 seed 12345, as the scene files and the anchor.
  uint64_t state = 12345;
  auto next = [&] {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * (1.0 / 9007199254740992.0);
  };
  for (int i = 0; i < n; ++i) {
    const int layer = i / 100, gx = i % 10, gy = (i % 100) / 10;
    BenchBody b = box_at({(gx - 4.5) * 0.35, (gy - 4.5) * 0.35, 0.2 + 0.35 * layer}, mu);
    const Eigen::Vector3d axis(2 * next() - 1, 2 * next() - 1, 2 * next() - 1);
    const double angle = 0.3 * next();
    if (axis.norm() > 0) b.X_WB.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    b.v_m_s.x() += start_velocity_perturbation_m_s(i, run);
    scene.bodies.push_back(b);
  }
  DropRun out;
  auto engine = make_engine(e);
  try {
    engine->build(scene, 1e-3);
  } catch (const std::exception& ex) {
    out.error = ex.what();
    return out;
  }
  std::vector<double> ms;
  out.steps = std::lround(duration / 1e-3);
  const auto run_start = Clock::now();
  // A wall-clock cap: an engine that crawls is reported with the time it covered.
  for (long s = 0; s < out.steps && std::chrono::duration<double>(Clock::now() - run_start).count() < kWallCap_s;
       ++s, ++out.done) {
    const auto t0 = Clock::now();
    engine->step();
    ms.push_back(1e3 * std::chrono::duration<double>(Clock::now() - t0).count());
    if (s % 10 == 9 || s + 1 == out.steps) {
      out.final_penetration_m = 0;
      for (int i = 1; i <= n; ++i)
        out.final_penetration_m = std::max(out.final_penetration_m, corner_penetration(engine->pose(i), {0.1, 0.1, 0.1}));
      out.deepest_m = std::max(out.deepest_m, out.final_penetration_m);
      std::vector<Eigen::Isometry3d> poses;
      for (int i = 1; i <= n; ++i) poses.push_back(engine->pose(i));
      out.overlap_m = std::max(out.overlap_m, box_overlap(poses, {0.1, 0.1, 0.1}));
    }
  }
  out.median_ms = median(ms);
  out.mean_ms = mean(ms);
  return out;
}

void run_drop(const std::vector<std::string>& all, const std::vector<int>& counts, double duration, int runs, Csv& csv,
              const std::string& runs_csv_path) {
  // Median and mean ms per step: a pile's steps range over two orders of magnitude (quiet
  // steps, then the busy collapse), and its median moves with the trajectory, which is chaotic.
  std::printf("\n== drop: N boxes on a plane, dt 1 ms, %.1f s\n%-18s %5s %5s %10s %10s %16s %10s %14s\n", duration, "engine",
              "N", "mu", "ms/step", "mean_ms", "max_pen_mm", "final_pen_mm", "box_overlap_mm");
  // The pile (N = 1000) again with perturbed starts, on arphys and ODE quickstep (the
  // issue's target): medians by run, for a ratio that is not one trajectory's luck.
  std::map<std::pair<std::string, double>, std::vector<double>> pile_medians;
  for (int n : counts)
    for (double mu : {0.0, 0.5}) {
      // At N = 1000 the slowest variants (MuJoCo PGS and CG, 10 to 70 ms per step in the
      // anchor) would take most of the run: the fastest of each engine family stay.
      std::vector<std::string> engines;
      for (const auto& e : all)
        if (n < 1000 || (e != "mujoco-pgs" && e != "mujoco-cg")) engines.push_back(e);
      for (const std::string& e : engines) {
        const DropRun r = drop_once(e, n, mu, duration, 0);
        if (!r.error.empty()) {
          std::printf("%-18s %5d %5.1f  could not build: %s\n", e.c_str(), n, mu, r.error.c_str());
          continue;
        }
        std::printf("%-18s %5d %5.1f %10.3f %10.3f %16.4f %10.4f %14.4f%s\n", e.c_str(), n, mu, r.median_ms, r.mean_ms,
                    1e3 * r.deepest_m, 1e3 * r.final_penetration_m, 1e3 * r.overlap_m,
                    r.done < r.steps ? ("  (wall-clock cap: " + std::to_string(r.done * 1e-3) + " s simulated)").c_str() : "");
        csv.out << e << "," << n << "," << mu << "," << r.median_ms << "," << 1e3 * r.deepest_m << ","
                << 1e3 * r.final_penetration_m << "," << r.done * 1e-3 << "," << 1e3 * r.overlap_m << "," << r.mean_ms << "\n";
        std::fflush(stdout);
        if (n >= 1000 && std::find(std::begin(kPileEngines), std::end(kPileEngines), e) != std::end(kPileEngines))
          pile_medians[{e, mu}].push_back(r.median_ms);
      }
    }
  if (pile_medians.empty() || runs < 2) return;
  Csv runs_csv(runs_csv_path, "engine,n,mu,run,median_ms_per_step");
  std::printf("\n== drop, N = 1000, %d runs (the first as above, then start velocities perturbed by up to 8 um/s)\n"
              "%-18s %5s %10s %s\n", runs, "engine", "mu", "mean of medians", "medians by run");
  // Run by run, the two engines of a friction setting one after the other: the machine's
  // speed drifts over minutes, and a ratio of runs made minutes apart carried it (all of
  // one engine's runs, then the other's).
  for (int run = 1; run < runs; ++run)
    for (double mu : {0.0, 0.5})
      for (const char* engine : kPileEngines) {
        const auto key = pile_medians.find({engine, mu});
        if (key == pile_medians.end()) continue;
        const DropRun r = drop_once(engine, 1000, mu, duration, run);
        if (r.error.empty()) key->second.push_back(r.median_ms);
        std::fprintf(stderr, "drop N = 1000, run %d of %d: %s mu %.1f, median %.3f ms/step\n", run + 1, runs, engine, mu,
                     r.median_ms);
      }
  for (auto& [key, medians] : pile_medians) {
    std::printf("%-18s %5.1f %10.3f     ", key.first.c_str(), key.second, mean(medians));
    for (std::size_t run = 0; run < medians.size(); ++run) {
      std::printf(" %.3f", medians[run]);
      runs_csv.out << key.first << ",1000," << key.second << "," << run << "," << medians[run] << "\n";
    }
    std::printf("\n");
    std::fflush(stdout);
  }
  for (const char* engine : {"arphys", "arphys-10um"})
    for (double mu : {0.0, 0.5}) {
      const auto ours = pile_medians.find({engine, mu}), theirs = pile_medians.find({"ode-quick", mu});
      if (ours == pile_medians.end() || theirs == pile_medians.end()) continue;
      std::printf("%s / ode-quick, mu %.1f: %.1fx (mean of the runs' medians)\n", engine, mu,
                  mean(ours->second) / mean(theirs->second));
    }
}

// The 1000-box pile as the anchor measured the target (4.35 ms per step for ODE's
// quickstep): 2 s simulated, the cost as wall time per simulated second (the mean ms per
// step), one run. The drop scene above stops at 1 s, while the pile is still landing; in
// the second second a frictionless pile spreads over its frictionless floor, its boxes
// striking each other, and the ratio there is a different one.
void run_anchor_pile(const std::vector<std::string>& all, Csv& csv) {
  std::printf("\n== pile as the anchor ran it: N = 1000, dt 1 ms, 2 s, mean ms per step (= wall s per simulated s)\n"
              "%-18s %5s %10s %10s %16s %14s %12s\n", "engine", "mu", "mean_ms", "median_ms", "max_pen_mm",
              "box_overlap_mm", "simulated_s");
  std::map<std::pair<std::string, double>, double> mean_ms;  // by (engine, mu)
  for (double mu : {0.0, 0.5})
    for (const std::string& e : all) {
      if (e != "arphys" && e != "arphys-10um" && e != "arphys-resolve" && e != "ode-quick" && e != "bullet") continue;
      const DropRun r = drop_once(e, 1000, mu, 2.0, 0);
      if (!r.error.empty()) {
        std::printf("%-18s %5.1f  could not build: %s\n", e.c_str(), mu, r.error.c_str());
        continue;
      }
      std::printf("%-18s %5.1f %10.3f %10.3f %16.4f %14.4f %12.3f%s\n", e.c_str(), mu, r.mean_ms, r.median_ms,
                  1e3 * r.deepest_m, 1e3 * r.overlap_m, r.done * 1e-3, r.done < r.steps ? "  (wall-clock cap)" : "");
      csv.out << e << "," << mu << "," << r.mean_ms << "," << r.median_ms << "," << 1e3 * r.deepest_m << ","
              << 1e3 * r.overlap_m << "," << r.done * 1e-3 << "\n";
      std::fflush(stdout);
      mean_ms[{e, mu}] = r.mean_ms;
    }
  for (const auto& [key, ms] : mean_ms) {
    const auto quick = mean_ms.find({"ode-quick", key.second});
    if (key.first.rfind("arphys", 0) != 0 || quick == mean_ms.end()) continue;
    std::printf("%s / ode-quick, mu %.1f: %.1fx (mean ms per step)\n", key.first.c_str(), key.second, ms / quick->second);
  }
}

// Pairs whose surfaces cross at their current poses: two meshes (bunnies), and a mesh
// with a non-dynamic box (a bunny in the table or in the tracked box).
struct Crossings {
  long meshes = 0, with_fixed = 0;
};
Crossings crossing_pairs(const arphys::dynamics::World& world) {
  using Type = arphys::collision::Shape::Type;
  const auto& bodies = world.body_copies();
  Crossings crossing;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    for (std::size_t j = i + 1; j < bodies.size(); ++j) {
      const auto& a = bodies[i];
      const auto& b = bodies[j];
      const bool meshes = a.shape.type() == Type::kMesh && b.shape.type() == Type::kMesh;
      const bool with_fixed = (a.shape.type() == Type::kMesh && !b.is_dynamic() && b.shape.type() == Type::kBox) ||
                              (b.shape.type() == Type::kMesh && !a.is_dynamic() && a.shape.type() == Type::kBox);
      if (!meshes && !with_fixed) continue;
      if ((a.X_WB.translation() - b.X_WB.translation()).norm() > a.bounding_radius_m() + b.bounding_radius_m()) continue;
      if (!arphys::collision::intersects(*a.shape.triangles(), a.X_WB, *b.shape.triangles(), b.X_WB)) continue;
      ++(meshes ? crossing.meshes : crossing.with_fixed);
    }
  return crossing;
}

void run_bunnies(const std::string& configs, double duration, int runs, Csv& csv) {
  // The scenes are chaotic (a rounding difference sends bunnies elsewhere within a second),
  // so one run's time says little: run 0 is the scene as shipped, each further run starts
  // its bunnies with velocities perturbed by up to 8 um/s (seeded), and the mean is printed.
  // After every step (outside the timing) every close pair of meshes is checked for
  // crossing surfaces: "crossed" counts pair-steps of two bunnies ending so, "in fixed"
  // those of a bunny in the table or the tracked box (a mesh has no depth to
  // report), "waited" the steps in which a group ended its step early (the event cap, or
  // a mesh pair crossing at once while nothing tracked moves: docs/dynamics.md, "Mesh pairs").
  std::printf("\n== bunnies (arphys): the paper's scene, dt 10 ms, %.1f s, %d run(s)\n%-12s %4s %8s %10s %16s %10s %8s %8s %7s\n",
              duration, runs, "scene", "run", "bodies", "ms/step", "real-time factor", "impacts", "crossed", "in fixed", "waited");
  for (const std::string name : {"bunnies20", "bunnies100"}) {
    const auto scene = arphys::config::load_scene(configs + "/scenes/" + name + ".yaml");
    std::vector<double> ms_per_step;
    for (int run = 0; run < runs; ++run) {
      arphys::dynamics::World world = arphys::scene::build_world(scene);
      for (int i = 0; i < world.body_count(); ++i)
        if (world.body_model(i).is_dynamic()) {
          const arphys::dynamics::BodyState& body = world.body_state(i);
          world.set_velocity(i, body.v_WBcm_m_s + Eigen::Vector3d(start_velocity_perturbation_m_s(i, run), 0, 0),
                             body.w_WB_rad_s);
        }
      const long steps = std::lround(duration / scene.time_step_s);
      long impacts = 0, done = 0, crossed = 0, in_fixed = 0, waited = 0;
      double wall = 0;  // seconds in World::step
      const auto start = Clock::now();
      // A wall-clock cap: a scene that slows to a crawl is reported, not waited for.
      while (done < steps && std::chrono::duration<double>(Clock::now() - start).count() < 120.0) {
        const auto step_start = Clock::now();
        const auto report = world.step(scene.time_step_s);
        wall += std::chrono::duration<double>(Clock::now() - step_start).count();
        impacts += report.events + report.impacts_resolved;
        waited += report.events_capped;
        const Crossings crossing = crossing_pairs(world);
        crossed += crossing.meshes;
        in_fixed += crossing.with_fixed;
        ++done;
      }
      const double simulated = done * scene.time_step_s;
      ms_per_step.push_back(1e3 * wall / done);
      std::printf("%-12s %4d %8d %10.3f %16.2f %10ld %8ld %8ld %7ld%s\n", name.c_str(), run, world.body_count(),
                  1e3 * wall / done, simulated / wall, impacts, crossed, in_fixed, waited,
                  done < steps
                      ? ("  (stopped after 120 s of wall time at t = " + std::to_string(simulated) + " s)").c_str()
                      : "");
      csv.out << name << "," << world.body_count() << "," << 1e3 * wall / done << "," << simulated / wall << ","
              << impacts << "," << simulated << "," << run << "," << crossed << "," << waited << "," << in_fixed
              << "\n";
      std::fflush(stdout);
    }
    if (runs > 1)
      std::printf("%-12s %4s %8s %10.3f %16.2f\n", name.c_str(), "mean", "", mean(ms_per_step),
                  1e3 * scene.time_step_s / mean(ms_per_step));
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys dynamics benchmark against Bullet 3.24, ODE 0.16 and MuJoCo 2.2.2 on the scenes of the dynamics issue."};
  std::vector<std::string> scenes{"stack", "push", "drop", "anchor-pile", "bunnies", "bunnies-peers"};
  std::vector<std::string> engines = all_engines();
  std::string out = ".";
  bool quick = false;
  std::vector<int> drop_counts{10, 100, 1000};
  double drop_seconds = 1.0, stack_seconds = 0;
  int bunny_runs = 0, pile_runs = 3;
  std::vector<double> stack_dts{1e-3, 1e-2};
  app.add_option("--scenes", scenes, "scenes to run")->delimiter(',');
  app.add_option("--engines", engines, "engines to run")->delimiter(',');
  app.add_option("--out", out, "directory for the CSV files");
  app.add_flag("--quick", quick, "short runs (smoke test)");
  app.add_option("--drop-counts", drop_counts, "drop scene: numbers of boxes")->delimiter(',');
  app.add_option("--drop-seconds", drop_seconds, "drop scene: simulated seconds");
  app.add_option("--stack-dts", stack_dts, "stack scene: time steps, seconds")->delimiter(',')->capture_default_str();
  app.add_option("--stack-seconds", stack_seconds, "stack scene: simulated seconds (default 60, --quick 2)");
  app.add_option("--pile-runs", pile_runs,
                 "drop scene, N = 1000: runs on arphys, arphys-10um and ODE quickstep, the first as shipped, the others with "
                 "perturbed start velocities")
      ->capture_default_str();
  app.add_option("--bunny-runs", bunny_runs,
                 "bunnies scene: runs, the first as shipped, the others with perturbed start velocities (default 3, --quick 1)");
  CLI11_PARSE(app, argc, argv);
  // (memory_policy.hpp; it holds for every engine of the run, so the run says so.)
  const bool memory_kept = arphys::dynamics::keep_freed_memory_for_reuse();
  std::printf("arphys-dyn-bench: engines %s\n", [&] {
    std::string s;
    for (const auto& e : engines) s += e + " ";
    return s;
  }().c_str());
  std::printf("allocator: freed memory %s (every engine)\n",
              memory_kept ? "kept for reuse" : "returned to the system (the C library's default)");
  try {
    for (const std::string& scene : scenes) {
      if (scene == "stack") {
        Csv csv(out + "/dyn_stack.csv", "engine,n,dt_s,toppled,topple_t_s,top_drift_mm,max_tilt_deg,ms_per_step,simulated_s");
        run_stack(engines, stack_seconds > 0 ? stack_seconds : (quick ? 2.0 : 60.0), stack_dts, csv);
      } else if (scene == "push") {
        Csv csv(out + "/dyn_push.csv", "engine,dt_s,noise_m,peak_speed_ratio,max_overlap_mm,ms_per_step,filtered,peak_t_s");
        run_push(engines, csv);
      } else if (scene == "drop") {
        Csv csv(out + "/dyn_drop.csv", "engine,n,mu,median_ms_per_step,max_penetration_mm,final_penetration_mm,simulated_s,max_box_overlap_mm,mean_ms_per_step");
        run_drop(engines, quick ? std::vector<int>{10, 100} : drop_counts, quick ? 0.3 : drop_seconds, pile_runs, csv,
                 out + "/dyn_drop_pile_runs.csv");
      } else if (scene == "anchor-pile") {
        if (quick) continue;  // minutes: the frictionless pile runs to the wall-clock cap
        Csv csv(out + "/dyn_anchor_pile.csv", "engine,mu,mean_ms_per_step,median_ms_per_step,max_penetration_mm,max_box_overlap_mm,simulated_s");
        run_anchor_pile(engines, csv);
      } else if (scene == "bunnies") {
        Csv csv(out + "/dyn_bunnies.csv", "scene,bodies,ms_per_step,real_time_factor,impacts,simulated_s,run,crossed_pair_steps,waited_steps,in_fixed_pair_steps");
        run_bunnies(ARPHYS_SOURCE_DIR "/configs", quick ? 0.5 : 3.0, bunny_runs > 0 ? bunny_runs : (quick ? 1 : 3), csv);
      } else if (scene == "bunnies-peers") {
        Csv csv(out + "/dyn_bunnies_peers.csv", "scene,engine,ms_per_step,real_time_factor,deepest_overlap_mm,simulated_s");
        run_bunnies_peers(ARPHYS_SOURCE_DIR "/configs", quick ? 0.3 : 3.0, csv.out);
      } else {
        std::fprintf(stderr, "unknown scene '%s'\n", scene.c_str());
        return 2;
      }
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "arphys-dyn-bench: %s\n", error.what());
    return 1;
  }
  return 0;
}
