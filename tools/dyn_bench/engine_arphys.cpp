#include "tools/dyn_bench/engine.hpp"

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>

#include "simulator/dynamics/world.hpp"
#include "simulator/geometry/mass_properties.hpp"

namespace arphys::dyn_bench {

class ArphysEngine : public Engine {
 public:
  // adjust: the variant's change to the world's default options.
  ArphysEngine(std::string name, std::function<void(dynamics::WorldOptions&)> adjust)
      : name_(std::move(name)), adjust_(std::move(adjust)) {}
  std::string name() const override { return name_; }
  void build(const BenchScene& scene, double dt_s) override {
    dynamics::WorldOptions options;
    options.gravity_m_s2 = scene.gravity_m_s2;
    if (adjust_) adjust_(options);
    world_ = std::make_unique<dynamics::World>(options);
    dt_ = dt_s;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      const BenchBody& b = scene.bodies[i];
      dynamics::RigidBody body;
      body.id = "b" + std::to_string(i);
      body.X_WB = b.X_WB;
      body.restitution = b.restitution;
      if (b.friction > 0) body.friction = b.friction;
      switch (b.shape) {
        case BenchBody::Shape::kPlane: body.shape = collision::Shape::plane(); break;
        case BenchBody::Shape::kBox: body.shape = collision::Shape::box(2 * b.half_extents_m); break;
        case BenchBody::Shape::kSphere: body.shape = collision::Shape::sphere(b.radius_m); break;
      }
      body.motion = b.motion == BenchBody::Motion::kDynamic ? dynamics::BodyMotion::kDynamic
                    : b.motion == BenchBody::Motion::kKinematic ? dynamics::BodyMotion::kKinematic
                                                                 : dynamics::BodyMotion::kStatic;
      if (body.motion == dynamics::BodyMotion::kDynamic) {
        body.mass = b.shape == BenchBody::Shape::kSphere
                        ? geometry::with_mass(geometry::sphere_mass_properties(b.radius_m, 1000), b.mass_kg)
                        : geometry::with_mass(geometry::box_mass_properties(2 * b.half_extents_m, 1000), b.mass_kg);
        body.v_WBcm_m_s = b.v_m_s;
      }
      world_->add_body(body);
    }
  }
  void set_kinematic(int i, const Eigen::Isometry3d& X, const Eigen::Vector3d& v) override {
    dynamics::KinematicTrajectory trajectory;
    trajectory.add(world_->time_s(), X);
    Eigen::Isometry3d next = X;
    next.translation() += v * dt_;
    trajectory.add(world_->time_s() + dt_, next);
    world_->set_trajectory(i, std::move(trajectory));
  }
  void step() override { world_->step(dt_); }
  Eigen::Isometry3d pose(int i) const override { return world_->body_state(i).X_WB; }
  Eigen::Vector3d velocity(int i) const override { return world_->body_state(i).v_WBcm_m_s; }

 private:
  std::string name_;
  std::function<void(dynamics::WorldOptions&)> adjust_;
  std::unique_ptr<dynamics::World> world_;
  double dt_ = 0.001;
};

std::unique_ptr<Engine> make_arphys_engine(const std::string& variant) {
  if (variant == "arphys") return std::make_unique<ArphysEngine>(variant, nullptr);
  if (variant == "arphys-iterative")
    return std::make_unique<ArphysEngine>(variant, [](dynamics::WorldOptions& o) {
      o.solver.kind = dynamics::ContactSolverKind::kProjectedGaussSeidel;
    });
  // The accuracy budget (penetration <= 1e-5 m) spent on speed: a resting gap
  // and an overlap tolerance of 10 um instead of 1 um.
  if (variant == "arphys-10um")
    return std::make_unique<ArphysEngine>(variant, [](dynamics::WorldOptions& o) { o.contact_gap_m = o.overlap_tolerance_m = 1e-5; });
  // Resting points left too deep lifted by a velocity constraint and a re-solve of the
  // step, not by moving end poses (WorldOptions::project_deep_points = false;
  // docs/decisions/0004).
  if (variant == "arphys-resolve")
    return std::make_unique<ArphysEngine>(variant, [](dynamics::WorldOptions& o) { o.project_deep_points = false; });
  throw std::invalid_argument("unknown arphys variant '" + variant + "'");
}

}  // namespace arphys::dyn_bench
