#pragma once
// A fixed number of threads for a step's per-pair work (contact manifolds, sweeps, end
// checks), on a TBB arena of its own. Each index's result goes to its own slot and is
// merged in index order afterwards, so a step computes the same thing whatever the
// thread count or the scheduling (the simulate CSV is byte for byte the same).
#include <functional>
#include <memory>

namespace arphys::dynamics {

class WorkerPool {
 public:
  // threads >= 1 (std::invalid_argument naming the value otherwise); 1 runs inline.
  explicit WorkerPool(int threads = 1);
  int threads() const { return threads_; }
  // Calls f(k) once for every k in [0, n); returns when all are done. An exception from
  // f is rethrown here (the first one, when several throw).
  void for_each(int n, const std::function<void(int)>& f) const;

 private:
  struct Arena;
  int threads_ = 1;
  std::shared_ptr<Arena> arena_;  // (shared: a World is copyable; the arena holds no step state)
};

}  // namespace arphys::dynamics
