// MuJoCo 2.2.2 on the bunny scenes, as the dynamics benchmark's anchor runs it (Euler, 100
// iterations, tolerance 1e-8, pyramidal cone, Newton, default solref/solimp, condim 3 with
// friction): each bunny a free body with the bunny's mass and inertia and one mesh geom per
// piece (MuJoCo collides a mesh as its convex hull: the pieces are hulls already), the
// table a box of the world body, the tracked box a mocap body. MuJoCo has no restitution.
#include <mujoco/mujoco.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "tools/dyn_bench/bunny_peer.hpp"

namespace arphys::dyn_bench {
namespace {

std::string pose_attributes(const geometry::Pose& X) {
  const Eigen::Quaterniond q(X.linear());
  std::ostringstream s;
  s << "pos=\"" << X.translation().transpose() << "\" quat=\"" << q.w() << " " << q.x() << " " << q.y() << " " << q.z()
    << "\"";
  return s.str();
}

// The model as MJCF: the pieces' meshes once, as assets, and the bodies in scene order.
std::string mjcf(const BunnyModel& model, double dt_s, std::vector<std::string>* names) {
  std::ostringstream xml;
  xml.precision(17);
  xml << "<mujoco><option timestep=\"" << dt_s << "\" gravity=\"" << model.gravity_m_s2.transpose()
      << "\" integrator=\"Euler\" iterations=\"100\" tolerance=\"1e-8\" cone=\"pyramidal\" solver=\"Newton\"/>"
      << "<size nconmax=\"" << 20 * model.bodies.size() + 100 << "\" njmax=\"" << 80 * model.bodies.size() + 400
      << "\"/><asset>";
  const dynamics::RigidBody* bunny = nullptr;
  for (const dynamics::RigidBody& b : model.bodies)
    if (b.shape.type() == collision::Shape::Type::kConvexSet) bunny = &b;
  const int pieces = bunny ? static_cast<int>(bunny->shape.convex()->pieces.size()) : 0;
  for (int k = 0; k < pieces; ++k) {
    xml << "<mesh name=\"piece" << k << "\" vertex=\"";
    for (const Eigen::Vector3d& v : bunny->shape.convex()->pieces[k].vertices_m()) xml << v.transpose() << " ";
    xml << "\"/>";
  }
  xml << "</asset><worldbody>";
  for (std::size_t i = 0; i < model.bodies.size(); ++i) {
    const dynamics::RigidBody& b = model.bodies[i];
    const std::string name = "b" + std::to_string(i);
    names->push_back(name);
    const double mu = b.friction.value_or(0.0);
    std::ostringstream geom_common;
    geom_common << "condim=\"" << (mu > 0 ? 3 : 1) << "\" friction=\"" << mu << " 0.005 0.0001\"";
    if (b.shape.type() == collision::Shape::Type::kBox) {
      const Eigen::Vector3d half = 0.5 * b.shape.size_m();
      const bool mocap = b.motion == dynamics::BodyMotion::kKinematic;
      xml << "<body name=\"" << name << "\" " << pose_attributes(b.X_WB) << (mocap ? " mocap=\"true\"" : "") << ">"
          << "<geom type=\"box\" size=\"" << half.transpose() << "\" " << geom_common.str() << "/></body>";
      continue;
    }
    Eigen::Vector3d moments;
    const geometry::Pose X_BP = principal_frame(b, &moments);
    xml << "<body name=\"" << name << "\" " << pose_attributes(b.X_WB) << "><freejoint/><inertial "
        << pose_attributes(X_BP) << " mass=\"" << b.mass.mass_kg << "\" diaginertia=\"" << moments.transpose() << "\"/>";
    for (int k = 0; k < pieces; ++k) xml << "<geom type=\"mesh\" mesh=\"piece" << k << "\" " << geom_common.str() << "/>";
    xml << "</body>";
  }
  xml << "</worldbody></mujoco>";
  return xml.str();
}

class MujocoBunnies : public BunnyPeer {
 public:
  MujocoBunnies(const BunnyModel& model, double dt_s) {
    std::vector<std::string> names;
    const std::string path = "/tmp/arphys_bunnies_mujoco_" + std::to_string(getpid()) + ".xml";
    std::ofstream(path) << mjcf(model, dt_s, &names);
    char error[1000] = "";
    model_ = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
    std::remove(path.c_str());
    if (!model_) throw std::runtime_error(std::string("MuJoCo: ") + error);
    data_ = mj_makeData(model_);
    for (const std::string& name : names) body_of_.push_back(mj_name2id(model_, mjOBJ_BODY, name.c_str()));
    for (std::size_t i = 0; i < model.bodies.size(); ++i) {
      const dynamics::RigidBody& b = model.bodies[i];
      if (!b.is_dynamic()) continue;
      // A free joint's velocity: the body origin's linear velocity (world) and the angular one (body frame).
      const int dof = model_->body_dofadr[body_of_[i]];
      const Eigen::Vector3d v = b.origin_velocity();
      const Eigen::Vector3d w_B = b.X_WB.linear().transpose() * b.w_WB_rad_s;
      for (int k = 0; k < 3; ++k) {
        data_->qvel[dof + k] = v[k];
        data_->qvel[dof + 3 + k] = w_B[k];
      }
    }
    mj_forward(model_, data_);
  }
  ~MujocoBunnies() override {
    if (data_) mj_deleteData(data_);
    if (model_) mj_deleteModel(model_);
  }
  void set_kinematic(int i, const geometry::Pose& X_WB, const Eigen::Vector3d&) override {
    const int mocap = model_->body_mocapid[body_of_[i]];
    const Eigen::Quaterniond q(X_WB.linear());
    for (int k = 0; k < 3; ++k) data_->mocap_pos[3 * mocap + k] = X_WB.translation()[k];
    const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
    for (int k = 0; k < 4; ++k) data_->mocap_quat[4 * mocap + k] = wxyz[k];
  }
  void step(double) override { mj_step(model_, data_); }
  bool diverged() const override { return data_->warning[mjWARN_BADQACC].number > 0; }
  geometry::Pose pose(int i) const override {
    geometry::Pose X = geometry::Pose::Identity();
    const int b = body_of_[i];
    X.translation() = Eigen::Vector3d(data_->xpos[3 * b], data_->xpos[3 * b + 1], data_->xpos[3 * b + 2]);
    const double* q = data_->xquat + 4 * b;
    X.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    return X;
  }

 private:
  mjModel* model_ = nullptr;
  mjData* data_ = nullptr;
  std::vector<int> body_of_;
};

}  // namespace

std::unique_ptr<BunnyPeer> make_mujoco_bunnies(const BunnyModel& model, double dt_s) {
  return std::make_unique<MujocoBunnies>(model, dt_s);
}

}  // namespace arphys::dyn_bench
