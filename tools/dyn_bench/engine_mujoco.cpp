#include <mujoco/mujoco.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "tools/dyn_bench/engine.hpp"

namespace arphys::dyn_bench {
namespace {

// MuJoCo 2.2.2 as the anchor ran it: Euler, 100 iterations, tolerance 1e-8, pyramidal
// cone, default solref/solimp, condim 1 frictionless and 3 with friction; kinematic
// bodies are mocap bodies. The model is written as MJCF and loaded from a file.
class MujocoEngine : public Engine {
 public:
  explicit MujocoEngine(std::string solver) : solver_(std::move(solver)) {}
  ~MujocoEngine() override {
    if (data_) mj_deleteData(data_);
    if (model_) mj_deleteModel(model_);
  }
  std::string name() const override { return "mujoco-" + solver_; }
  void build(const BenchScene& scene, double dt_s) override {
    std::ostringstream xml;
    const std::string solver = solver_ == "newton" ? "Newton" : solver_ == "pgs" ? "PGS" : "CG";
    xml << "<mujoco><option timestep=\"" << dt_s << "\" gravity=\"" << scene.gravity_m_s2.transpose()
        << "\" integrator=\"Euler\" iterations=\"100\" tolerance=\"1e-8\" cone=\"pyramidal\" solver=\"" << solver
        << "\"/><size nconmax=\"" << 20 * scene.bodies.size() + 100 << "\" njmax=\"" << 80 * scene.bodies.size() + 400
        << "\"/><worldbody>";
    int index = 0;
    for (const BenchBody& b : scene.bodies) {
      const Eigen::Quaterniond q(b.X_WB.linear());
      const Eigen::Vector3d& p = b.X_WB.translation();
      std::ostringstream geom;
      const int condim = b.friction > 0 ? 3 : 1;
      geom << "<geom condim=\"" << condim << "\" friction=\"" << b.friction << " 0.005 0.0001\" ";
      if (b.shape == BenchBody::Shape::kPlane) {
        geom << "type=\"plane\" size=\"0 0 1\"/>";
        xml << "<body pos=\"" << p.transpose() << "\" quat=\"" << q.w() << " " << q.x() << " " << q.y() << " " << q.z()
            << "\">" << geom.str() << "</body>";
      } else {
        if (b.shape == BenchBody::Shape::kBox) {
          geom << "type=\"box\" size=\"" << b.half_extents_m.transpose() << "\" mass=\"" << b.mass_kg << "\"/>";
        } else {
          geom << "type=\"sphere\" size=\"" << b.radius_m << "\" mass=\"" << b.mass_kg << "\"/>";
        }
        const bool mocap = b.motion == BenchBody::Motion::kKinematic;
        xml << "<body name=\"b" << index << "\" pos=\"" << p.transpose() << "\" quat=\"" << q.w() << " " << q.x() << " "
            << q.y() << " " << q.z() << "\"" << (mocap ? " mocap=\"true\"" : "") << ">"
            << (b.motion == BenchBody::Motion::kDynamic ? "<freejoint/>" : "") << geom.str() << "</body>";
      }
      ++index;
    }
    xml << "</worldbody></mujoco>";
    const std::string path = "/tmp/arphys_dyn_bench_" + std::to_string(getpid()) + ".xml";
    std::ofstream(path) << xml.str();
    char error[1000] = "";
    model_ = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
    std::remove(path.c_str());
    if (!model_) throw std::runtime_error(std::string("MuJoCo: ") + error);
    data_ = mj_makeData(model_);
    body_of_.clear();
    for (int i = 0; i < index; ++i) body_of_.push_back(mj_name2id(model_, mjOBJ_BODY, ("b" + std::to_string(i)).c_str()));
    // Initial velocities of free bodies.
    for (int i = 0; i < index; ++i) {
      const BenchBody& b = scene.bodies[i];
      if (b.motion != BenchBody::Motion::kDynamic || body_of_[i] < 0) continue;
      const int dof = model_->body_dofadr[body_of_[i]];
      for (int k = 0; k < 3; ++k) data_->qvel[dof + k] = b.v_m_s[k];
    }
    mj_forward(model_, data_);
  }
  void set_kinematic(int i, const Eigen::Isometry3d& X, const Eigen::Vector3d&) override {
    const int mocap = model_->body_mocapid[body_of_[i]];
    const Eigen::Quaterniond q(X.linear());
    for (int k = 0; k < 3; ++k) data_->mocap_pos[3 * mocap + k] = X.translation()[k];
    data_->mocap_quat[4 * mocap + 0] = q.w();
    data_->mocap_quat[4 * mocap + 1] = q.x();
    data_->mocap_quat[4 * mocap + 2] = q.y();
    data_->mocap_quat[4 * mocap + 3] = q.z();
  }
  void step() override { mj_step(model_, data_); }
  Eigen::Isometry3d pose(int i) const override {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    const int b = body_of_[i];
    if (b < 0) return X;
    X.translation() = Eigen::Vector3d(data_->xpos[3 * b], data_->xpos[3 * b + 1], data_->xpos[3 * b + 2]);
    const double* q = data_->xquat + 4 * b;
    X.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
    return X;
  }
  Eigen::Vector3d velocity(int i) const override {
    const int b = body_of_[i];
    if (b < 0 || model_->body_dofnum[b] == 0) return Eigen::Vector3d::Zero();
    const int dof = model_->body_dofadr[b];
    return {data_->qvel[dof], data_->qvel[dof + 1], data_->qvel[dof + 2]};
  }

 private:
  std::string solver_;
  mjModel* model_ = nullptr;
  mjData* data_ = nullptr;
  std::vector<int> body_of_;
};

}  // namespace

std::unique_ptr<Engine> make_mujoco_engine(const std::string& solver) { return std::make_unique<MujocoEngine>(solver); }

}  // namespace arphys::dyn_bench
