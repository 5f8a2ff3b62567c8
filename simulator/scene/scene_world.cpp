#include "simulator/scene/scene_world.hpp"

#include <map>
#include <tuple>
#include <stdexcept>

namespace arphys::scene {

using dynamics::BodyMotion;
using dynamics::ContactSolverKind;

namespace {

constexpr double kWaterDensity_kg_m3 = 1000.0;

// Meshes are shared by every body and instance that uses them.
std::shared_ptr<const collision::CollisionMesh> cached_mesh(const std::string& path, const Eigen::Vector3d& scale) {
  static std::map<std::pair<std::string, std::tuple<double, double, double>>, std::shared_ptr<const collision::CollisionMesh>> cache;
  const auto key = std::make_pair(path, std::make_tuple(scale.x(), scale.y(), scale.z()));
  auto& slot = cache[key];
  if (!slot) slot = collision::CollisionMesh::load(path, scale);
  return slot;
}

std::shared_ptr<const collision::ConvexSet> cached_pieces(const std::string& path, const Eigen::Vector3d& scale) {
  static std::map<std::pair<std::string, std::tuple<double, double, double>>, std::shared_ptr<const collision::ConvexSet>> cache;
  auto& slot = cache[std::make_pair(path, std::make_tuple(scale.x(), scale.y(), scale.z()))];
  if (!slot) slot = collision::load_convex_set(path, scale);
  return slot;
}

BodyMotion motion_of(config::Motion motion) {
  switch (motion) {
    case config::Motion::kStatic: return BodyMotion::kStatic;
    case config::Motion::kKinematic: return BodyMotion::kKinematic;
    case config::Motion::kDynamic: return BodyMotion::kDynamic;
  }
  return BodyMotion::kStatic;
}

}  // namespace

collision::Shape shape_of(const config::ShapeConfig& shape) {
  switch (shape.type) {
    case config::ShapeType::kPlane: return collision::Shape::plane();
    case config::ShapeType::kBox: return collision::Shape::box(shape.size_m);
    case config::ShapeType::kSphere: return collision::Shape::sphere(shape.radius_m);
    case config::ShapeType::kMesh: return collision::Shape::mesh(cached_mesh(shape.mesh_path, shape.scale));
    case config::ShapeType::kConvexSet: return collision::Shape::convex_set(cached_pieces(shape.pieces_path, shape.scale));
  }
  return collision::Shape::plane();
}

geometry::MassProperties mass_properties_of(const config::ObjectConfig& object) {
  const double density = object.density_kg_m3.value_or(kWaterDensity_kg_m3);
  geometry::MassProperties props;
  switch (object.collision.type) {
    case config::ShapeType::kBox: props = geometry::box_mass_properties(object.collision.size_m, density); break;
    case config::ShapeType::kSphere: props = geometry::sphere_mass_properties(object.collision.radius_m, density); break;
    case config::ShapeType::kMesh:
    case config::ShapeType::kConvexSet: {
      // Every spawn of a model asks again: loading, capping and integrating a 5k mesh
      // takes about 10 ms, a hitch in the live simulator at each spawn. Convex pieces
      // weigh what their source mesh does, or their hulls' union when none is named.
      const bool pieces = object.collision.type == config::ShapeType::kConvexSet && object.collision.mesh_path.empty();
      const std::string& path = pieces ? object.collision.pieces_path : object.collision.mesh_path;
      static std::map<std::tuple<std::string, double, double, double, double>, geometry::MassProperties> cache;
      const auto key = std::make_tuple(path, object.collision.scale.x(), object.collision.scale.y(),
                                       object.collision.scale.z(), density);
      const auto cached = cache.find(key);
      if (cached != cache.end()) {
        props = cached->second;
        break;
      }
      auto mesh = geometry::load_mesh(path, object.collision.scale);
      if (!pieces) geometry::cap_boundary_loops(mesh);
      try {
        props = geometry::mesh_mass_properties(mesh, density);
      } catch (const std::exception& e) {
        throw std::invalid_argument("object '" + object.id + "': " + e.what());
      }
      cache.emplace(key, props);
      break;
    }
    case config::ShapeType::kPlane: throw std::invalid_argument("object '" + object.id + "': a plane has no mass");
  }
  return object.mass_kg ? geometry::with_mass(props, *object.mass_kg) : props;
}

WorldOptions world_options_of(const config::SceneConfig& scene) {
  WorldOptions options;
  options.gravity_m_s2 = scene.gravity_m_s2;
  options.solver.kind = scene.solver == "iterative" ? ContactSolverKind::kProjectedGaussSeidel : ContactSolverKind::kExact;
  options.solver.iterations = scene.solver_iterations;
  if (scene.contact_gap_m) options.contact_gap_m = *scene.contact_gap_m;
  if (scene.overlap_tolerance_m) options.overlap_tolerance_m = *scene.overlap_tolerance_m;
  options.sleep_after_s = scene.sleep_after_s;
  options.sleep_speed_m_s = scene.sleep_speed_m_s;
  return options;
}

RigidBody make_instance(const config::ObjectConfig& object, const std::string& id, const geometry::Pose& X_WB,
                        const Eigen::Vector3d& v_WO_m_s, const Eigen::Vector3d& w_WB_rad_s) {
  RigidBody body;
  body.id = id;
  body.model = object.id;
  body.real = object.role == config::Role::kReal;
  body.motion = BodyMotion::kDynamic;
  body.shape = shape_of(object.collision);
  body.mass = mass_properties_of(object);
  body.restitution = object.restitution;
  body.friction = object.friction;
  body.X_WB = X_WB;
  body.set_origin_velocity(v_WO_m_s, w_WB_rad_s);
  return body;
}

World build_world(const config::SceneConfig& scene, int threads) {
  WorldOptions options = world_options_of(scene);
  options.threads = threads;
  World world(options);
  for (const config::ObjectConfig& object : scene.objects) {
    if (object.motion == config::Motion::kDynamic) {
      if (object.spawn_at_start.empty()) {
        world.add_body(make_instance(object, object.id, object.X_WO, object.v_WO_m_s, object.w_WO_rad_s));
      } else {
        for (std::size_t k = 0; k < object.spawn_at_start.size(); ++k) {
          const config::SpawnConfig& s = object.spawn_at_start[k];
          world.add_body(make_instance(object, object.id + "#" + std::to_string(k), s.X_WB, s.v_WB_m_s, s.w_WB_rad_s));
        }
      }
      continue;
    }
    RigidBody body;
    body.id = object.id;
    body.model = object.id;
    body.real = object.role == config::Role::kReal;
    body.motion = motion_of(object.motion);
    body.shape = shape_of(object.collision);
    body.restitution = object.restitution;
    body.friction = object.friction;
    body.X_WB = object.X_WO;
    for (const config::TimedPoseConfig& sample : object.trajectory) body.trajectory.add(sample.t_s, sample.X_WO);
    if (!body.trajectory.empty()) body.X_WB = body.trajectory.pose_at(0.0);
    world.add_body(std::move(body));
  }
  return world;
}

}  // namespace arphys::scene
