#include "tracker/detection/edge_refinement.hpp"

#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>

namespace arphys::tracking {

namespace {

// Bilinear sample in OpenCV's convention; false outside the image.
bool sample(const cv::Mat& gray, const Eigen::Vector2d& p, double* value) {
  const double x = p.x(), y = p.y();
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= gray.cols || y0 + 1 >= gray.rows) return false;
  const double fx = x - x0, fy = y - y0;
  const uint8_t* r0 = gray.ptr<uint8_t>(y0) + x0;
  const uint8_t* r1 = gray.ptr<uint8_t>(y0 + 1) + x0;
  *value = (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) + fy * ((1 - fx) * r1[0] + fx * r1[1]);
  return true;
}

struct Line {
  Eigen::Vector2d point;
  Eigen::Vector2d direction;
};

}  // namespace

bool refine_corners_on_edges(const cv::Mat& gray, DetectedMarker& marker, double max_shift_px) {
  if (gray.empty() || gray.type() != CV_8UC1) return false;
  const auto& c = marker.corners_px;
  // Signed area tells which side of each edge is inside (the black border).
  double area2 = 0;
  for (int k = 0; k < 4; ++k) {
    const auto& a = c[k];
    const auto& b = c[(k + 1) % 4];
    area2 += a.x() * b.y() - b.x() * a.y();
  }
  if (std::abs(area2) < 16) return false;
  const double side_px = std::sqrt(std::abs(area2) / 2);
  // The black border is one cell of an 8-cell (tag36h11) or 6-cell (4x4) square: stay
  // inside a third of that on either side, and within the pixel that can hold the edge.
  const double reach = std::clamp(side_px / 24.0, 1.0, 3.0);
  const double step = 0.25;

  std::array<Line, 4> lines;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d p0 = c[k], p1 = c[(k + 1) % 4];
    const double length = (p1 - p0).norm();
    if (length < 6) return false;
    const Eigen::Vector2d d = (p1 - p0) / length;
    Eigen::Vector2d outward(d.y(), -d.x());
    if (area2 < 0) outward = -outward;
    std::vector<Eigen::Vector2d> crossings;
    const int samples = static_cast<int>(length);
    for (int i = 0; i <= samples; ++i) {
      const double t = 0.12 + 0.76 * i / std::max(1, samples);
      const Eigen::Vector2d q = p0 + t * (p1 - p0);
      const int n = static_cast<int>(std::round(2 * reach / step));
      std::vector<double> profile(n + 1);
      bool inside = true;
      for (int j = 0; j <= n && inside; ++j) inside = sample(gray, q + (-reach + j * step) * outward, &profile[j]);
      if (!inside) continue;
      const double dark = 0.5 * (profile[0] + profile[1]);
      const double bright = 0.5 * (profile[n] + profile[n - 1]);
      if (bright - dark < 20) continue;
      const double mid = 0.5 * (dark + bright);
      // The crossing nearest the current edge estimate (s = 0).
      double best_s = 1e9;
      for (int j = 0; j < n; ++j) {
        if ((profile[j] - mid) * (profile[j + 1] - mid) > 0 || profile[j + 1] == profile[j]) continue;
        const double s = -reach + (j + (mid - profile[j]) / (profile[j + 1] - profile[j])) * step;
        if (std::abs(s) < std::abs(best_s)) best_s = s;
      }
      if (best_s < 1e8) crossings.push_back(q + best_s * outward);
    }
    if (crossings.size() < 5) return false;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : crossings) mean += p;
    mean /= static_cast<double>(crossings.size());
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto& p : crossings) scatter += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
    lines[k] = {mean, eig.eigenvectors().col(1)};
  }
  std::array<Eigen::Vector2d, 4> refined;
  for (int k = 0; k < 4; ++k) {
    // Corner k joins the edge ending at it (k-1) and the edge starting at it (k).
    const Line& a = lines[(k + 3) % 4];
    const Line& b = lines[k];
    Eigen::Matrix2d A;
    A << a.direction, -b.direction;
    if (std::abs(A.determinant()) < 1e-6) return false;
    const Eigen::Vector2d st = A.lu().solve(b.point - a.point);
    refined[k] = a.point + st.x() * a.direction;
    if ((refined[k] - c[k]).norm() > max_shift_px) return false;
  }
  marker.corners_px = refined;
  return true;
}

}  // namespace arphys::tracking
