#include "tools/eval/model_study.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "simulator/scene/scene_world.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::eval {

ModelOutcome run_model_variant(const config::SceneConfig& scene_in, const ModelVariant& v, double duration_s,
                               const std::string& work_dir) {
  config::SceneConfig scene = scene_in;
  config::ObjectConfig* table = nullptr;
  config::ObjectConfig* bunny = nullptr;
  for (auto& o : scene.objects) {
    o.spawn_at_start.clear();
    if (o.id == "table") table = &o;
    if (o.id == "bunny") bunny = &o;
  }
  if (!table || !bunny) throw std::invalid_argument("model study: the scene needs 'table' and 'bunny'");
  const Eigen::Vector3d table_size = table->collision.size_m;
  if (v.table == "plane") {
    table->collision = config::ShapeConfig{};
    table->collision.type = config::ShapeType::kPlane;
    table->X_WO = geometry::Pose::Identity();  // the top surface, z = 0
  } else if (v.table == "mesh") {
    const std::string path = work_dir + "/table_box_mesh.obj";
    geometry::save_obj(geometry::make_box_mesh(table_size), path);
    table->collision.type = config::ShapeType::kMesh;
    table->collision.mesh_path = path;
    table->collision.scale = Eigen::Vector3d::Ones();
  } else if (v.table != "box") {
    throw std::invalid_argument("model study: table must be plane, box or mesh, not '" + v.table + "'");
  }
  // The collision mesh varies; the mass properties stay those of the scene's bunny, so
  // every variant has the same (and the clustered meshes do not close into a solid).
  config::ShapeConfig collision = bunny->collision;
  if (v.bunny_pieces.empty()) {
    collision.type = config::ShapeType::kMesh;
    collision.mesh_path = v.bunny_mesh;
  } else {
    collision.type = config::ShapeType::kConvexSet;
    collision.pieces_path = v.bunny_pieces;
  }
  if (!v.friction) {
    bunny->friction.reset();
    table->friction.reset();
  } else {
    bunny->friction = 0.5;
    table->friction = 0.5;
  }
  dynamics::World world = arphys::scene::build_world(scene);
  // A virtual object without spawns starts as one body at its pose: placed here instead.
  if (world.find("bunny") >= 0) world.remove_body(world.find("bunny"));
  // Three bunnies far apart, dropped from 8 cm with different tilts and spins.
  const double tilts[3] = {0.0, 0.5, -0.8};
  for (int i = 0; i < 3; ++i) {
    const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(tilts[i], Eigen::Vector3d::UnitY())) *
                                 Eigen::Quaterniond(0.7071067811865476, 0.7071067811865476, 0, 0);
    geometry::Pose X = geometry::Pose::Identity();
    X.linear() = q.toRotationMatrix();
    X.translation() = Eigen::Vector3d(-0.35 + 0.3 * i, 0.2, 0.16);
    dynamics::RigidBody body =
        arphys::scene::make_instance(*bunny, "bunny#" + std::to_string(i), X, {0.05 * (i - 1), 0, 0}, {0, 0, 1.0 * i});
    body.shape = arphys::scene::shape_of(collision);
    world.add_body(std::move(body));
  }
  // The fourth, upright on its base (the first's orientation), its lowest vertex 1 mm
  // above the table top (z = 0), away from the others and the box.
  {
    geometry::Pose X = geometry::Pose::Identity();
    X.linear() = Eigen::Quaterniond(0.7071067811865476, 0.7071067811865476, 0, 0).toRotationMatrix();
    dynamics::RigidBody body = arphys::scene::make_instance(*bunny, "bunny#upright", X, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
    body.shape = arphys::scene::shape_of(collision);
    double lowest_m = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& v : body.shape.triangles()->mesh().vertices_m) lowest_m = std::min(lowest_m, (X.linear() * v).z());
    X.translation() = Eigen::Vector3d(-0.1, -0.25, 1e-3 - lowest_m);
    body.X_WB = X;
    world.add_body(std::move(body));
  }
  ModelOutcome out;
  const double dt = scene.time_step_s;
  const long steps = std::lround(duration_s / dt);
  const auto start = std::chrono::steady_clock::now();
  for (long k = 0; k < steps; ++k) {
    const auto report = world.step(dt);
    out.max_penetration_mm = std::max(out.max_penetration_mm, 1e3 * report.max_penetration_m);
  }
  out.ms_per_step = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / steps;
  for (int i = 0; i < 3; ++i) out.rest_poses.push_back(world.body_state(world.find("bunny#" + std::to_string(i))).X_WB);
  out.upright_rest_pose = world.body_state(world.find("bunny#upright")).X_WB;
  return out;
}

std::pair<double, double> rest_pose_error(const std::vector<Eigen::Isometry3d>& a, const std::vector<Eigen::Isometry3d>& b) {
  double position = 0, rotation = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    position += (a[i].translation() - b[i].translation()).norm();
    rotation += Eigen::AngleAxisd(a[i].linear().transpose() * b[i].linear()).angle();
  }
  return {1e3 * position / a.size(), rotation / a.size() * 180 / M_PI};
}

}  // namespace arphys::eval
