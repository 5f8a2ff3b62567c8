#include <btBulletDynamicsCommon.h>

#include "tools/dyn_bench/bullet_poses.hpp"
#include "tools/dyn_bench/engine.hpp"

namespace arphys::dyn_bench {
namespace {

// Bullet 3.24 as the anchor ran it: sequential impulses, 10 iterations, split impulse,
// no deactivation; friction and restitution are multiplied per pair, so each object
// gets the square root.
class BulletEngine : public Engine {
 public:
  std::string name() const override { return "bullet"; }
  ~BulletEngine() override {
    for (auto* b : bodies_) {
      world_->removeRigidBody(b);
      delete b->getMotionState();
      delete b;
    }
  }
  void build(const BenchScene& scene, double dt_s) override {
    dt_ = dt_s;
    config_ = std::make_unique<btDefaultCollisionConfiguration>();
    dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
    broadphase_ = std::make_unique<btDbvtBroadphase>();
    solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
    world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(), config_.get());
    world_->setGravity(btVector3(scene.gravity_m_s2.x(), scene.gravity_m_s2.y(), scene.gravity_m_s2.z()));
    world_->getSolverInfo().m_numIterations = 10;
    world_->getSolverInfo().m_splitImpulse = 1;
    for (const BenchBody& b : scene.bodies) {
      std::unique_ptr<btCollisionShape> shape;
      switch (b.shape) {
        case BenchBody::Shape::kPlane: shape = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0); break;
        case BenchBody::Shape::kBox:
          shape = std::make_unique<btBoxShape>(btVector3(b.half_extents_m.x(), b.half_extents_m.y(), b.half_extents_m.z()));
          break;
        case BenchBody::Shape::kSphere: shape = std::make_unique<btSphereShape>(b.radius_m); break;
      }
      const bool dynamic = b.motion == BenchBody::Motion::kDynamic;
      btVector3 inertia(0, 0, 0);
      if (dynamic) shape->calculateLocalInertia(b.mass_kg, inertia);
      auto* state = new btDefaultMotionState(to_bt(b.X_WB));
      btRigidBody::btRigidBodyConstructionInfo info(dynamic ? b.mass_kg : 0.0, state, shape.get(), inertia);
      info.m_friction = std::sqrt(b.friction);
      info.m_restitution = std::sqrt(b.restitution);
      auto* body = new btRigidBody(info);
      body->setActivationState(DISABLE_DEACTIVATION);
      if (b.motion == BenchBody::Motion::kKinematic)
        body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
      if (dynamic) body->setLinearVelocity(btVector3(b.v_m_s.x(), b.v_m_s.y(), b.v_m_s.z()));
      world_->addRigidBody(body);
      bodies_.push_back(body);
      shapes_.push_back(std::move(shape));
    }
  }
  void set_kinematic(int i, const Eigen::Isometry3d& X, const Eigen::Vector3d& v) override {
    bodies_[i]->getMotionState()->setWorldTransform(to_bt(X));
    bodies_[i]->setLinearVelocity(btVector3(v.x(), v.y(), v.z()));
  }
  void step() override { world_->stepSimulation(dt_, 0); }
  Eigen::Isometry3d pose(int i) const override { return from_bt(bodies_[i]->getWorldTransform()); }
  Eigen::Vector3d velocity(int i) const override {
    const btVector3 v = bodies_[i]->getLinearVelocity();
    return {v.x(), v.y(), v.z()};
  }

 private:
  double dt_ = 0.001;
  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<btRigidBody*> bodies_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
};

}  // namespace

std::unique_ptr<Engine> make_bullet_engine() { return std::make_unique<BulletEngine>(); }

}  // namespace arphys::dyn_bench
