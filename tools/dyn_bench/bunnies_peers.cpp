#include "tools/dyn_bench/bunnies_peers.hpp"

#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include <Eigen/Eigenvalues>

#include "configs/loader/scene_config.hpp"
#include "simulator/collision/shape_query.hpp"
#include "simulator/dynamics/scene_world.hpp"
#include "tools/dyn_bench/bullet_poses.hpp"

namespace arphys::dyn_bench {
namespace {

using Clock = std::chrono::steady_clock;
using dynamics::RigidBody;

// Deepest overlap (metres, >= 0) of any two bodies at these poses, by arphys's manifolds.
double deepest_overlap_m(const std::vector<RigidBody>& bodies, const std::vector<geometry::Pose>& X_WB) {
  double deepest = 0;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    for (std::size_t j = i + 1; j < bodies.size(); ++j) {
      if (!bodies[i].is_dynamic() && !bodies[j].is_dynamic()) continue;
      if ((X_WB[i].translation() - X_WB[j].translation()).norm() >
          bodies[i].bounding_radius_m() + bodies[j].bounding_radius_m())
        continue;
      for (const auto& p : collision::contact_manifold(bodies[i].shape, X_WB[i], bodies[j].shape, X_WB[j], 0.0))
        deepest = std::max(deepest, -p.distance_m);
    }
  return deepest;
}

struct Row {
  double ms_per_step = 0, simulated_s = 0, deepest_overlap_m = 0;
};

// Bullet as the dynamics benchmark runs it (sequential impulses, 10 iterations, split
// impulse, no deactivation, no CCD), bodies in their principal frames: a bunny is a
// compound of its pieces' hulls placed in the frame of its centre of mass and principal
// axes. A hull's collision margin is added outside it (Bullet's default, 4 cm, would rest
// the bunnies on cushions as thick as their ears): 1 mm, the contact tolerance of arphys.
constexpr double kHullMargin_m = 1e-3;
class BulletBunnies {
 public:
  explicit BulletBunnies(const std::vector<RigidBody>& bodies, const Eigen::Vector3d& gravity) {
    world_ = std::make_unique<btDiscreteDynamicsWorld>(&dispatcher_, &broadphase_, &solver_, &config_);
    world_->setGravity(btVector3(gravity.x(), gravity.y(), gravity.z()));
    world_->getSolverInfo().m_numIterations = 10;
    world_->getSolverInfo().m_splitImpulse = 1;
    for (const RigidBody& body : bodies) add(body);
  }
  ~BulletBunnies() {
    for (auto* b : bodies_) {
      world_->removeRigidBody(b);
      delete b->getMotionState();
      delete b;
    }
  }
  void set_kinematic(int i, const geometry::Pose& X_WB, const Eigen::Vector3d& v_W) {
    bodies_[i]->getMotionState()->setWorldTransform(to_bt(X_WB * X_BP_[i]));
    bodies_[i]->setLinearVelocity(btVector3(v_W.x(), v_W.y(), v_W.z()));
  }
  void step(double dt_s) { world_->stepSimulation(dt_s, 0); }
  geometry::Pose pose(int i) const { return from_bt(bodies_[i]->getWorldTransform()) * X_BP_[i].inverse(); }

 private:
  void add(const RigidBody& body) {
    geometry::Pose X_BP = geometry::Pose::Identity();
    btVector3 inertia(0, 0, 0);
    std::unique_ptr<btCollisionShape> shape;
    if (body.shape.type() == collision::Shape::Type::kConvexSet) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> principal(body.mass.inertia_about_com_kg_m2);
      X_BP.linear() = principal.eigenvectors();
      if (X_BP.linear().determinant() < 0) X_BP.linear().col(2) *= -1;
      X_BP.translation() = body.mass.center_of_mass_m;
      auto compound = std::make_unique<btCompoundShape>();
      for (const auto& piece : body.shape.convex()->pieces) {
        auto hull = std::make_unique<btConvexHullShape>();
        for (const Eigen::Vector3d& v : piece.vertices_m()) {
          const Eigen::Vector3d x = X_BP.inverse() * v;
          hull->addPoint(btVector3(x.x(), x.y(), x.z()), false);
        }
        hull->setMargin(kHullMargin_m);
        hull->recalcLocalAabb();
        compound->addChildShape(btTransform::getIdentity(), hull.get());
        children_.push_back(std::move(hull));
      }
      const Eigen::Vector3d moments = principal.eigenvalues();
      inertia = btVector3(moments.x(), moments.y(), moments.z());
      shape = std::move(compound);
    } else {
      const Eigen::Vector3d half = 0.5 * body.shape.size_m();  // the table and the tracked box
      shape = std::make_unique<btBoxShape>(btVector3(half.x(), half.y(), half.z()));
    }
    const double mass = body.is_dynamic() ? body.mass.mass_kg : 0.0;
    auto* state = new btDefaultMotionState(to_bt(body.X_WB * X_BP));
    btRigidBody::btRigidBodyConstructionInfo info(mass, state, shape.get(), inertia);
    info.m_friction = std::sqrt(body.friction.value_or(0.0));
    info.m_restitution = std::sqrt(body.restitution);
    auto* b = new btRigidBody(info);
    b->setActivationState(DISABLE_DEACTIVATION);
    if (body.motion == dynamics::BodyMotion::kKinematic)
      b->setCollisionFlags(b->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    world_->addRigidBody(b);
    bodies_.push_back(b);
    shapes_.push_back(std::move(shape));
    X_BP_.push_back(X_BP);
  }

  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_{&config_};
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<btRigidBody*> bodies_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_, children_;
  std::vector<geometry::Pose> X_BP_;
};

Row run_arphys(const config::SceneConfig& scene, double duration_s) {
  dynamics::World world = dynamics::build_world(scene);
  Row row;
  const long steps = std::lround(duration_s / scene.time_step_s);
  double wall = 0;
  for (long k = 0; k < steps; ++k) {
    const auto start = Clock::now();
    world.step(scene.time_step_s);
    wall += std::chrono::duration<double>(Clock::now() - start).count();
    std::vector<geometry::Pose> poses;
    for (const RigidBody& b : world.bodies()) poses.push_back(b.X_WB);
    row.deepest_overlap_m = std::max(row.deepest_overlap_m, deepest_overlap_m(world.bodies(), poses));
    row.simulated_s += scene.time_step_s;
    if (wall > 120) break;  // a scene that slows to a crawl is reported, not waited for
  }
  row.ms_per_step = 1e3 * wall * scene.time_step_s / row.simulated_s;
  return row;
}

Row run_bullet(const config::SceneConfig& scene, double duration_s) {
  const dynamics::World world = dynamics::build_world(scene);
  const std::vector<RigidBody>& bodies = world.bodies();
  BulletBunnies bullet(bodies, scene.gravity_m_s2);
  Row row;
  const long steps = std::lround(duration_s / scene.time_step_s);
  double wall = 0;
  std::vector<geometry::Pose> poses(bodies.size());
  for (long k = 0; k < steps; ++k) {
    const double t = k * scene.time_step_s;
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].motion == dynamics::BodyMotion::kKinematic) {
        const geometry::Pose X = bodies[i].trajectory.pose_at(t + scene.time_step_s);
        bullet.set_kinematic(static_cast<int>(i), X, bodies[i].trajectory.twist_at(t).v_WBo_m_s);
      }
    const auto start = Clock::now();
    bullet.step(scene.time_step_s);
    wall += std::chrono::duration<double>(Clock::now() - start).count();
    for (std::size_t i = 0; i < bodies.size(); ++i) poses[i] = bullet.pose(static_cast<int>(i));
    row.deepest_overlap_m = std::max(row.deepest_overlap_m, deepest_overlap_m(bodies, poses));
    row.simulated_s += scene.time_step_s;
  }
  row.ms_per_step = 1e3 * wall * scene.time_step_s / row.simulated_s;
  return row;
}

}  // namespace

void run_bunnies_peers(const std::string& configs_dir, double duration_s, std::ostream& csv) {
  std::printf("\n== bunnies against Bullet's compound of the same pieces: dt 10 ms, %.1f s, one run\n"
              "%-12s %-16s %10s %16s %18s\n",
              duration_s, "scene", "engine", "ms/step", "real-time factor", "deepest overlap mm");
  for (const std::string name : {"bunnies20", "bunnies100"}) {
    const auto scene = config::load_scene(configs_dir + "/scenes/" + name + ".yaml");
    for (const std::string engine : {"arphys", "bullet-compound"}) {
      const Row row = engine == "arphys" ? run_arphys(scene, duration_s) : run_bullet(scene, duration_s);
      std::printf("%-12s %-16s %10.3f %16.2f %18.3f\n", name.c_str(), engine.c_str(), row.ms_per_step,
                  1e3 * scene.time_step_s / row.ms_per_step, 1e3 * row.deepest_overlap_m);
      std::fflush(stdout);
      csv << name << "," << engine << "," << row.ms_per_step << "," << 1e3 * scene.time_step_s / row.ms_per_step << ","
          << 1e3 * row.deepest_overlap_m << "," << row.simulated_s << "\n";
    }
  }
}

}  // namespace arphys::dyn_bench
