// ODE 0.16 on the bunny scenes, as the dynamics benchmark runs it (quickstep, 20 SOR
// iterations, ERP 0.2, CFM 1e-10, dContactApprox1 friction, bounce with the larger
// restitution): each bunny its mesh as a trimesh, in its principal frame with the bunny's
// mass and inertia; the table and the tracked box (kinematic) boxes.
#include <ode/ode.h>

#include <algorithm>
#include <cmath>

#include "tools/dyn_bench/bunny_peer.hpp"

namespace arphys::dyn_bench {
namespace {

// Contacts per geom pair: a trimesh pair reports one per crossing triangle pair.
constexpr int kMaxContacts = 16;

class OdeBunnies : public BunnyPeer {
 public:
  explicit OdeBunnies(const BunnyModel& model) {
    static const bool initialised = [] { return dInitODE2(0) != 0; }();
    (void)initialised;
    world_ = dWorldCreate();
    space_ = dHashSpaceCreate(nullptr);
    contacts_ = dJointGroupCreate(0);
    const Eigen::Vector3d& g = model.gravity_m_s2;
    dWorldSetGravity(world_, g.x(), g.y(), g.z());
    dWorldSetERP(world_, 0.2);
    dWorldSetCFM(world_, 1e-10);
    dWorldSetQuickStepNumIterations(world_, 20);
    for (const dynamics::RigidBody& body : model.bodies) add(body, model.bunny_mesh);
  }
  ~OdeBunnies() override {
    dJointGroupDestroy(contacts_);
    dSpaceDestroy(space_);
    for (dTriMeshDataID data : mesh_data_) dGeomTriMeshDataDestroy(data);
    dWorldDestroy(world_);
  }
  void set_kinematic(int i, const geometry::Pose& X_WB, const Eigen::Vector3d& v_W) override {
    // (ODE moves a kinematic body by its velocity over the step: it is set to start where
    // the step starts, which is where the last one ended.)
    dBodySetLinearVel(entries_[i].body, v_W.x(), v_W.y(), v_W.z());
    (void)X_WB;
  }
  void step(double dt_s) override {
    dSpaceCollide(space_, this, &OdeBunnies::near_callback);
    dWorldQuickStep(world_, dt_s);
    dJointGroupEmpty(contacts_);
  }
  geometry::Pose pose(int i) const override {
    const Entry& e = entries_[i];
    geometry::Pose X_WP = geometry::Pose::Identity();
    const dReal* p = dGeomGetPosition(e.geom);
    dQuaternion q;
    dGeomGetQuaternion(e.geom, q);
    X_WP.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    X_WP.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    return X_WP * e.X_BP.inverse();
  }

 private:
  struct Entry {
    dGeomID geom = nullptr;
    dBodyID body = nullptr;
    double friction = 0, restitution = 0;
    geometry::Pose X_BP = geometry::Pose::Identity();
  };
  dGeomID bunny_geom(const geometry::Pose& X_PB, const geometry::TriangleMesh& mesh) {
    auto& vertices = vertex_arrays_.emplace_back();
    auto& indices = index_arrays_.emplace_back();
    for (const Eigen::Vector3d& v : mesh.vertices_m) {
      const Eigen::Vector3d x = X_PB * v;
      vertices.insert(vertices.end(), {x.x(), x.y(), x.z()});
    }
    for (const Eigen::Vector3i& t : mesh.triangles)
      for (int k = 0; k < 3; ++k) indices.push_back(static_cast<dTriIndex>(t[k]));
    dTriMeshDataID data = dGeomTriMeshDataCreate();
    dGeomTriMeshDataBuildDouble(data, vertices.data(), 3 * sizeof(double), static_cast<int>(mesh.vertices_m.size()),
                                indices.data(), static_cast<int>(indices.size()), 3 * sizeof(dTriIndex));
    mesh_data_.push_back(data);
    return dCreateTriMesh(space_, data, nullptr, nullptr, nullptr);
  }
  void add(const dynamics::RigidBody& b, const geometry::TriangleMesh& mesh) {
    Entry e;
    e.friction = b.friction.value_or(0.0);
    e.restitution = b.restitution;
    if (b.shape.type() == collision::Shape::Type::kConvexSet) {
      Eigen::Vector3d moments;
      e.X_BP = principal_frame(b, &moments);
      e.geom = bunny_geom(e.X_BP.inverse(), mesh);
      e.body = dBodyCreate(world_);
      dMass mass;
      dMassSetParameters(&mass, b.mass.mass_kg, 0, 0, 0, moments.x(), moments.y(), moments.z(), 0, 0, 0);
      dBodySetMass(e.body, &mass);
    } else {
      const Eigen::Vector3d size = b.shape.size_m();
      e.geom = dCreateBox(space_, size.x(), size.y(), size.z());
      if (b.motion == dynamics::BodyMotion::kKinematic) {
        e.body = dBodyCreate(world_);
        dBodySetKinematic(e.body);
      }
    }
    const geometry::Pose X_WP = b.X_WB * e.X_BP;
    const Eigen::Quaterniond q(X_WP.linear());
    const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
    if (e.body) {
      dGeomSetBody(e.geom, e.body);
      dBodySetPosition(e.body, X_WP.translation().x(), X_WP.translation().y(), X_WP.translation().z());
      dBodySetQuaternion(e.body, dq);
      if (b.is_dynamic()) {
        const Eigen::Vector3d v = b.v_WBcm_m_s;
        dBodySetLinearVel(e.body, v.x(), v.y(), v.z());
        dBodySetAngularVel(e.body, b.w_WB_rad_s.x(), b.w_WB_rad_s.y(), b.w_WB_rad_s.z());
      }
    } else {
      dGeomSetPosition(e.geom, X_WP.translation().x(), X_WP.translation().y(), X_WP.translation().z());
      dGeomSetQuaternion(e.geom, dq);
    }
    dGeomSetData(e.geom, reinterpret_cast<void*>(entries_.size()));
    entries_.push_back(e);
  }
  static void near_callback(void* data, dGeomID a, dGeomID b) {
    auto* self = static_cast<OdeBunnies*>(data);
    const Entry& ea = self->entries_[reinterpret_cast<std::size_t>(dGeomGetData(a))];
    const Entry& eb = self->entries_[reinterpret_cast<std::size_t>(dGeomGetData(b))];
    const bool dyn_a = ea.body && !dBodyIsKinematic(ea.body), dyn_b = eb.body && !dBodyIsKinematic(eb.body);
    if (!dyn_a && !dyn_b) return;
    dContact contact[kMaxContacts];
    const int n = dCollide(a, b, kMaxContacts, &contact[0].geom, sizeof(dContact));
    const double mu = std::sqrt(ea.friction * eb.friction);
    const double bounce = std::max(ea.restitution, eb.restitution);
    for (int k = 0; k < n; ++k) {
      contact[k].surface.mode = (mu > 0 ? dContactApprox1 : 0) | (bounce > 0 ? dContactBounce : 0);
      contact[k].surface.mu = mu;
      contact[k].surface.bounce = bounce;
      contact[k].surface.bounce_vel = 0.05;  // arphys's restitution threshold
      const dJointID j = dJointCreateContact(self->world_, self->contacts_, &contact[k]);
      dJointAttach(j, dGeomGetBody(a), dGeomGetBody(b));
    }
  }

  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  std::vector<Entry> entries_;
  std::vector<dTriMeshDataID> mesh_data_;
  std::vector<std::vector<double>> vertex_arrays_;  // (each array's data stays put as the outer vector grows)
  std::vector<std::vector<dTriIndex>> index_arrays_;
};

}  // namespace

std::unique_ptr<BunnyPeer> make_ode_bunnies(const BunnyModel& model) { return std::make_unique<OdeBunnies>(model); }

}  // namespace arphys::dyn_bench
