// arphys-ccd-bench: speed and accuracy of arphys's continuous collision detection
// against discrete sampling and FCL's continuous collision, on the same random
// screw motions, judged by a dense-sampling ground truth built on FCL's discrete test.
// Writes one CSV row per (query, method) and a summary CSV; prints the summary.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <random>
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

Eigen::Quaterniond uniform_rotation(std::mt19937_64& rng) {
  // Shoemake's uniform random unit quaternion.
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double u1 = u(rng), u2 = 2 * M_PI * u(rng), u3 = 2 * M_PI * u(rng);
  return Eigen::Quaterniond(std::sqrt(u1) * std::cos(u3), std::sqrt(1 - u1) * std::sin(u2),
                            std::sqrt(1 - u1) * std::cos(u2), std::sqrt(u1) * std::sin(u3));
}

Eigen::Vector3d uniform_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Vector3d v(n(rng), n(rng), n(rng));
  return v.normalized();
}

geometry::TriangleMesh scaled_to_unit_diagonal(geometry::TriangleMesh mesh, bool recentre) {
  const double diagonal = mesh.bounds().diagonal().norm();
  const Eigen::Vector3d centre = recentre ? Eigen::Vector3d(mesh.bounds().center()) : Eigen::Vector3d::Zero();
  for (auto& v : mesh.vertices_m) v = (v - centre) / diagonal;
  return mesh;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"arphys CCD benchmark: random screw motions of a mesh against a static copy (or another mesh),\n"
               "arphys CCD vs discrete sampling vs FCL continuousCollide, judged by a dense-sampling ground truth."};
  std::string mesh_a_path = std::string(ARPHYS_SOURCE_DIR) + "/configs/models/stanford-bunny-5k.obj";
  std::string mesh_b_path;
  int queries = 1000, truth_samples = 2000;
  unsigned seed = 1;
  double extent = 0.9, max_rotation_deg = 90;
  std::string csv_path = "ccd_sweep.csv", summary_path = "ccd_sweep_summary.csv";
  bool with_fcl = true, with_fcl_rss = true, recentre = true;
  app.add_option("--mesh-a", mesh_a_path, "static mesh (scaled to a bounding-box diagonal of 1)");
  app.add_option("--mesh-b", mesh_b_path, "moving mesh (default: the same as --mesh-a)");
  app.add_option("--queries", queries, "number of random motions")->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "random seed");
  app.add_option("--truth-samples", truth_samples, "uniform samples of the ground truth before bisection");
  app.add_option("--extent", extent, "start/end positions uniform in [-extent, extent]^3 (units of the diagonal)");
  app.add_option("--max-rotation-deg", max_rotation_deg, "largest rotation between start and end");
  app.add_option("--csv", csv_path, "per-query CSV output");
  app.add_option("--summary", summary_path, "summary CSV output");
  app.add_flag("!--no-fcl", with_fcl, "skip FCL's continuousCollide");
  app.add_flag("!--no-fcl-rss", with_fcl_rss, "skip FCL's conservative advancement on RSS (about 20 ms per query)");
  app.add_flag("!--no-recentre", recentre, "keep the meshes' own origins (default: bounding-box centre at the origin)");
  CLI11_PARSE(app, argc, argv);
  if (mesh_b_path.empty()) mesh_b_path = mesh_a_path;

  const geometry::TriangleMesh mesh_a = scaled_to_unit_diagonal(geometry::load_mesh(mesh_a_path), recentre);
  const geometry::TriangleMesh mesh_b = scaled_to_unit_diagonal(geometry::load_mesh(mesh_b_path), recentre);
  const collision::CollisionMesh ours_a(mesh_a), ours_b(mesh_b);
  const ccd_reference::FclMesh fcl_a(mesh_a), fcl_b(mesh_b);

  // Motions: A static at the identity; B between two collision-free poses.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> position(-extent, extent), unit(0.0, 1.0);
  std::vector<std::pair<ScrewMotion, ScrewMotion>> motions;
  const Pose identity = Pose::Identity();
  long draws = 0;
  while (static_cast<int>(motions.size()) < queries) {
    ++draws;
    Pose X0 = Pose::Identity(), X1 = Pose::Identity();
    const Eigen::Quaterniond q0 = uniform_rotation(rng);
    const Eigen::Quaterniond q1 =
        Eigen::Quaterniond(Eigen::AngleAxisd(unit(rng) * max_rotation_deg * M_PI / 180, uniform_direction(rng))) * q0;
    X0.linear() = q0.toRotationMatrix();
    X1.linear() = q1.normalized().toRotationMatrix();
    X0.translation() = Eigen::Vector3d(position(rng), position(rng), position(rng));
    X1.translation() = Eigen::Vector3d(position(rng), position(rng), position(rng));
    if (ccd_reference::fcl_intersects(fcl_a, identity, fcl_b, X0) ||
        ccd_reference::fcl_intersects(fcl_a, identity, fcl_b, X1))
      continue;
    motions.emplace_back(ScrewMotion(identity, identity), ScrewMotion(X0, X1));
  }

  collision::ContinuousOptions options_1e9, options_1e6;
  options_1e6.time_tolerance = 1e-6;
  std::vector<Method> methods = {
      {"arphys-ccd", [&](const ScrewMotion& a, const ScrewMotion& b) {
         const auto r = collision::time_of_impact(ours_a, a, ours_b, b, options_1e9);
         return Outcome{r.collides, r.time_of_impact};
       }},
      {"arphys-ccd-tol1e-6", [&](const ScrewMotion& a, const ScrewMotion& b) {
         const auto r = collision::time_of_impact(ours_a, a, ours_b, b, options_1e6);
         return Outcome{r.collides, r.time_of_impact};
       }},
  };
  for (int n : {10, 100, 1000}) {
    methods.push_back({"discrete-" + std::to_string(n), [&, n](const ScrewMotion& a, const ScrewMotion& b) {
                         for (int k = 0; k <= n; ++k) {
                           const double t = static_cast<double>(k) / n;
                           if (collision::intersects(ours_a, a.pose_at(t), ours_b, b.pose_at(t))) return Outcome{true, t};
                         }
                         return Outcome{false, 1.0};
                       }});
  }
  if (with_fcl) {
    for (int n : {10, 100}) {
      methods.push_back({"fcl-naive-" + std::to_string(n), [&, n](const ScrewMotion& a, const ScrewMotion& b) {
                           const auto r = ccd_reference::fcl_naive(fcl_a, a, fcl_b, b, n);
                           return Outcome{r.hit, r.toi};
                         }});
    }
    methods.push_back({"fcl-ca-obbrss", [&](const ScrewMotion& a, const ScrewMotion& b) {
                         const auto r = ccd_reference::fcl_conservative_advancement(
                             fcl_a, a, fcl_b, b, ccd_reference::FclBoundingVolume::kObbRss);
                         return Outcome{r.hit, r.toi};
                       }});
    if (with_fcl_rss) {
      methods.push_back({"fcl-ca-rss", [&](const ScrewMotion& a, const ScrewMotion& b) {
                           const auto r = ccd_reference::fcl_conservative_advancement(
                               fcl_a, a, fcl_b, b, ccd_reference::FclBoundingVolume::kRss);
                           return Outcome{r.hit, r.toi};
                         }});
    }
  }

  std::ofstream csv(csv_path);
  csv << "query,method,hit,toi,truth_hit,truth_toi,error,micros\n";
  struct Tally {
    long hits = 0, misses = 0, late = 0, false_positives = 0, verified_grazing = 0;
    double max_late = 0, max_abs_error = 0;
    std::vector<double> micros;
  };
  std::map<std::string, Tally> tally;
  long true_hits = 0;
  std::vector<double> truth_micros;
  for (int q = 0; q < queries; ++q) {
    const auto& [motion_a, motion_b] = motions[q];
    const auto t0 = std::chrono::steady_clock::now();
    const auto truth = ccd_reference::sampled_truth(fcl_a, motion_a, fcl_b, motion_b, truth_samples);
    truth_micros.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    true_hits += truth.hit;
    for (const Method& method : methods) {
      const auto start = std::chrono::steady_clock::now();
      const Outcome out = method.run(motion_a, motion_b);
      const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
      Tally& t = tally[method.name];
      t.micros.push_back(us);
      double error = 0;
      if (out.hit) ++t.hits;
      if (truth.hit && !out.hit) {
        ++t.misses;
      } else if (!truth.hit && out.hit) {
        // The sampled truth can step over a grazing touch: check the surfaces really meet.
        const auto sep = collision::separation(ours_a, motion_a.pose_at(out.toi), ours_b, motion_b.pose_at(out.toi), 1e-3);
        if (sep.distance_m <= 1e-6) {
          ++t.verified_grazing;
        } else {
          ++t.false_positives;
        }
      } else if (truth.hit && out.hit) {
        error = out.toi - truth.toi_lo;
        if (out.toi > truth.toi) {
          ++t.late;
          t.max_late = std::max(t.max_late, out.toi - truth.toi);
        }
        t.max_abs_error = std::max(t.max_abs_error, std::abs(error));
      }
      char row[256];
      std::snprintf(row, sizeof row, "%d,%s,%d,%.12f,%d,%.12f,%.3e,%.2f\n", q, method.name.c_str(), out.hit, out.toi,
                    truth.hit, truth.toi, error, us);
      csv << row;
    }
    if ((q + 1) % 50 == 0 || q + 1 == queries)
      std::fprintf(stderr, "\r[ccd-bench] %d/%d queries, %ld true hits", q + 1, queries, true_hits);
  }
  std::fprintf(stderr, "\n");

  const double ours_median = median(tally["arphys-ccd"].micros);
  std::ofstream summary(summary_path);
  summary << "method,queries,true_hits,hits,misses,late,max_late,false_positives,verified_grazing,max_abs_toi_error,"
             "median_us,ratio_to_arphys\n";
  std::printf("mesh A %s (%zu tris), mesh B %s (%zu tris); %d motions (%ld draws), seed %u; %ld true hits; truth "
              "median %.0f us\n",
              mesh_a_path.c_str(), mesh_a.num_triangles(), mesh_b_path.c_str(), mesh_b.num_triangles(), queries, draws,
              seed, true_hits, median(truth_micros));
  std::printf("%-20s %6s %6s %6s %10s %6s %8s %12s %11s %9s\n", "method", "hits", "missed", "late", "max_late", "FP",
              "grazing", "max|err|", "median_us", "x arphys");
  for (const Method& method : methods) {
    const Tally& t = tally[method.name];
    const double med = median(t.micros);
    std::printf("%-20s %6ld %6ld %6ld %10.2e %6ld %8ld %12.2e %11.1f %9.2f\n", method.name.c_str(), t.hits, t.misses,
                t.late, t.max_late, t.false_positives, t.verified_grazing, t.max_abs_error, med, med / ours_median);
    char row[512];
    std::snprintf(row, sizeof row, "%s,%d,%ld,%ld,%ld,%ld,%.3e,%ld,%ld,%.3e,%.2f,%.3f\n", method.name.c_str(), queries,
                  true_hits, t.hits, t.misses, t.late, t.max_late, t.false_positives, t.verified_grazing,
                  t.max_abs_error, med, med / ours_median);
    summary << row;
  }
  return 0;
}
