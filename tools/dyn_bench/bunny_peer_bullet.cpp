// Bullet on the bunny scenes: sequential impulses as the dynamics benchmark runs them (10
// iterations, split impulse, no deactivation, no CCD), bodies in their principal frames.
#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <btBulletDynamicsCommon.h>

#include <cmath>

#include <Eigen/Eigenvalues>

#include "tools/dyn_bench/bullet_poses.hpp"
#include "tools/dyn_bench/bunny_peer.hpp"

namespace arphys::dyn_bench {

geometry::Pose principal_frame(const dynamics::RigidBody& body, Eigen::Vector3d* moments_kg_m2) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> principal(body.mass.inertia_about_com_kg_m2);
  geometry::Pose X_BP = geometry::Pose::Identity();
  X_BP.linear() = principal.eigenvectors();
  if (X_BP.linear().determinant() < 0) X_BP.linear().col(2) *= -1;
  X_BP.translation() = body.mass.center_of_mass_m;
  *moments_kg_m2 = principal.eigenvalues();
  return X_BP;
}

namespace {

// A hull's or a mesh's collision margin lies outside it (Bullet's default, 4 cm, would rest
// the bunnies on cushions as thick as their ears): 1 mm, the contact tolerance of arphys.
constexpr double kMargin_m = 1e-3;

class BulletBunnies : public BunnyPeer {
 public:
  BulletBunnies(const BunnyModel& model, bool gimpact) : gimpact_(gimpact) {
    if (gimpact) btGImpactCollisionAlgorithm::registerAlgorithm(&dispatcher_);
    world_ = std::make_unique<btDiscreteDynamicsWorld>(&dispatcher_, &broadphase_, &solver_, &config_);
    const Eigen::Vector3d& g = model.gravity_m_s2;
    world_->setGravity(btVector3(g.x(), g.y(), g.z()));
    world_->getSolverInfo().m_numIterations = 10;
    world_->getSolverInfo().m_splitImpulse = 1;
    for (const dynamics::RigidBody& body : model.bodies) add(body, model.bunny_mesh);
  }
  ~BulletBunnies() override {
    for (auto* b : bodies_) {
      world_->removeRigidBody(b);
      delete b->getMotionState();
      delete b;
    }
  }
  void set_kinematic(int i, const geometry::Pose& X_WB, const Eigen::Vector3d& v_W) override {
    bodies_[i]->getMotionState()->setWorldTransform(to_bt(X_WB * X_BP_[i]));
    bodies_[i]->setLinearVelocity(btVector3(v_W.x(), v_W.y(), v_W.z()));
  }
  void step(double dt_s) override { world_->stepSimulation(dt_s, 0); }
  geometry::Pose pose(int i) const override { return from_bt(bodies_[i]->getWorldTransform()) * X_BP_[i].inverse(); }

 private:
  // The bunny in its principal frame: the pieces' hulls, or its mesh for GImpact.
  std::unique_ptr<btCollisionShape> bunny_shape(const dynamics::RigidBody& body, const geometry::Pose& X_PB,
                                                const geometry::TriangleMesh& mesh) {
    if (gimpact_) {
      auto& vertices = vertex_arrays_.emplace_back();
      auto& indices = index_arrays_.emplace_back();
      for (const Eigen::Vector3d& v : mesh.vertices_m) {
        const Eigen::Vector3d x = X_PB * v;
        vertices.insert(vertices.end(), {x.x(), x.y(), x.z()});
      }
      for (const Eigen::Vector3i& t : mesh.triangles) indices.insert(indices.end(), {t[0], t[1], t[2]});
      auto array = std::make_unique<btTriangleIndexVertexArray>(static_cast<int>(mesh.triangles.size()), indices.data(),
                                                                3 * static_cast<int>(sizeof(int)),
                                                                static_cast<int>(mesh.vertices_m.size()), vertices.data(),
                                                                3 * static_cast<int>(sizeof(btScalar)));
      auto shape = std::make_unique<btGImpactMeshShape>(array.get());
      shape->setMargin(kMargin_m);
      shape->updateBound();
      arrays_.push_back(std::move(array));
      return shape;
    }
    auto compound = std::make_unique<btCompoundShape>();
    for (const auto& piece : body.shape.convex()->pieces) {
      auto hull = std::make_unique<btConvexHullShape>();
      for (const Eigen::Vector3d& v : piece.vertices_m()) {
        const Eigen::Vector3d x = X_PB * v;
        hull->addPoint(btVector3(x.x(), x.y(), x.z()), false);
      }
      hull->setMargin(kMargin_m);
      hull->recalcLocalAabb();
      compound->addChildShape(btTransform::getIdentity(), hull.get());
      children_.push_back(std::move(hull));
    }
    return compound;
  }
  void add(const dynamics::RigidBody& body, const geometry::TriangleMesh& mesh) {
    geometry::Pose X_BP = geometry::Pose::Identity();
    btVector3 inertia(0, 0, 0);
    std::unique_ptr<btCollisionShape> shape;
    if (body.shape.type() == collision::Shape::Type::kConvexSet) {
      Eigen::Vector3d moments;
      X_BP = principal_frame(body, &moments);
      inertia = btVector3(moments.x(), moments.y(), moments.z());
      shape = bunny_shape(body, X_BP.inverse(), mesh);
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

  bool gimpact_;
  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_{&config_};
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<btRigidBody*> bodies_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_, children_;
  std::vector<std::unique_ptr<btTriangleIndexVertexArray>> arrays_;
  std::vector<std::vector<btScalar>> vertex_arrays_;  // (a vector of vectors: each array's data stays put)
  std::vector<std::vector<int>> index_arrays_;
  std::vector<geometry::Pose> X_BP_;
};

}  // namespace

std::unique_ptr<BunnyPeer> make_bullet_bunnies(const BunnyModel& model, bool gimpact) {
  return std::make_unique<BulletBunnies>(model, gimpact);
}

}  // namespace arphys::dyn_bench
