#include "simulator/collision/broad_phase.hpp"

#include <gtest/gtest.h>

#include <random>

namespace arphys::collision {
namespace {

TEST(BroadPhase, SweptBoundsContainTheBallAlongTheScrew) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int m = 0; m < 100; ++m) {
    geometry::Pose X0 = geometry::rotation_pose(Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized(), 3 * u(rng));
    geometry::Pose X1 = geometry::rotation_pose(Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized(), 3 * u(rng));
    X0.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng));
    X1.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng));
    const geometry::ScrewMotion motion(X0, X1);
    const Eigen::Vector3d c(0.1, -0.2, 0.3);
    const double r = 0.05;
    const auto box = swept_bounds(motion, c, r);
    for (int k = 0; k <= 100; ++k) {
      const Eigen::Vector3d p = motion.pose_at(k / 100.0) * c;
      ASSERT_TRUE(box.contains(Eigen::AlignedBox3d(p.array() - r, p.array() + r))) << m << " " << k;
    }
    // Not wildly loose: within 1.5x of the sampled hull's size plus the radius.
    Eigen::AlignedBox3d hull;
    for (int k = 0; k <= 100; ++k) hull.extend(motion.pose_at(k / 100.0) * c);
    EXPECT_LT(box.sizes().maxCoeff(), 1.5 * hull.sizes().maxCoeff() + 2 * r + 0.2);
  }
}

// The closed form's corner cases: a half turn (split into pieces), a screw with axial
// travel (the path leaves the chord's box along the axis), a tiny turn about a far axis
// (a translation, numerically), a still body; each tight to the sampled path.
TEST(BroadPhase, SweptBoundsAreTightOnHalfTurnsScrewsAndNearTranslations) {
  const double r = 0.1;
  const Eigen::Vector3d c(0.3, 0, 0);
  std::vector<geometry::ScrewMotion> motions;
  motions.emplace_back(geometry::Pose::Identity(), geometry::rotation_pose(Eigen::Vector3d::UnitZ(), M_PI));
  geometry::Pose screw = geometry::rotation_pose(Eigen::Vector3d::UnitZ(), 2.0);
  screw.translation() = Eigen::Vector3d(0, 0, 0.5);
  motions.emplace_back(geometry::Pose::Identity(), screw);
  geometry::Pose far_turn = geometry::rotation_pose(Eigen::Vector3d::UnitY(), 1e-9);
  far_turn.translation() = Eigen::Vector3d(0.01, 0.02, -0.03);
  motions.emplace_back(geometry::Pose::Identity(), far_turn);
  motions.emplace_back(far_turn, far_turn);
  for (std::size_t m = 0; m < motions.size(); ++m) {
    const auto box = swept_bounds(motions[m], c, r);
    Eigen::AlignedBox3d hull;
    for (int k = 0; k <= 1000; ++k) {
      const Eigen::Vector3d p = motions[m].pose_at(k / 1000.0) * c;
      ASSERT_TRUE(box.contains(Eigen::AlignedBox3d(p.array() - r, p.array() + r))) << m << " " << k;
      hull.extend(Eigen::Vector3d(p.array() - r));
      hull.extend(Eigen::Vector3d(p.array() + r));
    }
    // Within a twentieth of the path's own box (the interval enclosure it replaced was
    // up to 1.5 times as large).
    EXPECT_LT((box.sizes() - hull.sizes()).maxCoeff(), 0.05 * hull.sizes().maxCoeff() + 1e-9) << m;
  }
}

std::vector<std::pair<int, int>> brute_force(const std::vector<Eigen::AlignedBox3d>& boxes) {
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i)
    for (int j = i + 1; j < static_cast<int>(boxes.size()); ++j)
      if (boxes[i].intersects(boxes[j])) pairs.emplace_back(i, j);
  return pairs;
}

// Random sizes, few and many, and a floor that meets many.
TEST(BroadPhase, OverlappingPairsMatchBruteForce) {
  for (const int count : {40, 300}) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> u(0, 10), size(0.1, 1.5);
    std::vector<Eigen::AlignedBox3d> boxes;
    for (int i = 0; i < count; ++i) {
      const Eigen::Vector3d lo(u(rng), u(rng), u(rng));
      boxes.emplace_back(lo, lo + Eigen::Vector3d(size(rng), size(rng), size(rng)));
    }
    const double inf = std::numeric_limits<double>::infinity();
    boxes.emplace_back(Eigen::Vector3d(-inf, -inf, -inf), Eigen::Vector3d(inf, inf, 0.5));  // a floor: meets many
    const auto pairs = overlapping_pairs(boxes);
    EXPECT_EQ(pairs, brute_force(boxes)) << count << " boxes";
    EXPECT_GT(pairs.size(), count == 300 ? 100u : 2u);
  }
}

// Layers of 8 x 8 swept boxes of a pile of 0.2 m boxes (0.35 m wide: their bounding
// spheres), 0.35 m apart, each moved by up to 2 cm: each overlaps about a dozen others.
std::vector<Eigen::AlignedBox3d> jittered_pile(std::mt19937& rng, int layers) {
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  std::vector<Eigen::AlignedBox3d> boxes;
  for (int layer = 0; layer < layers; ++layer)
    for (int gy = 0; gy < 8; ++gy)
      for (int gx = 0; gx < 8; ++gx) {
        // (Braced: the three draws in this order, whatever the compiler.)
        const Eigen::Vector3d c{0.35 * gx + jitter(rng), 0.35 * gy + jitter(rng), 0.2 + 0.35 * layer + jitter(rng)};
        boxes.emplace_back(c - Eigen::Vector3d::Constant(0.175), c + Eigen::Vector3d::Constant(0.175));
      }
  return boxes;
}

// A pile: equal boxes in touching columns and layers (each overlaps a dozen others;
// each pair reported once), one large box (a table), a floor, an empty box and a NaN
// box among them.
TEST(BroadPhase, PileWithOddBoxesMatchesBruteForce) {
  std::mt19937 rng(5);
  std::vector<Eigen::AlignedBox3d> boxes = jittered_pile(rng, 6);
  boxes.emplace_back(Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(3, 3, 0.1));  // a table
  const double inf = std::numeric_limits<double>::infinity();
  boxes.emplace_back(Eigen::Vector3d(-inf, -inf, -inf), Eigen::Vector3d(inf, inf, 0.05));
  boxes.insert(boxes.begin() + 17, Eigen::AlignedBox3d());  // empty
  const double nan = std::numeric_limits<double>::quiet_NaN();
  boxes.insert(boxes.begin() + 100, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(nan), Eigen::Vector3d::Constant(nan)));
  const auto pairs = overlapping_pairs(boxes);
  EXPECT_EQ(pairs, brute_force(boxes));
  EXPECT_GT(pairs.size(), 1000u);
}

// The re-solves of a step move a few boxes of many: the moved boxes' pairs must be the
// brute force's that involve them, and with the pairs carried over the fresh sweep's,
// whatever the moved boxes become (moved away, onto others, NaN, empty, valid again),
// with pairs of two moved boxes found once; with many moved, the full sweep.
TEST(BroadPhase, OverlappingPairsUpdatedMatchAFreshSweep) {
  std::mt19937 rng(21);
  std::vector<Eigen::AlignedBox3d> boxes = jittered_pile(rng, 4);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  boxes.emplace_back(Eigen::Vector3d(-inf, -inf, -inf), Eigen::Vector3d(inf, inf, 0.05));  // a floor
  boxes[40] = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(nan), Eigen::Vector3d::Constant(nan));
  const std::vector<std::pair<int, int>> before = overlapping_pairs(boxes);
  std::vector<char> changed(boxes.size(), 0);
  const auto change = [&](int i, const Eigen::AlignedBox3d& box) {
    boxes[i] = box;
    changed[i] = 1;
  };
  change(3, boxes[3].translated(Eigen::Vector3d(0.1, 0, 0)));    // onto its neighbour
  change(4, boxes[4].translated(Eigen::Vector3d(-0.1, 0, 0)));   // onto the moved one: a pair of two changed
  change(10, boxes[10].translated(Eigen::Vector3d(0, 0, 5)));    // lifted clear of everything
  change(40, boxes[41]);                                         // NaN before, valid now
  change(50, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(nan), Eigen::Vector3d::Constant(nan)));
  change(60, Eigen::AlignedBox3d());                             // empty
  change(static_cast<int>(boxes.size()) - 1,
         Eigen::AlignedBox3d(Eigen::Vector3d(-inf, -inf, -inf), Eigen::Vector3d(inf, inf, 0.3)));  // the floor rises
  const auto updated = overlapping_pairs_updated(boxes, changed, before);
  EXPECT_EQ(updated, brute_force(boxes));
  EXPECT_NE(updated, before);
  EXPECT_TRUE(std::binary_search(updated.begin(), updated.end(), std::make_pair(3, 4)));
  const auto involving_changed = [&] {
    std::vector<std::pair<int, int>> pairs;
    for (const auto& pair : brute_force(boxes))
      if (changed[pair.first] || changed[pair.second]) pairs.push_back(pair);
    return pairs;
  };
  EXPECT_EQ(overlapping_pairs_involving(boxes, changed), involving_changed());
  // Many changed: the full sweep, the same answer.
  for (std::size_t i = 0; i < boxes.size(); i += 2) change(static_cast<int>(i), boxes[i].translated(Eigen::Vector3d(0.05, 0.05, 0)));
  EXPECT_EQ(overlapping_pairs_updated(boxes, changed, before), brute_force(boxes));
  EXPECT_EQ(overlapping_pairs_involving(boxes, changed), involving_changed());
  EXPECT_THROW(overlapping_pairs_updated(boxes, std::vector<char>(3, 0), before), std::invalid_argument);
}

// The sweep runs within cells of a grid over y and z about a box wide: boxes spanning
// several cells (reported once), clusters a kilometre apart along y and along z (cells
// then widen rather than number in the millions), boxes ending exactly on a cell
// boundary, a column stacked along z and a box tall enough to be tested against all.
TEST(BroadPhase, CellsReportEachPairOnceAcrossBoundariesAndDistantClusters) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 2), size(0.05, 0.9);
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const Eigen::Vector3d& cluster : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1000, 0), Eigen::Vector3d(0, 0, -1000)})
    for (int i = 0; i < 150; ++i) {
      const Eigen::Vector3d lo = cluster + Eigen::Vector3d(u(rng), u(rng), u(rng));
      boxes.emplace_back(lo, lo + Eigen::Vector3d(size(rng), size(rng), size(rng)));
    }
  for (int i = 0; i < 20; ++i)  // touching along y: each ends where the next begins
    boxes.emplace_back(Eigen::Vector3d(5, 0.3 * i, 0), Eigen::Vector3d(5.2, 0.3 * (i + 1), 0.2));
  for (int i = 0; i < 20; ++i)  // a column touching along z
    boxes.emplace_back(Eigen::Vector3d(7, 1, 0.3 * i), Eigen::Vector3d(7.2, 1.2, 0.3 * (i + 1)));
  boxes.emplace_back(Eigen::Vector3d(6.9, 0.9, -500), Eigen::Vector3d(7.1, 1.1, 500));  // a pole through the column
  const auto pairs = overlapping_pairs(boxes);
  EXPECT_EQ(pairs, brute_force(boxes));
  EXPECT_GT(pairs.size(), 400u);
}

}  // namespace
}  // namespace arphys::collision
