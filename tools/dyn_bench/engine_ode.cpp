#include <ode/ode.h>

#include "tools/dyn_bench/engine.hpp"

namespace arphys::dyn_bench {
namespace {

// ODE 0.16 (double) as the anchor ran it: ERP 0.2, CFM 1e-10, up to 8 contacts per
// pair, frictionless contacts when mu = 0, dContactApprox1 otherwise, bounce with
// bounce_vel 0; dWorldStep (Dantzig LCP) or dWorldQuickStep (20 SOR iterations).
class OdeEngine : public Engine {
 public:
  explicit OdeEngine(bool quick) : quick_(quick) {
    static const bool initialised = [] { return dInitODE2(0) != 0; }();
    (void)initialised;
  }
  ~OdeEngine() override {
    if (contacts_) dJointGroupDestroy(contacts_);
    if (space_) dSpaceDestroy(space_);
    if (world_) dWorldDestroy(world_);
  }
  std::string name() const override { return quick_ ? "ode-quick" : "ode-step"; }
  void build(const BenchScene& scene, double dt_s) override {
    dt_ = dt_s;
    world_ = dWorldCreate();
    space_ = dHashSpaceCreate(nullptr);
    contacts_ = dJointGroupCreate(0);
    dWorldSetGravity(world_, scene.gravity_m_s2.x(), scene.gravity_m_s2.y(), scene.gravity_m_s2.z());
    dWorldSetERP(world_, 0.2);
    dWorldSetCFM(world_, 1e-10);
    dWorldSetQuickStepNumIterations(world_, 20);
    for (const BenchBody& b : scene.bodies) {
      Entry e;
      e.friction = b.friction;
      e.restitution = b.restitution;
      if (b.shape == BenchBody::Shape::kPlane) {
        const Eigen::Vector3d n = b.X_WB.linear().col(2);
        e.geom = dCreatePlane(space_, n.x(), n.y(), n.z(), n.dot(b.X_WB.translation()));
      } else {
        e.geom = b.shape == BenchBody::Shape::kBox
                     ? dCreateBox(space_, 2 * b.half_extents_m.x(), 2 * b.half_extents_m.y(), 2 * b.half_extents_m.z())
                     : dCreateSphere(space_, b.radius_m);
        if (b.motion != BenchBody::Motion::kStatic) {
          e.body = dBodyCreate(world_);
          dMass mass;
          if (b.shape == BenchBody::Shape::kBox) {
            dMassSetBoxTotal(&mass, b.mass_kg, 2 * b.half_extents_m.x(), 2 * b.half_extents_m.y(), 2 * b.half_extents_m.z());
          } else {
            dMassSetSphereTotal(&mass, b.mass_kg, b.radius_m);
          }
          dBodySetMass(e.body, &mass);
          dGeomSetBody(e.geom, e.body);
          if (b.motion == BenchBody::Motion::kKinematic) dBodySetKinematic(e.body);
          dBodySetLinearVel(e.body, b.v_m_s.x(), b.v_m_s.y(), b.v_m_s.z());
        }
        set_pose(e, b.X_WB);
      }
      dGeomSetData(e.geom, reinterpret_cast<void*>(entries_.size()));
      entries_.push_back(e);
    }
  }
  void set_kinematic(int i, const Eigen::Isometry3d& X, const Eigen::Vector3d& v) override {
    set_pose(entries_[i], X);
    dBodySetLinearVel(entries_[i].body, v.x(), v.y(), v.z());
  }
  void step() override {
    dSpaceCollide(space_, this, &OdeEngine::near_callback);
    quick_ ? dWorldQuickStep(world_, dt_) : dWorldStep(world_, dt_);
    dJointGroupEmpty(contacts_);
  }
  Eigen::Isometry3d pose(int i) const override {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    const dGeomID g = entries_[i].geom;
    if (dGeomGetClass(g) == dPlaneClass) return X;
    const dReal* p = dGeomGetPosition(g);
    dQuaternion q;
    dGeomGetQuaternion(g, q);
    X.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
    X.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    return X;
  }
  Eigen::Vector3d velocity(int i) const override {
    if (!entries_[i].body) return Eigen::Vector3d::Zero();
    const dReal* v = dBodyGetLinearVel(entries_[i].body);
    return {v[0], v[1], v[2]};
  }

 private:
  struct Entry {
    dGeomID geom = nullptr;
    dBodyID body = nullptr;
    double friction = 0, restitution = 0;
  };
  static void set_pose(const Entry& e, const Eigen::Isometry3d& X) {
    const Eigen::Quaterniond q(X.linear());
    dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
    if (e.body) {
      dBodySetPosition(e.body, X.translation().x(), X.translation().y(), X.translation().z());
      dBodySetQuaternion(e.body, dq);
    } else {
      dGeomSetPosition(e.geom, X.translation().x(), X.translation().y(), X.translation().z());
      dGeomSetQuaternion(e.geom, dq);
    }
  }
  static void near_callback(void* data, dGeomID a, dGeomID b) {
    auto* self = static_cast<OdeEngine*>(data);
    const Entry& ea = self->entries_[reinterpret_cast<std::size_t>(dGeomGetData(a))];
    const Entry& eb = self->entries_[reinterpret_cast<std::size_t>(dGeomGetData(b))];
    const bool dyn_a = ea.body && !dBodyIsKinematic(ea.body), dyn_b = eb.body && !dBodyIsKinematic(eb.body);
    if (!dyn_a && !dyn_b) return;
    dContact contact[8];
    const int n = dCollide(a, b, 8, &contact[0].geom, sizeof(dContact));
    const double mu = std::sqrt(ea.friction * eb.friction) > 0 ? std::sqrt(ea.friction * eb.friction)
                                                                : std::max(ea.friction, eb.friction);
    const double bounce = std::max(ea.restitution, eb.restitution);
    for (int k = 0; k < n; ++k) {
      contact[k].surface.mode = (mu > 0 ? dContactApprox1 : 0) | (bounce > 0 ? dContactBounce : 0);
      contact[k].surface.mu = mu;
      contact[k].surface.bounce = bounce;
      contact[k].surface.bounce_vel = 0;
      const dJointID j = dJointCreateContact(self->world_, self->contacts_, &contact[k]);
      dJointAttach(j, dGeomGetBody(a), dGeomGetBody(b));
    }
  }

  bool quick_;
  double dt_ = 0.001;
  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  std::vector<Entry> entries_;
};

}  // namespace

std::unique_ptr<Engine> make_ode_engine(bool quick) { return std::make_unique<OdeEngine>(quick); }

}  // namespace arphys::dyn_bench
