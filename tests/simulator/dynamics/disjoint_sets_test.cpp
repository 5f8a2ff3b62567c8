#include "simulator/dynamics/disjoint_sets.hpp"

#include <gtest/gtest.h>

namespace arphys::dynamics {
namespace {

// Groups are named by their smallest body whatever the order of the joins (the world
// steps groups in that order), and long chains are found (path halving).
TEST(DisjointSets, SetsAreNamedByTheirSmallestMemberWhateverTheJoinOrder) {
  DisjointSets sets(10);
  sets.join(9, 7);
  sets.join(7, 3);
  sets.join(5, 9);
  sets.join(2, 8);
  for (int x : {3, 5, 7, 9}) EXPECT_EQ(sets.find(x), 3) << x;
  for (int x : {2, 8}) EXPECT_EQ(sets.find(x), 2) << x;
  for (int x : {0, 1, 4, 6}) EXPECT_EQ(sets.find(x), x) << x;
  sets.join(8, 9);
  for (int x : {2, 3, 5, 7, 8, 9}) EXPECT_EQ(sets.find(x), 2) << x;

  DisjointSets chain(1000);
  for (int i = 999; i > 0; --i) chain.join(i, i - 1);
  EXPECT_EQ(chain.find(999), 0);
  EXPECT_THROW(DisjointSets(-1), std::invalid_argument);
}

}  // namespace
}  // namespace arphys::dynamics
