#pragma once
// The contact points a body pair keeps when its manifold has more than the solver
// should carry (WorldOptions::max_contacts_per_pair): a bunny resting on a table
// touches with hundreds of vertices that say no more than eight well-chosen ones.
#include <vector>

#include "simulator/collision/discrete_query.hpp"

namespace arphys::dynamics {

// At most `limit` of `points`, all of them if they fit. Points are grouped by normal
// (within 20 degrees); each group's closest point is kept first, groups in the order of
// their closest points, then each group's extremes along four directions across its
// normal among the points touching as its closest does (within 10 um: the support
// polygon it rests on), then among all its points. Closest first: two bunnies within the contact
// tolerance have a hundred and more features in a dozen directions, and filling the
// limit with the largest group's extremes (as this did first) dropped the one edge pair
// that touched, 2 pm apart; with no row to hold it, the pair sank 5 mm into each other
// over ten steps.
std::vector<collision::ManifoldPoint> reduce_manifold(std::vector<collision::ManifoldPoint> points, int limit);

}  // namespace arphys::dynamics
