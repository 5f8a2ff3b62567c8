#pragma once
// Disjoint sets over 0 .. n-1 (union-find with path halving): bodies coupled by contacts
// into islands, by contacts or overlapping sweeps into groups. Each set is represented
// by its smallest member, so a set's name does not depend on the order of the joins.
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace arphys::dynamics {

class DisjointSets {
 public:
  explicit DisjointSets(int n) : parent_(n < 0 ? 0 : n) {
    if (n < 0) throw std::invalid_argument("DisjointSets: negative size " + std::to_string(n));
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  // The smallest member of x's set. (Iterative: a recursive find through std::function
  // costs a few percent of a 1000-box pile's step.)
  int find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void join(int a, int b) {
    a = find(a);
    b = find(b);
    if (a > b) std::swap(a, b);
    parent_[b] = a;
  }
  int size() const { return static_cast<int>(parent_.size()); }

 private:
  std::vector<int> parent_;
};

}  // namespace arphys::dynamics
