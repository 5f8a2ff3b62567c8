#pragma once
// The paper's bunny scenes on arphys and on its peers (bunny_peer.hpp): Bullet 3.24 with a
// compound of the same convex pieces and with GImpact on the mesh they were made from,
// MuJoCo 2.2.2 with the pieces as mesh geoms, ODE 0.16 with the mesh as a trimesh; the
// table and the tracked box as boxes, the bunny's mass and inertia as arphys computes them.
// Per scene and engine: ms per step, real-time factor and the deepest overlap of any two
// bodies after each step, measured alike for all by arphys's signed-distance manifolds of
// the pieces at the poses each engine reports.
#include <ostream>
#include <string>

namespace arphys::dyn_bench {

// One row per scene and engine, printed and written to csv (header: see the caller).
void run_bunnies_peers(const std::string& configs_dir, double duration_s, std::ostream& csv);

}  // namespace arphys::dyn_bench
