#pragma once
// What a World is made of and never changes while it steps: its options and each body's
// model (shape, mass, material, how it moves), indexed like the state's bodies.
#include <vector>

#include "simulator/dynamics/rigid_body.hpp"
#include "simulator/dynamics/world_options.hpp"

namespace arphys::dynamics {

struct WorldModel {
  WorldOptions options;
  std::vector<BodyModel> bodies;
  std::vector<double> radius_m;  // each body's bounding radius about its origin
};

}  // namespace arphys::dynamics
