#pragma once
// The paper's bunny scenes on arphys and on Bullet 3.24 with the same convex pieces (a
// compound of convex hulls per bunny, the table and the tracked box as boxes, the bunny's
// mass and inertia as arphys computes them): ms per step, real-time factor and the deepest
// overlap of any two bodies after each step, measured alike for both by arphys's own
// signed-distance manifolds at the poses each engine reports.
#include <ostream>
#include <string>

namespace arphys::dyn_bench {

// One row per scene and engine, printed and written to csv (header: see the caller).
void run_bunnies_peers(const std::string& configs_dir, double duration_s, std::ostream& csv);

}  // namespace arphys::dyn_bench
