#pragma once
// One scene, several physics engines: the engine-neutral description the dynamics
// benchmark builds once and hands to thin adapters (arphys, Bullet, ODE, MuJoCo), as
// in ../shared/anchors/dyn.md. Peers are used here only.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace arphys::dyn_bench {

struct BenchBody {
  enum class Shape { kPlane, kBox, kSphere } shape = Shape::kBox;
  enum class Motion { kStatic, kKinematic, kDynamic } motion = Motion::kDynamic;
  Eigen::Vector3d half_extents_m = Eigen::Vector3d::Constant(0.1);
  double radius_m = 0.1;
  double mass_kg = 1;
  double friction = 0;     // Coulomb; 0: frictionless
  double restitution = 0;
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();  // a plane: its z = 0 plane, normal +z
  Eigen::Vector3d v_m_s = Eigen::Vector3d::Zero();
};

struct BenchScene {
  std::string name;
  Eigen::Vector3d gravity_m_s2{0, 0, -9.81};
  std::vector<BenchBody> bodies;
};

class Engine {
 public:
  virtual ~Engine() = default;
  virtual std::string name() const = 0;
  virtual void build(const BenchScene& scene, double dt_s) = 0;
  // Kinematic bodies: the pose and velocity they have over the next step.
  virtual void set_kinematic(int body, const Eigen::Isometry3d& X_WB, const Eigen::Vector3d& v_m_s) = 0;
  virtual void step() = 0;
  virtual Eigen::Isometry3d pose(int body) const = 0;
  virtual Eigen::Vector3d velocity(int body) const = 0;
};

// Variants: "arphys" / "arphys-iterative", "bullet", "ode-step" (exact LCP), "ode-quick",
// "mujoco-newton", "mujoco-pgs", "mujoco-cg".
std::unique_ptr<Engine> make_engine(const std::string& variant);
std::vector<std::string> all_engines();

}  // namespace arphys::dyn_bench
