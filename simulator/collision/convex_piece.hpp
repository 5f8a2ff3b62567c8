#pragma once
// A convex polyhedron of a body's collision model (docs/method.md section 4: model no more than a
// scene needs): a dynamic concave body collides as a few convex pieces, whose contacts
// come from separating axes with signed depths, not from every triangle pair of a scan.
// A piece is built from its closed hull mesh and refused, with the reason, when it is
// not one.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "simulator/geometry/triangle_mesh.hpp"

namespace arphys::collision {

class CollisionMesh;

class ConvexPiece {
 public:
  struct Face {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, outward, body frame
    double offset_m = 0;       // normal . x on the face
    std::vector<int> polygon;  // vertex indices, counter-clockwise seen from outside
  };
  struct Edge {
    int v0 = -1, v1 = -1;
    int face_left = -1, face_right = -1;  // the faces on either side (Gauss map arc ends)
  };

  // Throws std::invalid_argument with the reason (empty, non-finite, open, not
  // convex, degenerate) when the mesh is not the closed, convex, non-flat surface of a
  // polyhedron. Coplanar triangles are merged into polygon faces.
  explicit ConvexPiece(geometry::TriangleMesh hull);

  const std::vector<Eigen::Vector3d>& vertices_m() const { return hull_.vertices_m; }
  const std::vector<Face>& faces() const { return faces_; }
  const std::vector<Edge>& edges() const { return edges_; }
  const geometry::TriangleMesh& hull() const { return hull_; }
  const Eigen::Vector3d& centroid_m() const { return centroid_m_; }
  // Radius about the centroid containing every vertex.
  double radius_m() const { return radius_m_; }
  // The box of its vertices (body frame).
  const Eigen::AlignedBox3d& box_m() const { return box_m_; }
  // Half the smallest width over the face normals: no point moving less than half of
  // it can pass through the piece.
  double half_thickness_m() const { return half_thickness_m_; }
  double volume_m3() const { return volume_m3_; }
  // The vertex furthest along direction d (body frame).
  int support(const Eigen::Vector3d& d) const;

 private:
  geometry::TriangleMesh hull_;
  std::vector<Face> faces_;
  std::vector<Edge> edges_;
  Eigen::Vector3d centroid_m_ = Eigen::Vector3d::Zero();
  Eigen::AlignedBox3d box_m_;
  double radius_m_ = 0, half_thickness_m_ = 0, volume_m3_ = 0;
};

// A lower bound on the distance between two pieces from their boxes (a: A's frame, b: B's
// frame, X_AB: B in A): the largest gap along the boxes' six face axes (0 or less: the
// boxes overlap along every one). A few dozen flops, where GJK takes a few support searches.
double box_gap_lower_bound_m(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b, const Eigen::Isometry3d& X_AB);

// A body's collision model as convex pieces (body frame), with the union of their hull
// triangles as one mesh for the queries that take meshes (the CCD, pairs with a mesh).
struct ConvexSet {
  std::vector<ConvexPiece> pieces;
  std::shared_ptr<const CollisionMesh> hulls;  // every piece's hull triangles, one closed mesh each
  std::vector<std::shared_ptr<const CollisionMesh>> piece_hulls;  // each piece's alone, by piece
  double half_thickness_m = 0;                 // the thinnest piece's (ConvexPiece::half_thickness_m)
};

// Reads a convex-piece file (an OBJ with one object per piece, written by
// tools/models/convex-decompose) scaled by `scale`; throws std::invalid_argument naming the
// file, the piece (0-based, in file order) and the reason for a piece that is not convex.
std::shared_ptr<const ConvexSet> load_convex_set(const std::string& path,
                                                 const Eigen::Vector3d& scale = Eigen::Vector3d::Ones());
// The set of these pieces (each already validated).
std::shared_ptr<const ConvexSet> make_convex_set(std::vector<ConvexPiece> pieces);

}  // namespace arphys::collision
