#pragma once
// Continuous collision of two convex-piece sets (a box counts as a one-piece set):
// conservative advancement (Mirtich 1996; Tang, Kim & Manocha, C2A, 2009) proves a prefix
// of the motion contact-free, piece pair by piece pair, with GJK distances and a bound on
// how fast the pieces' points can close (a screw's velocity field is constant, so each
// point keeps its speed); what is left goes to the certified mesh query over the pieces'
// hulls. Most pairs of a pile whose sweeps overlap never come near: they are proven apart
// by a few distances instead of a sweep.
//
// Same contract as the mesh query (continuous_query.hpp): never late, at most the time
// tolerance early, nothing missed.
#include "simulator/collision/continuous_query.hpp"
#include "simulator/collision/convex_piece.hpp"

namespace arphys::collision {

ContinuousResult convex_sets_time_of_impact(const ConvexSet& A, const geometry::ScrewMotion& motion_A,
                                            const ConvexSet& B, const geometry::ScrewMotion& motion_B,
                                            const ContinuousOptions& options);

}  // namespace arphys::collision
