#pragma once
// What every time-of-impact test asks of a query's answer.
#include <gtest/gtest.h>

#include "simulator/collision/continuous_query.hpp"
#include "simulator/geometry/screw_motion.hpp"

namespace arphys::testing {

// A body that does not move over the step.
inline const geometry::ScrewMotion kStill{geometry::Pose::Identity(), geometry::Pose::Identity()};

// The time of impact must be within [truth - tolerance, truth]: never late, barely early.
inline void expect_toi(const collision::ContinuousResult& r, double truth, double tolerance = 2e-9) {
  ASSERT_TRUE(r.collides);
  EXPECT_LE(r.time_of_impact, truth + 1e-12);
  EXPECT_GE(r.time_of_impact, truth - tolerance);
}

}  // namespace arphys::testing
