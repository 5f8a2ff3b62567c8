#include "simulator/collision/broad_phase.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace arphys::collision {

Eigen::AlignedBox3d swept_bounds(const geometry::ScrewMotion& motion, const Eigen::Vector3d& center_B, double radius_m) {
  if (!std::isfinite(radius_m)) {
    const double inf = std::numeric_limits<double>::infinity();
    return Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-inf), Eigen::Vector3d::Constant(inf));
  }
  // Seen along the screw axis u the point moves on a circular arc of the screw's angle
  // theta (<= pi) between its end positions, so it stays within the arc's sagitta
  // (c/2) tan(theta/4) of the chord (c: the chord normal to u); along u it moves
  // linearly. The path is thus inside the parallelogram spanned by that chord and the
  // axial travel, widened by the sagitta: its four corners, widened, bound it. (Closed
  // form; enclosing the path piecewise with interval arithmetic was 6 % of a pile's step.)
  // A large turn is split into pieces of at most half a radian (the same screw, at a
  // fraction of the angle), where the bound stays tight.
  const int pieces = std::max(1, static_cast<int>(std::ceil(motion.angle_rad() / 0.5)));
  const Eigen::Vector3d& u = motion.axis();
  const double tan_quarter = std::tan(0.25 * motion.angle_rad() / pieces);
  Eigen::AlignedBox3d box;
  Eigen::Vector3d p0 = motion.start() * center_B;
  for (int k = 1; k <= pieces; ++k) {
    const Eigen::Vector3d p1 = k == pieces ? Eigen::Vector3d(motion.end() * center_B)
                                           : Eigen::Vector3d(motion.pose_at(static_cast<double>(k) / pieces) * center_B);
    const Eigen::Vector3d axial = (p1 - p0).dot(u) * u;
    const double chord_m = (p1 - p0 - axial).norm();
    // Rounding of the poses and of the screw's own parameters: a relative 1e-12 of the
    // coordinates involved keeps the bound certified.
    const double rounding_m = 1e-12 * (p0.cwiseAbs().maxCoeff() + p1.cwiseAbs().maxCoeff() + chord_m + 1.0);
    const double reach = radius_m + 0.5 * chord_m * tan_quarter + rounding_m;
    for (const Eigen::Vector3d& corner : {p0, p1, Eigen::Vector3d(p0 + axial), Eigen::Vector3d(p1 - axial)}) {
      box.extend(Eigen::Vector3d(corner.array() - reach));
      box.extend(Eigen::Vector3d(corner.array() + reach));
    }
    p0 = p1;
  }
  return box;
}

namespace {

bool overlap(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
  return a.min().x() <= b.max().x() && b.min().x() <= a.max().x() && a.min().y() <= b.max().y() &&
         b.min().y() <= a.max().y() && a.min().z() <= b.max().z() && b.min().z() <= a.max().z();
}

// A box with a NaN coordinate overlaps nothing; in the sweep it would break the order
// (and stop a scan early, hiding pairs). An empty one neither.
bool takes_part(const Eigen::AlignedBox3d& box) {
  return !(box.min().array().isNaN().any() || box.max().array().isNaN().any() || box.isEmpty());
}

}  // namespace

std::vector<std::pair<int, int>> overlapping_pairs_involving(const std::vector<Eigen::AlignedBox3d>& boxes,
                                                             const std::vector<char>& selected) {
  if (selected.size() != boxes.size())
    throw std::invalid_argument("overlapping_pairs_involving: " + std::to_string(selected.size()) + " flags for " +
                                std::to_string(boxes.size()) + " boxes");
  const int n = static_cast<int>(boxes.size());
  std::vector<int> chosen;
  for (int i = 0; i < n; ++i)
    if (selected[i]) chosen.push_back(i);
  std::vector<std::pair<int, int>> pairs;
  if (8 * chosen.size() > boxes.size()) {
    for (const auto& pair : overlapping_pairs(boxes))
      if (selected[pair.first] || selected[pair.second]) pairs.push_back(pair);
    return pairs;
  }
  std::vector<char> part(n);
  for (int i = 0; i < n; ++i) part[i] = takes_part(boxes[i]);
  for (const int i : chosen) {
    if (!part[i]) continue;
    for (int j = 0; j < n; ++j)
      // A pair of two selected boxes is found once, from its first.
      if (j != i && part[j] && (!selected[j] || j > i) && overlap(boxes[i], boxes[j]))
        pairs.emplace_back(std::min(i, j), std::max(i, j));
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<std::pair<int, int>> overlapping_pairs_updated(const std::vector<Eigen::AlignedBox3d>& boxes,
                                                           const std::vector<char>& changed,
                                                           const std::vector<std::pair<int, int>>& before) {
  const std::vector<std::pair<int, int>> added = overlapping_pairs_involving(boxes, changed);
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(before.size() + added.size());
  for (const auto& pair : before)
    if (!changed[pair.first] && !changed[pair.second]) pairs.push_back(pair);
  const std::size_t kept = pairs.size();
  pairs.insert(pairs.end(), added.begin(), added.end());
  std::inplace_merge(pairs.begin(), pairs.begin() + static_cast<std::ptrdiff_t>(kept), pairs.end());
  return pairs;
}

namespace {

// The overlapping pairs among `narrow` (boxes about as wide as mean_extent, within lo..hi):
// sweep and prune along x within cells of a grid over y and z about as wide as a box.
void sweep_cells(const std::vector<Eigen::AlignedBox3d>& boxes, std::vector<int>& narrow, const Eigen::Vector3d& lo,
                 const Eigen::Vector3d& hi, const Eigen::Vector3d& mean_extent,
                 std::vector<std::pair<int, int>>& pairs) {
  const auto report = [&](int i, int j) { pairs.emplace_back(std::min(i, j), std::max(i, j)); };
  // At most about 2 sqrt(n) cells along each axis (clusters far apart would make
  // many empty ones): at most four per box.
  const double per_axis = std::ceil(2.0 * std::sqrt(static_cast<double>(narrow.size())));
  const double width_y = std::max({mean_extent.y(), (hi.y() - lo.y()) / per_axis, 1e-9});
  const double width_z = std::max({mean_extent.z(), (hi.z() - lo.z()) / per_axis, 1e-9});
  const auto cell_y = [&](double y) { return static_cast<int>((y - lo.y()) / width_y); };
  const auto cell_z = [&](double z) { return static_cast<int>((z - lo.z()) / width_z); };
  const int cells_z = cell_z(hi.z()) + 1;
  const int cells = (cell_y(hi.y()) + 1) * cells_z;
  std::sort(narrow.begin(), narrow.end(), [&](int a, int b) { return boxes[a].min().x() < boxes[b].min().x(); });
  // Each box's first cell along y and z (where a pair is reported), and its last.
  std::vector<std::array<int, 4>> span(boxes.size());
  for (const int i : narrow)
    span[i] = {cell_y(boxes[i].min().y()), cell_z(boxes[i].min().z()), cell_y(boxes[i].max().y()),
               cell_z(boxes[i].max().z())};
  // The cells' boxes, contiguous and in sweep order (a box's entries follow the x order
  // within each cell; indirect access to the boxes doubled the scan's cost).
  std::vector<int> start(cells + 1, 0);
  for (const int i : narrow)
    for (int y = span[i][0]; y <= span[i][2]; ++y)
      for (int z = span[i][1]; z <= span[i][3]; ++z) ++start[y * cells_z + z + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int> fill(start.begin(), start.end() - 1);
  std::vector<Eigen::AlignedBox3d> entry_box(start.back());
  std::vector<int> entry_index(start.back());
  for (const int i : narrow)
    for (int y = span[i][0]; y <= span[i][2]; ++y)
      for (int z = span[i][1]; z <= span[i][3]; ++z) {
        const int c = y * cells_z + z;
        entry_box[fill[c]] = boxes[i];
        entry_index[fill[c]++] = i;
      }
  for (int c = 0; c < cells; ++c) {
    const int y = c / cells_z, z = c % cells_z;
    for (int k = start[c]; k < start[c + 1]; ++k) {
      const Eigen::AlignedBox3d& a = entry_box[k];
      const double end_x = a.max().x();
      const std::array<int, 4>& span_a = span[entry_index[k]];
      for (int l = k + 1; l < start[c + 1] && entry_box[l].min().x() <= end_x; ++l) {
        const Eigen::AlignedBox3d& b = entry_box[l];
        if (a.min().y() <= b.max().y() && b.min().y() <= a.max().y() && a.min().z() <= b.max().z() &&
            b.min().z() <= a.max().z()) {
          const std::array<int, 4>& span_b = span[entry_index[l]];
          if (std::max(span_a[0], span_b[0]) == y && std::max(span_a[1], span_b[1]) == z)
            report(entry_index[k], entry_index[l]);
        }
      }
    }
  }
}

// Sorts pairs of indices below n by two counting passes (second index, then stably the
// first): linear in the pairs, where a comparison sort of a pile's thousands of pairs cost
// as much as the sweep.
void sort_pairs(std::vector<std::pair<int, int>>& pairs, int n) {
  std::vector<std::pair<int, int>> by_second(pairs.size());
  std::vector<int> start(n + 1);
  const auto counting_pass = [&](const std::vector<std::pair<int, int>>& in, std::vector<std::pair<int, int>>& out,
                                 int std::pair<int, int>::*key) {
    std::fill(start.begin(), start.end(), 0);
    for (const auto& pair : in) ++start[pair.*key + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    for (const auto& pair : in) out[start[pair.*key]++] = pair;
  };
  counting_pass(pairs, by_second, &std::pair<int, int>::second);
  counting_pass(by_second, pairs, &std::pair<int, int>::first);
}

}  // namespace

std::vector<std::pair<int, int>> overlapping_pairs(const std::vector<Eigen::AlignedBox3d>& boxes) {
  std::vector<int> order;
  order.reserve(boxes.size());
  Eigen::Vector3d extent_sum = Eigen::Vector3d::Zero();
  int finite_count = 0;
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i) {
    const Eigen::AlignedBox3d& box = boxes[i];
    if (!takes_part(box)) continue;
    order.push_back(i);
    if (box.sizes().allFinite()) {
      extent_sum += box.sizes();
      ++finite_count;
    }
  }
  // Sweep and prune along x within cells of a grid over y and z about as wide as a box.
  // A pile spread over the floor and stacked in columns: a box's x interval meets
  // hundreds of others, those in strips along y still its whole column and the next
  // (a strip's sweep was a twentieth of a 1000-box pile's step); a cell's, its
  // neighbours. A box is in every cell it reaches; a pair is reported in the first cell
  // both are in. Boxes much larger than a cell (a floor, a table) are tested against all.
  const Eigen::Vector3d mean_extent = extent_sum / std::max(finite_count, 1);
  std::vector<int> narrow, wide;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const int i : order) {
    const Eigen::AlignedBox3d& box = boxes[i];
    const bool small = box.sizes().allFinite() && box.sizes().y() <= 16 * mean_extent.y() + 1e-9 &&
                       box.sizes().z() <= 16 * mean_extent.z() + 1e-9;
    if (small) {
      narrow.push_back(i);
      lo = lo.cwiseMin(box.min());
      hi = hi.cwiseMax(box.max());
    } else {
      wide.push_back(i);
    }
  }
  std::vector<std::pair<int, int>> pairs;
  const auto report = [&](int i, int j) { pairs.emplace_back(std::min(i, j), std::max(i, j)); };
  for (std::size_t w = 0; w < wide.size(); ++w) {
    for (std::size_t v = w + 1; v < wide.size(); ++v)
      if (overlap(boxes[wide[w]], boxes[wide[v]])) report(wide[w], wide[v]);
    for (const int i : narrow)
      if (overlap(boxes[wide[w]], boxes[i])) report(wide[w], i);
  }
  if (!narrow.empty()) sweep_cells(boxes, narrow, lo, hi, mean_extent, pairs);
  sort_pairs(pairs, static_cast<int>(boxes.size()));
  return pairs;
}

}  // namespace arphys::collision
