#pragma once
// "Model no more than a scene needs": the paper's table-and-bunny scene with its models
// varied one at a time (the table as a plane, a box or a triangle mesh; the bunny's
// collision mesh at about 500, 1k, 5k and 70k triangles, or as convex pieces; friction on or off). Three
// bunnies are dropped apart (no bunny touches another, so the outcome is not chaotic)
// and come to rest; accuracy is how far their rest poses are from the richest model's
// (70k bunny, box table, same friction), cost is milliseconds per step. A tilted bunny
// topples one way or the other on tiny differences, so those rest poses compare
// outcomes more than models; a fourth bunny, set down upright on its base 1 mm above the
// table, settles where its model's base puts it, which ranks the models.
#include <string>
#include <vector>

#include "configs/loader/scene_config.hpp"

namespace arphys::eval {

struct ModelVariant {
  std::string table = "box";        // "plane" | "box" | "mesh"
  std::string bunny_mesh;           // absolute path of the collision mesh
  int bunny_triangles = 0;          // for the report
  bool friction = true;
  std::string bunny_pieces;         // a convex-piece file: the bunny collides as its pieces, not bunny_mesh
};

struct ModelOutcome {
  double ms_per_step = 0;
  double max_penetration_mm = 0;
  std::vector<Eigen::Isometry3d> rest_poses;  // the three dropped bunnies at the end
  Eigen::Isometry3d upright_rest_pose;        // the bunny set down upright, at the end
};

// work_dir: where the table mesh file is written (the "mesh" table).
ModelOutcome run_model_variant(const config::SceneConfig& scene, const ModelVariant& variant, double duration_s,
                               const std::string& work_dir);

// Mean position (mm) and rotation (deg) distance between two sets of rest poses.
std::pair<double, double> rest_pose_error(const std::vector<Eigen::Isometry3d>& a, const std::vector<Eigen::Isometry3d>& b);

}  // namespace arphys::eval
