// The CCD of convex-piece sets against an independent truth: 1000 random screw motions
// of one bunny-as-pieces past another (every other one with both carried along together), each sampled 1000 times with
// libccd's GJK intersection test of every piece pair (and the hulls' exact triangle test), the first intersecting
// sample bisected to 1e-10. The contract of the mesh query holds for the pieces: no miss, never late, at most the
// tolerance early.
#include <ccd/ccd.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <memory>
#include <random>

#include "simulator/collision/collision_mesh.hpp"
#include "simulator/collision/convex_distance.hpp"
#include "simulator/collision/convex_manifold.hpp"
#include "simulator/collision/shape_query.hpp"
#include "tests/support/poses.hpp"

namespace arphys::collision {
namespace {

using geometry::Pose;
using geometry::ScrewMotion;
using testing::at;
using testing::random_pose;

// The shipped bunny's convex pieces at the bunny scenes' scale.
std::shared_ptr<const ConvexSet> bunny_pieces() {
  return load_convex_set(std::string(ARPHYS_SOURCE_DIR) + "/configs/models/stanford-bunny-1k-quadric.pieces.obj",
                         Eigen::Vector3d::Constant(0.8));
}

struct PlacedPiece {
  const ConvexPiece* piece;
  Pose X_WP;
};

void support(const void* object, const ccd_vec3_t* direction, ccd_vec3_t* out) {
  const auto* p = static_cast<const PlacedPiece*>(object);
  const Eigen::Vector3d d_W(direction->v[0], direction->v[1], direction->v[2]);
  const Eigen::Vector3d v = p->X_WP * p->piece->vertices_m()[p->piece->support(p->X_WP.linear().transpose() * d_W)];
  ccdVec3Set(out, v.x(), v.y(), v.z());
}

ccd_t gjk() {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = support;
  ccd.support2 = support;
  ccd.max_iterations = 1000;
  ccd.epa_tolerance = 1e-12;
  return ccd;
}

// libccd's GJK over every pair of pieces whose balls meet, and the exact triangle test of
// the hulls: libccd's GJK misses some shallow crossings of nearly parallel faces that
// the triangles show (one in these 1000 motions, 10 um deep).
bool sets_intersect(const ConvexSet& A, const Pose& X_WA, const ConvexSet& B, const Pose& X_WB) {
  if (intersects(*A.hulls, X_WA, *B.hulls, X_WB)) return true;
  ccd_t ccd = gjk();
  for (const ConvexPiece& a : A.pieces)
    for (const ConvexPiece& b : B.pieces) {
      if ((X_WA * a.centroid_m() - X_WB * b.centroid_m()).norm() > a.radius_m() + b.radius_m()) continue;
      const PlacedPiece pa{&a, X_WA}, pb{&b, X_WB};
      if (ccdGJKIntersect(&pa, &pb, &ccd)) return true;
    }
  return false;
}

// The deepest penetration of any piece pair (libccd's EPA), 0 where none overlap.
double penetration_m(const ConvexSet& A, const Pose& X_WA, const ConvexSet& B, const Pose& X_WB) {
  ccd_t ccd = gjk();
  double deepest = 0;
  for (const ConvexPiece& a : A.pieces)
    for (const ConvexPiece& b : B.pieces) {
      const PlacedPiece pa{&a, X_WA}, pb{&b, X_WB};
      ccd_real_t depth = 0;
      ccd_vec3_t direction, position;
      if (ccdGJKPenetration(&pa, &pb, &ccd, &depth, &direction, &position) == 0) deepest = std::max(deepest, depth);
    }
  return deepest;
}

struct Truth {
  bool hit = false;
  double toi = 1;
};

Truth sampled_truth(const ConvexSet& A, const ScrewMotion& motion_A, const ConvexSet& B, const ScrewMotion& motion,
                    int samples) {
  double free_t = 0;
  for (int k = 1; k <= samples; ++k) {
    const double t = static_cast<double>(k) / samples;
    if (!sets_intersect(A, motion_A.pose_at(t), B, motion.pose_at(t))) {
      free_t = t;
      continue;
    }
    double lo = free_t, hi = t;
    while (hi - lo > 1e-10) {
      const double mid = 0.5 * (lo + hi);
      (sets_intersect(A, motion_A.pose_at(mid), B, motion.pose_at(mid)) ? hi : lo) = mid;
    }
    return {true, hi};
  }
  return {};
}

struct Score {
  int hits = 0, grazing = 0, late_by_gjk = 0;
  double worst_early = 0;
};

// One motion of B (motion) against A (motion_A), both the bunny's pieces, judged against the
// sampled truth: no miss, never late (beyond libccd's own contact tolerance), at most the
// tolerance early except at a graze the samples stepped over.
void judge(const ConvexSet& set, const Shape& bunny, const ScrewMotion& motion_A, const ScrewMotion& motion,
           const ContinuousOptions& options, int tested, Score& score) {
  const ContinuousResult ours = time_of_impact(bunny, motion_A, bunny, motion, options);
  const Truth truth = sampled_truth(set, motion_A, set, motion, 1000);
  if (truth.hit) {
    ++score.hits;
    ASSERT_TRUE(ours.collides) << "motion " << tested << " missed (truth " << truth.toi << ")";
    // libccd decides contact to sqrt(DBL_EPSILON) = 1.5e-8 m: its GJK calls pieces that
    // close intersecting, so its truth can be a little early. A time of impact after
    // it is late only where the pieces overlap there by more than that (EPA's depth).
    if (ours.time_of_impact > truth.toi + 1e-9) {
      EXPECT_LT(penetration_m(set, motion_A.pose_at(ours.time_of_impact), set, motion.pose_at(ours.time_of_impact)),
                3e-8)
          << "motion " << tested << " late: " << ours.time_of_impact << " after " << truth.toi;
    }
    score.late_by_gjk += ours.time_of_impact > truth.toi + 1e-9;
    // Earlier than the tolerance only at a touch the samples stepped over (a graze
    // before the contact they found): the pieces must meet there.
    if (ours.time_of_impact < truth.toi - 1e-6 - 1e-9) {
      ++score.grazing;
      EXPECT_TRUE(sets_intersect(set, motion_A.pose_at(ours.time_of_impact + 1e-5), set,
                                 motion.pose_at(ours.time_of_impact + 1e-5)))
          << "motion " << tested << " early: " << ours.time_of_impact << " before " << truth.toi;
    } else {
      score.worst_early = std::max(score.worst_early, truth.toi - ours.time_of_impact);
    }
  } else if (ours.collides) {
    // A touch between two samples that never goes deeper: the pieces must be touching
    // at the reported time.
    ++score.grazing;
    const auto at_toi = contact_manifold(bunny, motion_A.pose_at(ours.time_of_impact), bunny,
                                         motion.pose_at(ours.time_of_impact), 1e-5);
    EXPECT_FALSE(at_toi.empty()) << "motion " << tested << ": a hit at " << ours.time_of_impact << " with nothing near";
  }
}

TEST(ConvexCcd, BunnyPiecesMatchDenseSamplingTruth) {
  const auto set = bunny_pieces();
  const Shape bunny = Shape::convex_set(set);
  std::mt19937 rng(2027);
  std::uniform_real_distribution<double> u(-0.1, 0.1), angle(0, M_PI / 2);
  std::normal_distribution<double> normal;
  ContinuousOptions options;
  options.time_tolerance = 1e-6;  // the simulator's
  int tested = 0;
  Score score;
#ifdef ARPHYS_UNDER_SANITIZERS
  const int motions = 50;  // memory and UB checks of the same paths (1000 take three minutes there)
#else
  const int motions = 1000;
#endif
  while (tested < motions) {
    Pose X0 = Pose::Identity(), X1 = Pose::Identity();
    X0.linear() = Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().toRotationMatrix();
    const Eigen::Vector3d axis = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    X1.linear() = Eigen::AngleAxisd(angle(rng), axis) * X0.linear();
    X0.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng));
    X1.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng));
    // Every other motion carries both bodies along (a pile shoved together): A drifts up to
    // 0.4 m and turns up to 0.3 rad, and B's end pose is taken along with it.
    Pose Y1 = Pose::Identity();
    if (tested % 2 == 1) {
      Y1 = geometry::rotation_pose(Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized(),
                                   0.3 * angle(rng) / (M_PI / 2));
      Y1.translation() = 2 * Eigen::Vector3d(u(rng), u(rng), u(rng));
      X1 = Y1 * X1;
    }
    const ScrewMotion motion_A(Pose::Identity(), Y1);
    if (sets_intersect(*set, Pose::Identity(), *set, X0) || sets_intersect(*set, Y1, *set, X1)) continue;
    ++tested;
    judge(*set, bunny, motion_A, ScrewMotion(X0, X1), options, tested, score);
  }
  std::printf(
      "convex CCD: %d motions, %d hits (%d after GJK's touching tolerance, none overlapping), %d grazing, "
      "worst early %.2e (tolerance 1e-6)\n",
      tested, score.hits, score.late_by_gjk, score.grazing, score.worst_early);
  EXPECT_GT(score.hits, motions * 15 / 100);
  EXPECT_LE(score.grazing, 10);
}

// Resting and sliding, where the advancement's bounds stall and its vertex-wise bound takes
// over: B set down on A to within 10-100 um (any turn of either), then slid up to 5 mm,
// rocked up to 0.4 rad about a random axis and moved up to 100 um down or 1 mm up. Half of
// these meet; the same truth and the same contract.
TEST(ConvexCcd, RestingAndSlidingPiecesMatchDenseSamplingTruth) {
  const auto set = bunny_pieces();
  const Shape bunny = Shape::convex_set(set);
  std::mt19937 rng(2028);
  std::uniform_real_distribution<double> u(-1, 1), unit(0, 1);
  std::normal_distribution<double> normal;
  ContinuousOptions options;
  options.time_tolerance = 1e-6;
#ifdef ARPHYS_UNDER_SANITIZERS
  const int motions = 30;
#else
  const int motions = 400;
#endif
  Score score;
  const ScrewMotion still(Pose::Identity(), Pose::Identity());
  for (int tested = 0; tested < motions; ++tested) {
    Pose X0 = Pose::Identity();
    X0.linear() =
        Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().toRotationMatrix();
    X0.translation() = Eigen::Vector3d(0.03 * u(rng), 0.03 * u(rng), 0.2);
    // Down until within 10-100 um of A (bisection on the height: apart by 10 um, not by 100 um).
    double apart = 0.2, touching = -0.2;
    for (int k = 0; k < 60; ++k) {
      X0.translation().z() = 0.5 * (apart + touching);
      const bool near = !convex_sets_apart_by(*set, Pose::Identity(), *set, X0, 1e-4);
      if (near && convex_sets_apart_by(*set, Pose::Identity(), *set, X0, 1e-5)) break;
      (near ? touching : apart) = X0.translation().z();
    }
    Pose X1 =
        geometry::rotation_pose(Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized(), 0.4 * unit(rng));
    X1.linear() = X1.linear() * X0.linear();
    X1.translation() = X0.translation() + Eigen::Vector3d(0.005 * u(rng), 0.005 * u(rng), -1e-4 + 1.1e-3 * unit(rng));
    judge(*set, bunny, still, ScrewMotion(X0, X1), options, tested, score);
  }
  std::printf(
      "convex CCD, resting and sliding: %d motions, %d hits (%d after GJK's touching tolerance), %d grazing, "
      "worst early %.2e (tolerance 1e-6)\n",
      motions, score.hits, score.late_by_gjk, score.grazing, score.worst_early);
  EXPECT_GT(score.hits, motions / 5);
  EXPECT_LT(score.hits, motions * 9 / 10);
  EXPECT_LE(score.grazing, motions / 20);
}

// The clearance a free answer reports is a lower bound on the sets' distance all along the
// motions (their pieces' GJK distances at 400 times of each motion never come closer), and
// asked for 2 mm beyond need, most free answers have one.
TEST(ConvexCcd, ClearanceIsNeverMoreThanTheClosestApproach) {
  const auto set = bunny_pieces();
  const Shape bunny = Shape::convex_set(set);
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(-0.1, 0.1), turn(-0.2, 0.2);
  ContinuousOptions options;
  int free = 0, with_clearance = 0;
#ifdef ARPHYS_UNDER_SANITIZERS
  const int motions = 20;
#else
  const int motions = 100;
#endif
  for (int tested = 0; tested < motions;) {
    const Pose X0 = random_pose(rng, 0.0) * at({0.12 + u(rng), u(rng), u(rng)});
    const Pose X1 = at(0.1 * Eigen::Vector3d(u(rng), u(rng), u(rng)), Eigen::Vector3d::UnitZ(), turn(rng)) * X0;
    if (sets_intersect(*set, Pose::Identity(), *set, X0)) continue;
    ++tested;
    const ScrewMotion still(Pose::Identity(), Pose::Identity()), motion(X0, X1);
    const ContinuousResult r = time_of_impact(bunny, still, bunny, motion, options);
    if (r.collides) continue;
    ++free;
    if (r.clearance_m <= 0) continue;
    ++with_clearance;
    double closest = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= 200; ++k)
      for (const ConvexPiece& a : set->pieces)
        for (const ConvexPiece& b : set->pieces)
          closest = std::min(closest, convex_distance(a, Pose::Identity(), b, motion.pose_at(k / 200.0)).upper_m);
    EXPECT_LE(r.clearance_m, closest + 1e-9) << "motion " << tested;
  }
  EXPECT_GT(free, motions / 4);
  EXPECT_GT(with_clearance, free / 2);
}

// A bunny 10 um above a table, sliding and sinking 20 um: with its touching piece pairs left
// to the caller's end check (they cannot pass through each other over a 2 mm slide), no
// meeting is timed and nothing is swept; sliding 3 cm, or with the option off, the pairs are
// swept and the meeting timed as before.
TEST(ConvexCcd, TouchingPiecesThatCannotPassThroughAreLeftToTheEndCheck) {
  const auto set = bunny_pieces();
  const Shape bunny = Shape::convex_set(set);
  const Shape table = Shape::box({1.0, 1.0, 0.04});
  double lowest = std::numeric_limits<double>::infinity();
  for (const ConvexPiece& piece : set->pieces)
    for (const Eigen::Vector3d& v : piece.vertices_m()) lowest = std::min(lowest, v.z());
  const Pose X0 = at({0, 0, 0.02 + 1e-5 - lowest});
  const ScrewMotion still(Pose::Identity(), Pose::Identity());
  const auto slide = [&](double m) { return ScrewMotion(X0, at({m, 0, -2e-5}) * X0); };
  ContinuousOptions options;
  options.touching_unswept_m = 1e-3;
  const ContinuousResult short_slide = time_of_impact(table, still, bunny, slide(2e-3), options);
  EXPECT_TRUE(short_slide.touching_unswept);
  EXPECT_FALSE(short_slide.collides);
  EXPECT_EQ(short_slide.stats.triangle_pairs_tested, 0);
  EXPECT_EQ(short_slide.clearance_m, 0);  // (no clearance while a pair is left unswept)
  const ContinuousResult long_slide = time_of_impact(table, still, bunny, slide(3e-2), options);
  EXPECT_FALSE(long_slide.touching_unswept);
  EXPECT_TRUE(long_slide.collides);
  EXPECT_NEAR(long_slide.time_of_impact, 0.5, 1e-3);
  options.touching_unswept_m = 0;
  const ContinuousResult off = time_of_impact(table, still, bunny, slide(2e-3), options);
  EXPECT_FALSE(off.touching_unswept);
  EXPECT_TRUE(off.collides);
  EXPECT_NEAR(off.time_of_impact, 0.5, 1e-3);
}

}  // namespace
}  // namespace arphys::collision
