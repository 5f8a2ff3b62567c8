#pragma once
// FCL as a reference for the CCD tests and benchmarks (never used by arphys itself):
// FCL's discrete mesh test drives a dense-sampling ground truth along *our* screw
// paths, and FCL's own continuous collision is run for comparison.
#include <memory>

#include "simulator/geometry/screw_motion.hpp"
#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::ccd_reference {

class FclMesh {
 public:
  explicit FclMesh(const geometry::TriangleMesh& mesh);
  ~FclMesh();
  FclMesh(const FclMesh&) = delete;
  FclMesh& operator=(const FclMesh&) = delete;
  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// FCL's discrete collide (OBBRSS tree, first contact): do the surfaces intersect?
bool fcl_intersects(const FclMesh& A, const geometry::Pose& X_WA, const FclMesh& B, const geometry::Pose& X_WB);

struct ReferenceToi {
  bool hit = false;
  double toi = 1.0;      // first sample found intersecting (after bisection: within `bracket` of it)
  double toi_lo = 1.0;   // last sample found free before it
};

// Ground truth: `samples` uniform times of FCL's discrete test along the screw paths,
// then bisection of the first bracket down to `tolerance`. Misses contacts shorter
// than one sample interval (a grazing touch), which callers must keep in mind.
ReferenceToi sampled_truth(const FclMesh& A, const geometry::ScrewMotion& motion_A, const FclMesh& B,
                           const geometry::ScrewMotion& motion_B, int samples, double tolerance = 1e-9);

// FCL 0.7 continuousCollide with its NAIVE solver (n uniform samples, screw motion type).
ReferenceToi fcl_naive(const FclMesh& A, const geometry::ScrewMotion& motion_A, const FclMesh& B,
                       const geometry::ScrewMotion& motion_B, int samples);

// FCL 0.7 conservative advancement through its working oriented path
// (detail::ConservativeAdvancementImpl; the public continuousCollide CA path misses
// collisions, see docs/ccd.md), on RSS or OBBRSS trees, FCL's ScrewMotion.
enum class FclBoundingVolume { kRss, kObbRss };
ReferenceToi fcl_conservative_advancement(const FclMesh& A, const geometry::ScrewMotion& motion_A, const FclMesh& B,
                                          const geometry::ScrewMotion& motion_B, FclBoundingVolume bv);

}  // namespace arphys::ccd_reference
