#include "simulator/collision/broad_phase.hpp"

#include <algorithm>
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

std::vector<std::pair<int, int>> overlapping_pairs(const std::vector<Eigen::AlignedBox3d>& boxes) {
  std::vector<int> order;
  order.reserve(boxes.size());
  double extent_sum = 0;
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i) {
    const Eigen::AlignedBox3d& box = boxes[i];
    if (!takes_part(box)) continue;
    order.push_back(i);
    if (std::isfinite(box.sizes().y())) extent_sum += box.sizes().y();
  }
  // Sweep and prune along x within strips along y about as wide as a box: in a pile
  // spread over the floor, a box's x interval meets hundreds of others, its strips'
  // share of them a tenth (the plain sweep was a tenth of a 1000-box pile's step).
  // A box is in every strip it reaches; a pair is reported in the first strip both
  // are in. Boxes much wider than a strip (a floor, a table) are tested against all.
  const double strip_m = std::max(extent_sum / std::max<std::size_t>(order.size(), 1), 1e-9);
  std::vector<int> narrow, wide;
  double y0 = std::numeric_limits<double>::infinity(), y1 = -y0;
  for (const int i : order) {
    const Eigen::AlignedBox3d& box = boxes[i];
    if (std::isfinite(box.min().y()) && std::isfinite(box.max().y()) && box.sizes().y() <= 16 * strip_m) {
      narrow.push_back(i);
      y0 = std::min(y0, box.min().y());
      y1 = std::max(y1, box.max().y());
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
  if (!narrow.empty()) {
    // (Clusters far apart would make many empty strips: at most four per box.)
    const double width = std::max(strip_m, (y1 - y0) / (4.0 * static_cast<double>(narrow.size())));
    const auto strip = [&](double y) { return static_cast<int>((y - y0) / width); };
    const int strips = strip(y1) + 1;
    std::sort(narrow.begin(), narrow.end(), [&](int a, int b) { return boxes[a].min().x() < boxes[b].min().x(); });
    // The strips' boxes, contiguous and in sweep order (a box's entries follow the
    // x order within each strip; indirect access to the boxes doubled the scan's cost).
    std::vector<int> start(strips + 1, 0);
    for (const int i : narrow)
      for (int s = strip(boxes[i].min().y()); s <= strip(boxes[i].max().y()); ++s) ++start[s + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<int> fill(start.begin(), start.end() - 1);
    std::vector<Eigen::AlignedBox3d> entry_box(start.back());
    std::vector<int> entry_index(start.back());
    for (const int i : narrow)
      for (int s = strip(boxes[i].min().y()); s <= strip(boxes[i].max().y()); ++s) {
        entry_box[fill[s]] = boxes[i];
        entry_index[fill[s]++] = i;
      }
    for (int s = 0; s < strips; ++s)
      for (int k = start[s]; k < start[s + 1]; ++k) {
        const Eigen::AlignedBox3d& a = entry_box[k];
        const double end_x = a.max().x();
        const int first_a = strip(a.min().y());
        for (int l = k + 1; l < start[s + 1] && entry_box[l].min().x() <= end_x; ++l) {
          const Eigen::AlignedBox3d& b = entry_box[l];
          if (a.min().y() <= b.max().y() && b.min().y() <= a.max().y() && a.min().z() <= b.max().z() &&
              b.min().z() <= a.max().z() && std::max(first_a, strip(b.min().y())) == s)
            report(entry_index[k], entry_index[l]);
        }
      }
  }
  // Sorted by two counting passes (second index, then stably the first): linear in the
  // pairs, where a comparison sort of a pile's thousands of pairs cost as much as the sweep.
  std::vector<std::pair<int, int>> by_second(pairs.size());
  std::vector<int> start(boxes.size() + 1);
  const auto counting_pass = [&](const std::vector<std::pair<int, int>>& in, std::vector<std::pair<int, int>>& out,
                                 int std::pair<int, int>::*key) {
    std::fill(start.begin(), start.end(), 0);
    for (const auto& pair : in) ++start[pair.*key + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    for (const auto& pair : in) out[start[pair.*key]++] = pair;
  };
  counting_pass(pairs, by_second, &std::pair<int, int>::second);
  counting_pass(by_second, pairs, &std::pair<int, int>::first);
  return pairs;
}

}  // namespace arphys::collision
