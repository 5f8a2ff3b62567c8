#include "tools/ccd_bench/fcl_reference.hpp"

#include <fcl/fcl.h>
#include <fcl/narrowphase/detail/conservative_advancement_func_matrix.h>

namespace arphys::ccd_reference {

struct FclMesh::Impl {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> model;
  std::shared_ptr<fcl::BVHModel<fcl::RSSd>> rss_model;
};

FclMesh::FclMesh(const geometry::TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  std::vector<fcl::Vector3d> vertices(mesh.vertices_m.begin(), mesh.vertices_m.end());
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  impl_->model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  impl_->model->beginModel();
  impl_->model->addSubModel(vertices, triangles);
  impl_->model->endModel();
  impl_->rss_model = std::make_shared<fcl::BVHModel<fcl::RSSd>>();
  impl_->rss_model->beginModel();
  impl_->rss_model->addSubModel(vertices, triangles);
  impl_->rss_model->endModel();
}
FclMesh::~FclMesh() = default;

bool fcl_intersects(const FclMesh& A, const geometry::Pose& X_WA, const FclMesh& B, const geometry::Pose& X_WB) {
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl::collide(A.impl().model.get(), X_WA, B.impl().model.get(), X_WB, request, result);
  return result.isCollision();
}

ReferenceToi sampled_truth(const FclMesh& A, const geometry::ScrewMotion& motion_A, const FclMesh& B,
                           const geometry::ScrewMotion& motion_B, int samples, double tolerance) {
  auto hit_at = [&](double t) { return fcl_intersects(A, motion_A.pose_at(t), B, motion_B.pose_at(t)); };
  ReferenceToi out;
  if (hit_at(0.0)) return {true, 0.0, 0.0};
  double free_t = 0;
  for (int k = 1; k <= samples; ++k) {
    const double t = static_cast<double>(k) / samples;
    if (!hit_at(t)) {
      free_t = t;
      continue;
    }
    double lo = free_t, hi = t;
    while (hi - lo > tolerance) {
      const double mid = 0.5 * (lo + hi);
      (hit_at(mid) ? hi : lo) = mid;
    }
    return {true, hi, lo};
  }
  return out;
}

ReferenceToi fcl_naive(const FclMesh& A, const geometry::ScrewMotion& motion_A, const FclMesh& B,
                       const geometry::ScrewMotion& motion_B, int samples) {
  fcl::ContinuousCollisionRequestd request(samples, 1.0 / samples, fcl::CCDM_SCREW, fcl::GST_LIBCCD, fcl::CCDC_NAIVE);
  fcl::ContinuousCollisionResultd result;
  fcl::continuousCollide(A.impl().model.get(), motion_A.start(), motion_A.end(), B.impl().model.get(),
                         motion_B.start(), motion_B.end(), request, result);
  ReferenceToi out;
  out.hit = result.is_collide;
  out.toi = out.toi_lo = result.is_collide ? result.time_of_contact : 1.0;
  return out;
}

ReferenceToi fcl_conservative_advancement(const FclMesh& A, const geometry::ScrewMotion& motion_A, const FclMesh& B,
                                          const geometry::ScrewMotion& motion_B, FclBoundingVolume bv) {
  fcl::ScrewMotion<double> screw_A(motion_A.start(), motion_A.end()), screw_B(motion_B.start(), motion_B.end());
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  double toc = 1.0;
  bool hit = false;
  if (bv == FclBoundingVolume::kRss) {
    hit = fcl::detail::ConservativeAdvancementImpl<double, fcl::BVHModel<fcl::RSSd>, fcl::detail::GJKSolver_libccd<double>>::run(
        *A.impl().rss_model, &screw_A, *B.impl().rss_model, &screw_B, nullptr, request, result, toc);
  } else {
    hit = fcl::detail::ConservativeAdvancementImpl<double, fcl::BVHModel<fcl::OBBRSSd>, fcl::detail::GJKSolver_libccd<double>>::run(
        *A.impl().model, &screw_A, *B.impl().model, &screw_B, nullptr, request, result, toc);
  }
  ReferenceToi out;
  out.hit = hit;
  out.toi = out.toi_lo = hit ? toc : 1.0;
  return out;
}

}  // namespace arphys::ccd_reference
