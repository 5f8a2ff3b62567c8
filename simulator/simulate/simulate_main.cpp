// simulate SCENE --duration S [--dt S] --csv OUT: runs a scene headless, without LCM,
// and writes one CSV row per body per step:
//   t,id,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz
// (SI units, world frame; p and v of the body frame's origin). Kinematic bodies follow
// their scripted trajectories. A summary (timing, events, penetration) goes to stderr.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include "configs/loader/config_error.hpp"
#include "configs/loader/scene_config.hpp"
#include "simulator/dynamics/memory_policy.hpp"
#include "simulator/scene/scene_world.hpp"

namespace {

using namespace arphys;

void write_rows(std::ostream& out, const dynamics::World& world) {
  char row[512];
  for (int i = 0; i < world.body_count(); ++i) {
    const dynamics::BodyModel& body = world.body_model(i);
    const dynamics::BodyState& now = world.body_state(i);
    const Eigen::Vector3d p = now.X_WB.translation();
    const Eigen::Quaterniond q(now.X_WB.linear());
    const Eigen::Vector3d v = dynamics::origin_velocity(body, now);
    const Eigen::Vector3d& w = now.w_WB_rad_s;
    std::snprintf(row, sizeof row, "%.6f,%s,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g\n",
                  world.time_s(), body.id.c_str(), p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z(), v.x(), v.y(), v.z(),
                  w.x(), w.y(), w.z());
    out << row;
  }
}

// What a run's steps reported, summed, and the time spent in World::step alone (the CSV's
// formatting is the tool's, not the step's).
struct RunTotals {
  long steps = 0, resolves = 0, lifts = 0, cuts = 0, capped = 0, infeasible = 0, launches = 0, held = 0, iterative = 0;
  double stepping_s = 0, deepest = 0, worst_kkt = 0;

  void add(const dynamics::StepReport& report, double step_s) {
    ++steps;
    stepping_s += step_s;
    resolves += report.impacts_resolved - report.projections;
    lifts += report.projections;
    cuts += report.events;
    capped += report.events_capped;
    infeasible += report.infeasible;
    launches += report.launches_prevented;
    held += report.non_finite_held;
    iterative += report.iterative_islands;
    deepest = std::max(deepest, report.max_penetration_m);
    worst_kkt = std::max(worst_kkt, report.kkt_residual_m_s);
  }
};

// One row of --step-times: the step's time and what it had to resolve.
void write_step_time(std::ostream& out, double t_s, const dynamics::StepReport& report, double step_s) {
  out << t_s << ',' << 1e3 * step_s << ',' << report.impacts_resolved - report.projections << ',' << report.projections
      << ',' << report.events << ',' << report.contacts << ',' << report.max_penetration_m << '\n';
}

void print_summary(const std::string& scene, const dynamics::World& world, double dt_s, double duration_s, int threads,
                   const RunTotals& t, double wall_s) {
  std::fprintf(stderr,
               "\r[simulate] %s: %ld steps of %.4g s, %d bodies, %d thread%s; %.3f ms per step (real-time factor %.2f; "
               "%.2f s in all with the CSV); %ld re-solves (CCD meetings and end checks), %ld lifts of resting points "
               "left too deep, %ld cuts at a time of impact, %ld capped steps, %ld squeezed steps, %ld launches "
               "prevented, %ld bodies held after a numerical failure, %ld island solves too large for the exact "
               "solver; deepest overlap %.3g m; worst KKT residual %.3g m/s\n",
               scene.c_str(), t.steps, dt_s, world.body_count(), threads, threads == 1 ? "" : "s",
               1e3 * t.stepping_s / std::max(1L, t.steps), duration_s / std::max(t.stepping_s, 1e-9), wall_s,
               t.resolves, t.lifts, t.cuts, t.capped, t.infeasible, t.launches, t.held, t.iterative, t.deepest,
               t.worst_kkt);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Run an arphys scene headless (no LCM) and write every body's state per step as CSV:\n"
               "t,id,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz (SI units, world frame, body origin)."};
  std::string scene_path, csv_path;
  double duration_s = 0, dt_s = 0;
  std::string solver, step_times_path;
  int threads = 1;
  app.add_option("SCENE", scene_path, "scene YAML file")->required()->check(CLI::ExistingFile);
  app.add_option("--duration", duration_s, "simulated time, seconds")->required()->check(CLI::PositiveNumber);
  app.add_option("--dt", dt_s, "time step, seconds (default: the scene's physics.time_step_s)")->check(CLI::PositiveNumber);
  app.add_option("--csv", csv_path, "output CSV file ('-' for standard output)")->required();
  app.add_option("--solver", solver, "override the scene's contact solver")->check(CLI::IsMember({"exact", "iterative"}));
  app.add_option("--threads", threads, "worker threads of the step's collision queries (the CSV is the same for any)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  app.add_option("--step-times", step_times_path,
                 "also write t_s,step_ms,resolves,lifts,cuts,contacts,deepest_overlap_m per step to this CSV (where a "
                 "run spends its time)");
  CLI11_PARSE(app, argc, argv);
  dynamics::keep_freed_memory_for_reuse();  // (memory_policy.hpp)

  config::SceneConfig scene;
  try {
    scene = config::load_scene(scene_path);
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "simulate: %s\n", e.what());
    return 2;
  }
  if (!solver.empty()) scene.solver = solver;
  if (dt_s == 0) dt_s = scene.time_step_s;
  dynamics::World world;
  try {
    world = arphys::scene::build_world(scene, threads);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "simulate: %s: %s\n", scene_path.c_str(), e.what());
    return 2;
  }
  std::ofstream file;
  if (csv_path != "-") {
    file.open(csv_path);
    if (!file) {
      std::fprintf(stderr, "simulate: cannot write %s\n", csv_path.c_str());
      return 2;
    }
  }
  std::ostream& out = csv_path == "-" ? std::cout : file;
  out << "t,id,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";
  std::ofstream step_times;
  if (!step_times_path.empty()) {
    step_times.open(step_times_path);
    if (!step_times) {
      std::fprintf(stderr, "simulate: cannot write %s\n", step_times_path.c_str());
      return 2;
    }
    step_times << "t_s,step_ms,resolves,lifts,cuts,contacts,deepest_overlap_m\n";
  }
  write_rows(out, world);

  const long steps = std::lround(duration_s / dt_s);
  RunTotals totals;
  const auto start = std::chrono::steady_clock::now();
  auto last_progress = start;
  for (long k = 0; k < steps; ++k) {
    const auto step_start = std::chrono::steady_clock::now();
    const dynamics::StepReport report = world.step(dt_s);
    const double step_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - step_start).count();
    totals.add(report, step_s);
    if (step_times.is_open()) write_step_time(step_times, world.time_s(), report, step_s);
    write_rows(out, world);
    const auto now = std::chrono::steady_clock::now();
    if (now - last_progress > std::chrono::seconds(2)) {
      std::fprintf(stderr, "\r[simulate] %s: t = %.3f / %.3f s", scene.name.c_str(), world.time_s(), duration_s);
      last_progress = now;
    }
  }
  print_summary(scene.name, world, dt_s, duration_s, threads, totals,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}
