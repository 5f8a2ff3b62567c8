// The cheap proof that two boxes stay apart over their screw motions: it settles the
// resting pair it was built for, notices a tilt that closes the gap, and never says
// "apart" for a pair the CCD finds meeting.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/collision/discrete_query.hpp"
#include "simulator/collision/separation_certificate.hpp"
#include "simulator/collision/collision_mesh.hpp"
#include "simulator/collision/shape.hpp"
#include "tests/support/poses.hpp"

namespace arphys::collision {
namespace {

using testing::at;
using geometry::Pose;
using geometry::ScrewMotion;

const Eigen::Vector3d kHalf = Eigen::Vector3d::Constant(0.1);

Eigen::Matrix3d turn(double angle_rad, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

bool ccd_meets(const ScrewMotion& a, const ScrewMotion& b) {
  const Shape box = Shape::box(2 * kHalf);
  return time_of_impact(*box.triangles(), a, *box.triangles(), b).collides;
}

// A box resting 1 um above another, sliding 1 mm and turning 1 mrad about the vertical
// in a step (a pile settling): apart throughout, and the certificate proves it.
TEST(SeparationCertificate, ProvesASlidingRestingBoxApart) {
  const ScrewMotion lower(at({0, 0, 0.1}), at({0, 0, 0.1}));
  const ScrewMotion upper(at({0, 0, 0.3 + 1e-6}), at({1e-3, 0, 0.3 + 1e-6}, turn(1e-3, Eigen::Vector3d::UnitZ())));
  EXPECT_TRUE(boxes_stay_apart(kHalf, lower, kHalf, upper));
  EXPECT_TRUE(boxes_stay_apart(kHalf, upper, kHalf, lower));
  EXPECT_FALSE(ccd_meets(lower, upper));
}

// The same box tilting 1e-4 rad about a horizontal axis: an edge 0.1 m from the axis
// drops 10 um, through the 1 um gap. Not apart, and the certificate must not say so.
TEST(SeparationCertificate, DoesNotProveATiltThatClosesTheGap) {
  const ScrewMotion lower(at({0, 0, 0.1}), at({0, 0, 0.1}));
  const ScrewMotion upper(at({0, 0, 0.3 + 1e-6}), at({0, 0, 0.3 + 1e-6}, turn(1e-4, Eigen::Vector3d::UnitX())));
  EXPECT_FALSE(boxes_stay_apart(kHalf, lower, kHalf, upper));
  EXPECT_TRUE(ccd_meets(lower, upper));
}

// Random pairs near contact (gaps of 0-100 um, turns up to 0.05 rad, shifts up to
// 5 mm): whenever the certificate says apart, the CCD finds no meeting.
TEST(SeparationCertificate, NeverProvesApartAPairTheCcdSeesMeet) {
  std::mt19937 rng(20261126);
  std::uniform_real_distribution<double> unit(-1, 1), gap(0, 1e-4);
  int proven = 0, meeting = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Eigen::Matrix3d R0 = turn(0.2 * unit(rng), Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    const Pose A0 = at({0, 0, 0.1});
    const Pose B0 = at({0.02 * unit(rng), 0.02 * unit(rng), 0.3 + 0.05 + gap(rng)}, R0);
    // Lift B until it is just clear of A's top face (its lowest corner at the gap).
    Pose B0_clear = B0;
    double lowest = 1e9;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner((c & 1 ? 1 : -1) * 0.1, (c & 2 ? 1 : -1) * 0.1, (c & 4 ? 1 : -1) * 0.1);
      lowest = std::min(lowest, (B0 * corner).z());
    }
    B0_clear.translation().z() += 0.2 + gap(rng) - lowest;
    auto moved = [&](const Pose& X, double shift_m, double angle_rad) {
      Pose Y = X;
      Y.linear() = turn(angle_rad * unit(rng), Eigen::Vector3d(unit(rng), unit(rng), unit(rng))) * X.linear();
      Y.translation() += shift_m * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
      return Y;
    };
    const ScrewMotion a(A0, moved(A0, 5e-3, 0.05)), b(B0_clear, moved(B0_clear, 5e-3, 0.05));
    const bool apart = boxes_stay_apart(kHalf, a, kHalf, b);
    const bool meets = ccd_meets(a, b);
    proven += apart;
    meeting += meets;
    EXPECT_FALSE(apart && meets) << "trial " << trial;
  }
  // Neither side vacuous.
  EXPECT_GT(proven, 40);
  EXPECT_GT(meeting, 40);
}

// The start-pose gap the world uses to skip a pair's CCD: exact where a face normal
// separates, and never more than the true distance (2000 random pairs, the distance
// measured between the boxes' surfaces).
TEST(SeparationCertificate, TheGapAlongFaceNormalsIsALowerBoundOnTheDistance) {
  EXPECT_NEAR(box_gap_lower_bound_m(kHalf, at({0, 0, 0}), kHalf, at({0.25, 0, 0})), 0.05, 1e-15);
  EXPECT_NEAR(box_gap_lower_bound_m(kHalf, at({0, 0, 0}), kHalf, at({0.25, 0, 0}, turn(M_PI / 4, Eigen::Vector3d::UnitZ()))),
              0.25 - 0.1 - 0.1 * std::sqrt(2.0), 1e-15);
  EXPECT_LT(box_gap_lower_bound_m(kHalf, at({0, 0, 0}), kHalf, at({0.15, 0, 0})), 0);  // overlapping
  const Shape box = Shape::box(2 * kHalf);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-0.4, 0.4), unit(-1, 1), angle(-M_PI, M_PI);
  int positive = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Pose A = at({0, 0, 0}, turn(angle(rng), {unit(rng), unit(rng), unit(rng) + 1e-3}));
    const Pose B = at({coordinate(rng), coordinate(rng), coordinate(rng)}, turn(angle(rng), {unit(rng), unit(rng), unit(rng) + 1e-3}));
    const double gap = box_gap_lower_bound_m(kHalf, A, kHalf, B);
    if (gap <= 0) continue;
    ++positive;
    const double distance = separation(*box.triangles(), A, *box.triangles(), B).distance_m;
    ASSERT_LE(gap, distance + 1e-12) << "trial " << trial;
  }
  EXPECT_GT(positive, 500);
}

// Any two shapes by their bounding boxes (a mesh's root box, a sphere's cube): never more
// than the distance between the bunny and a box, a sphere or another bunny (1000 random
// pairs each), and nothing to say about a plane.
TEST(SeparationCertificate, TheBoundingBoxGapOfMeshesAndSpheresIsALowerBoundOnTheDistance) {
  const Shape bunny =
      Shape::mesh(CollisionMesh::load(std::string(ARPHYS_SOURCE_DIR) + "/configs/models/stanford-bunny-1k-quadric.obj"));
  const Shape box = Shape::box({0.2, 0.1, 0.05}), sphere = Shape::sphere(0.03), point = Shape::box(Eigen::Vector3d::Constant(1e-9));
  EXPECT_EQ(gap_lower_bound_m(Shape::plane(), at({0, 0, 0}), box, at({0, 0, 1})), -1);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coordinate(-0.25, 0.25), unit(-1, 1), angle(-M_PI, M_PI);
#ifdef ARPHYS_UNDER_SANITIZERS
  const int kTrials = 250;  // the same paths checked for memory and UB (1000 took 50 s there)
#else
  const int kTrials = 1000;
#endif
  for (const Shape* other : {&box, &sphere, &bunny}) {
    int positive = 0;
    for (int trial = 0; trial < kTrials; ++trial) {
      const Pose A = at({0, 0, 0}, turn(angle(rng), {unit(rng), unit(rng), unit(rng) + 1e-3}));
      const Pose B = at({coordinate(rng), coordinate(rng), coordinate(rng)}, turn(angle(rng), {unit(rng), unit(rng), unit(rng) + 1e-3}));
      const double gap = gap_lower_bound_m(bunny, A, *other, B);
      if (gap <= 0) continue;
      ++positive;
      // Only features closer than the gap claims are looked for: any found is a failure.
      // (The sphere's distance: its centre's, as a nanometre box's, less its radius.)
      const double distance =
          other == &sphere ? separation(*bunny.triangles(), A, *point.triangles(), B, gap + 0.03).distance_m - 0.03
                           : separation(*bunny.triangles(), A, *other->triangles(), B, gap).distance_m;
      ASSERT_LE(gap, distance + 1e-8) << "trial " << trial;
    }
    EXPECT_GT(positive, 3 * kTrials / 10);
  }
}

}  // namespace
}  // namespace arphys::collision
