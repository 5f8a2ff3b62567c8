// arphys-ccd-bench: speed and accuracy of arphys's continuous collision detection
// against discrete sampling and FCL's continuous collision, on the same motions.
//
//   sweep       random screw motions of mesh B against a static mesh A, judged by a
//               dense-sampling ground truth built on FCL's discrete test (default)
//   tunnelling  a small body flying through a thin plate at growing speed: the
//               missed-collision rate of each method
//
// Every method runs on every query in turn (interleaved, the first one rotating), so
// slow drifts of a shared machine and cold caches hit them alike; compare the ratios.
// Writes CSV and prints a summary.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "tools/ccd_bench/fcl_reference.hpp"

namespace {

using namespace arphys;
using geometry::Pose;
using geometry::ScrewMotion;

struct Outcome {
  bool hit;
  double toi;
};

struct Method {
  std::string name;
  std::function<Outcome(const ScrewMotion&, const ScrewMotion&)> run;
};

struct Bodies {
  geometry::TriangleMesh mesh_a, mesh_b;
  std::unique_ptr<collision::CollisionMesh> ours_a, ours_b;
  std::unique_ptr<ccd_reference::FclMesh> fcl_a, fcl_b;
  void build() {
    ours_a = std::make_unique<collision::CollisionMesh>(mesh_a);
    ours_b = std::make_unique<collision::CollisionMesh>(mesh_b);
    fcl_a = std::make_unique<ccd_reference::FclMesh>(mesh_a);
    fcl_b = std::make_unique<ccd_reference::FclMesh>(mesh_b);
  }
};

Eigen::Quaterniond uniform_rotation(std::mt19937_64& rng) {
  // Shoemake's uniform random unit quaternion.
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double u1 = u(rng), u2 = 2 * M_PI * u(rng), u3 = 2 * M_PI * u(rng);
  return Eigen::Quaterniond(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2),
                            std::sqrt(1 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
}

Eigen::Vector3d uniform_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
}

void transform(geometry::TriangleMesh& mesh, const Eigen::Vector3d& centre, double scale) {
  for (auto& v : mesh.vertices_m) v = (v - centre) * scale;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))];
}

template <typename F>
double time_us(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
}

std::string machine_line() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  int cpus = 0;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0 && model == "unknown CPU") model = line.substr(line.find(':') + 2);
    if (line.rfind("processor", 0) == 0) ++cpus;
  }
  char date[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  return std::string(date) + ", " + model + ", " + std::to_string(cpus) + " CPUs";
}

// The methods compared, on meshes A and B.
std::vector<Method> make_methods(const Bodies& bodies, bool with_fcl, bool with_fcl_rss) {
  std::vector<Method> methods;
  for (double tolerance : {1e-9, 1e-6, 1e-3}) {
    collision::ContinuousOptions options;
    options.time_tolerance = tolerance;
    char name[64];
    std::snprintf(name, sizeof name, tolerance == 1e-9 ? "arphys-ccd" : "arphys-ccd-tol%.0e", tolerance);
    methods.push_back({name, [&bodies, options](const ScrewMotion& a, const ScrewMotion& b) {
                         const auto r = collision::time_of_impact(*bodies.ours_a, a, *bodies.ours_b, b, options);
                         return Outcome{r.collides, r.time_of_impact};
                       }});
  }
  for (int n : {10, 100, 1000}) {
    methods.push_back({"discrete-" + std::to_string(n), [&bodies, n](const ScrewMotion& a, const ScrewMotion& b) {
                         for (int k = 0; k <= n; ++k) {
                           const double t = static_cast<double>(k) / n;
                           if (collision::intersects(*bodies.ours_a, a.pose_at(t), *bodies.ours_b, b.pose_at(t)))
                             return Outcome{true, t};
                         }
                         return Outcome{false, 1.0};
                       }});
  }
  if (!with_fcl) return methods;
  for (int n : {10, 100}) {
    methods.push_back({"fcl-naive-" + std::to_string(n), [&bodies, n](const ScrewMotion& a, const ScrewMotion& b) {
                         const auto r = ccd_reference::fcl_naive(*bodies.fcl_a, a, *bodies.fcl_b, b, n);
                         return Outcome{r.hit, r.toi};
                       }});
  }
  methods.push_back({"fcl-ca-obbrss", [&bodies](const ScrewMotion& a, const ScrewMotion& b) {
                       const auto r = ccd_reference::fcl_conservative_advancement(
                           *bodies.fcl_a, a, *bodies.fcl_b, b, ccd_reference::FclBoundingVolume::kObbRss);
                       return Outcome{r.hit, r.toi};
                     }});
  if (with_fcl_rss) {
    methods.push_back({"fcl-ca-rss", [&bodies](const ScrewMotion& a, const ScrewMotion& b) {
                         const auto r = ccd_reference::fcl_conservative_advancement(
                             *bodies.fcl_a, a, *bodies.fcl_b, b, ccd_reference::FclBoundingVolume::kRss);
                         return Outcome{r.hit, r.toi};
                       }});
  }
  return methods;
}

struct SweepOptions {
  int queries = 1000, truth_samples = 2000;
  unsigned seed = 1;
  double extent = 0.9, max_rotation_deg = 90;
  std::string csv_path, summary_path, label;
};

// Motions: A still at the identity; B between two collision-free poses. `draws`: how many
// pose pairs were drawn to find them.
std::vector<ScrewMotion> draw_motions(const Bodies& bodies, const SweepOptions& opt, long& draws) {
  std::mt19937_64 rng(opt.seed);
  std::uniform_real_distribution<double> position(-opt.extent, opt.extent), unit(0.0, 1.0);
  std::vector<ScrewMotion> motions;
  const Pose identity = Pose::Identity();
  draws = 0;
  while (static_cast<int>(motions.size()) < opt.queries) {
    ++draws;
    Pose X0 = Pose::Identity(), X1 = Pose::Identity();
    const Eigen::Quaterniond q0 = uniform_rotation(rng);
    const Eigen::Quaterniond q1 =
        Eigen::Quaterniond(Eigen::AngleAxisd(unit(rng) * opt.max_rotation_deg * M_PI / 180, uniform_direction(rng))) * q0;
    X0.linear() = q0.toRotationMatrix();
    X1.linear() = q1.normalized().toRotationMatrix();
    X0.translation() = Eigen::Vector3d(position(rng), position(rng), position(rng));
    X1.translation() = Eigen::Vector3d(position(rng), position(rng), position(rng));
    if (ccd_reference::fcl_intersects(*bodies.fcl_a, identity, *bodies.fcl_b, X0) ||
        ccd_reference::fcl_intersects(*bodies.fcl_a, identity, *bodies.fcl_b, X1))
      continue;
    motions.emplace_back(X0, X1);
  }
  return motions;
}

// One method's answers against the truth.
struct Tally {
  long hits = 0, misses = 0, late = 0, false_positives = 0, verified_grazing = 0;
  double max_late = 0;
  std::vector<double> abs_errors, micros;
  // Scores one answer; returns its error (0 unless both hit).
  double score(const Outcome& out, const ccd_reference::ReferenceToi& truth, const Bodies& bodies,
               const ScrewMotion& motion) {
    double error = 0;
    if (out.hit) ++hits;
    if (truth.hit && !out.hit) {
      ++misses;
    } else if (!truth.hit && out.hit) {
      // The sampled truth can step over a grazing touch: check the surfaces really meet.
      const auto sep =
          collision::separation(*bodies.ours_a, Pose::Identity(), *bodies.ours_b, motion.pose_at(out.toi), 1e-3);
      ++(sep.distance_m <= 1e-6 ? verified_grazing : false_positives);
    } else if (truth.hit && out.hit) {
      // Late: after the first sample found intersecting; error: from the last free one.
      error = out.toi - truth.toi_lo;
      if (out.toi > truth.toi) {
        ++late;
        max_late = std::max(max_late, out.toi - truth.toi);
      }
      abs_errors.push_back(std::abs(error));
    }
    return error;
  }
};

// The summary table, printed and written to opt.summary_path.
void write_summary(const std::vector<Method>& methods, std::map<std::string, Tally>& tally, const SweepOptions& opt,
                   long draws, long true_hits, const std::vector<double>& truth_micros) {
  const double ours_median = median(tally["arphys-ccd"].micros);
  std::ofstream summary(opt.summary_path);
  summary << "# " << opt.label << "; " << opt.queries << " motions (" << draws << " draws), seed " << opt.seed << ", "
          << true_hits << " true hits, truth " << opt.truth_samples << " samples + bisection; " << machine_line()
          << "\n";
  summary << "method,queries,true_hits,hits,misses,late,max_late,false_positives,verified_grazing,max_abs_toi_error,"
             "p95_abs_toi_error,median_us,ratio_to_arphys\n";
  std::printf("%s: %d motions (%ld draws), seed %u; %ld true hits; truth median %.0f us\n%s\n", opt.label.c_str(),
              opt.queries, draws, opt.seed, true_hits, median(truth_micros), machine_line().c_str());
  std::printf("%-20s %6s %6s %6s %10s %6s %8s %10s %10s %11s %9s\n", "method", "hits", "missed", "late", "max_late",
              "FP", "grazing", "max|err|", "p95|err|", "median_us", "x arphys");
  for (const Method& method : methods) {
    const Tally& t = tally[method.name];
    const double med = median(t.micros);
    const double max_err = t.abs_errors.empty() ? 0 : *std::max_element(t.abs_errors.begin(), t.abs_errors.end());
    const double p95 = percentile(t.abs_errors, 0.95);
    std::printf("%-20s %6ld %6ld %6ld %10.2e %6ld %8ld %10.2e %10.2e %11.1f %9.2f\n", method.name.c_str(), t.hits,
                t.misses, t.late, t.max_late, t.false_positives, t.verified_grazing, max_err, p95, med,
                med / ours_median);
    char row[512];
    std::snprintf(row, sizeof row, "%s,%d,%ld,%ld,%ld,%ld,%.3e,%ld,%ld,%.3e,%.3e,%.2f,%.3f\n", method.name.c_str(),
                  opt.queries, true_hits, t.hits, t.misses, t.late, t.max_late, t.false_positives, t.verified_grazing,
                  max_err, p95, med, med / ours_median);
    summary << row;
  }
}

int run_sweep(const Bodies& bodies, const std::vector<Method>& methods, const SweepOptions& opt) {
  long draws = 0;
  const std::vector<ScrewMotion> motions = draw_motions(bodies, opt, draws);
  const ScrewMotion still(Pose::Identity(), Pose::Identity());
  std::ofstream csv(opt.csv_path);
  csv << "# " << opt.label << "; " << machine_line() << "\n";
  csv << "query,method,hit,toi,truth_hit,truth_toi,error,micros\n";
  std::map<std::string, Tally> tally;
  long true_hits = 0;
  std::vector<double> truth_micros;
  for (int q = 0; q < opt.queries; ++q) {
    const ScrewMotion& motion = motions[q];
    ccd_reference::ReferenceToi truth;
    truth_micros.push_back(time_us([&] {
      truth = ccd_reference::sampled_truth(*bodies.fcl_a, still, *bodies.fcl_b, motion, opt.truth_samples);
    }));
    true_hits += truth.hit;
    // Rotate which method goes first: the first one after the truth (and after the
    // previous query's slowest method) runs with cold caches.
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const Method& method = methods[(q + m) % methods.size()];
      Outcome out{};
      const double us = time_us([&] { out = method.run(still, motion); });
      Tally& t = tally[method.name];
      t.micros.push_back(us);
      const double error = t.score(out, truth, bodies, motion);
      char row[256];
      std::snprintf(row, sizeof row, "%d,%s,%d,%.12f,%d,%.12f,%.3e,%.2f\n", q, method.name.c_str(), out.hit, out.toi,
                    truth.hit, truth.toi, error, us);
      csv << row;
    }
    if ((q + 1) % 20 == 0 || q + 1 == opt.queries)
      std::fprintf(stderr, "\r[ccd-bench] %s: %d/%d queries, %ld true hits", opt.label.c_str(), q + 1, opt.queries,
                   true_hits);
  }
  std::fprintf(stderr, "\n");
  write_summary(methods, tally, opt, draws, true_hits, truth_micros);
  return 0;
}

// A cube of side `size` flies straight through a plate of the same thickness along
// -z, travelling `ratio` times (plate thickness + cube side) per step, with a random
// lateral offset and orientation, spinning 5 degrees about its flight line: every
// flight crosses the plate, so any "no hit" is a missed collision.
int run_tunnelling(const std::vector<Method>& methods, int flights, unsigned seed, const std::string& csv_path) {
  std::ofstream csv(csv_path);
  csv << "# tunnelling: cube of side 0.01 through a 1 x 1 x 0.01 plate; " << machine_line() << "\n";
  csv << "travel_over_thickness,method,miss_rate,median_us\n";
  const Pose identity = Pose::Identity();
  const ScrewMotion still(identity, identity);
  std::printf("%-22s", "travel/thickness");
  for (const auto& m : methods) std::printf(" %14s", m.name.c_str());
  std::printf("\n");
  for (double ratio : {0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0}) {
    const double travel = ratio * 0.02;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> lateral(-0.4, 0.4), phase(0.0, 1.0);
    std::map<std::string, std::pair<long, std::vector<double>>> result;
    for (int f = 0; f < flights; ++f) {
      Pose X0 = Pose::Identity(), X1 = Pose::Identity();
      X0.linear() = uniform_rotation(rng).toRotationMatrix();
      // A 5 degree spin about the flight line: FCL's ScrewMotion mis-scales pure
      // translations (docs/ccd.md), and the spin leaves the crossing unchanged.
      X1.linear() = Eigen::AngleAxisd(5 * M_PI / 180, Eigen::Vector3d::UnitZ()) * X0.linear();
      // The crossing happens at a random phase of the step, so sampling has no lucky alignment.
      const double start = travel * (0.25 + 0.5 * phase(rng)) + 0.0201;
      const double x = lateral(rng), y = lateral(rng);
      X0.translation() = Eigen::Vector3d(x, y, start);
      X1.translation() = Eigen::Vector3d(x, y, start - travel - 0.0402);
      const ScrewMotion motion(X0, X1);
      for (const Method& m : methods) {
        Outcome out{};
        const double us = time_us([&] { out = m.run(still, motion); });
        auto& r = result[m.name];
        r.first += !out.hit;
        r.second.push_back(us);
      }
    }
    std::printf("%-22g", ratio);
    for (const Method& m : methods) {
      const auto& r = result[m.name];
      const double miss_rate = static_cast<double>(r.first) / flights;
      std::printf(" %14.3f", miss_rate);
      csv << ratio << "," << m.name << "," << miss_rate << "," << median(r.second) << "\n";
    }
    std::printf("\n");
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys CCD benchmark: arphys CCD vs discrete sampling vs FCL continuousCollide.\n"
               "  sweep (default): random screw motions of mesh B against a still mesh A, judged by dense sampling\n"
               "  tunnelling: missed-collision rate of a small cube flying through a thin plate at growing speed"};
  std::string mode = "sweep";
  std::string mesh_a_path = std::string(ARPHYS_SOURCE_DIR) + "/configs/models/stanford-bunny-5k.obj";
  std::string mesh_b_path;
  std::vector<double> box_b;
  SweepOptions sweep;
  sweep.csv_path = "ccd_sweep.csv";
  sweep.summary_path = "ccd_sweep_summary.csv";
  bool with_fcl = true, with_fcl_rss = true, recentre = true, common_scale = false;
  int flights = 200;
  app.add_option("mode", mode, "sweep or tunnelling")->check(CLI::IsMember({"sweep", "tunnelling"}));
  app.add_option("--mesh-a", mesh_a_path, "still mesh, scaled to a bounding-box diagonal of 1");
  app.add_option("--mesh-b", mesh_b_path, "moving mesh (default: the same as --mesh-a)");
  app.add_option("--box-b", box_b, "moving body is a box with these side lengths (units of A's diagonal)")
      ->expected(3);
  app.add_flag("--common-scale", common_scale, "scale B by A's factor (keeps a spoon and its cup in proportion)");
  app.add_option("--queries", sweep.queries, "number of random motions")->check(CLI::PositiveNumber);
  app.add_option("--seed", sweep.seed, "random seed");
  app.add_option("--truth-samples", sweep.truth_samples, "uniform samples of the ground truth before bisection");
  app.add_option("--extent", sweep.extent, "start/end positions uniform in [-extent, extent]^3 (units of the diagonal)");
  app.add_option("--max-rotation-deg", sweep.max_rotation_deg, "largest rotation between start and end, degrees");
  app.add_option("--csv", sweep.csv_path, "per-query CSV output (tunnelling: the rates)");
  app.add_option("--summary", sweep.summary_path, "summary CSV output");
  app.add_option("--label", sweep.label, "scene label written into the CSV files");
  app.add_option("--flights", flights, "tunnelling: flights per speed");
  app.add_flag("!--no-fcl", with_fcl, "skip FCL");
  app.add_flag("!--no-fcl-rss", with_fcl_rss, "skip FCL's conservative advancement on RSS (about 20 ms per query)");
  app.add_flag("!--no-recentre", recentre, "keep the meshes' own origins (default: bounding-box centre at the origin)");
  CLI11_PARSE(app, argc, argv);

  Bodies bodies;
  if (mode == "tunnelling") {
    bodies.mesh_a = geometry::make_box_mesh({1, 1, 0.01});
    bodies.mesh_b = geometry::make_box_mesh({0.01, 0.01, 0.01});
    bodies.build();
    return run_tunnelling(make_methods(bodies, with_fcl, false), flights, sweep.seed, sweep.csv_path);
  }
  if (mesh_b_path.empty()) mesh_b_path = mesh_a_path;
  bodies.mesh_a = geometry::load_mesh(mesh_a_path);
  const double scale_a = 1.0 / bodies.mesh_a.bounds().diagonal().norm();
  transform(bodies.mesh_a, recentre ? Eigen::Vector3d(bodies.mesh_a.bounds().center()) : Eigen::Vector3d::Zero(), scale_a);
  if (!box_b.empty()) {
    bodies.mesh_b = geometry::make_box_mesh({box_b[0], box_b[1], box_b[2]});
  } else {
    bodies.mesh_b = geometry::load_mesh(mesh_b_path);
    const double scale_b = common_scale ? scale_a : 1.0 / bodies.mesh_b.bounds().diagonal().norm();
    transform(bodies.mesh_b, recentre ? Eigen::Vector3d(bodies.mesh_b.bounds().center()) : Eigen::Vector3d::Zero(),
              scale_b);
  }
  bodies.build();
  if (sweep.label.empty()) {
    std::ostringstream label;
    label << bodies.mesh_a.num_triangles() << " vs " << bodies.mesh_b.num_triangles() << " triangles";
    sweep.label = label.str();
  }
  return run_sweep(bodies, make_methods(bodies, with_fcl, with_fcl_rss), sweep);
}
