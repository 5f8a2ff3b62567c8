#include "simulator/dynamics/worker_pool.hpp"

#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace arphys::dynamics {

struct WorkerPool::Arena {
  explicit Arena(int threads) : arena(threads) {}
  tbb::task_arena arena;
};

WorkerPool::WorkerPool(int threads) : threads_(threads) {
  if (threads < 1 || threads > 256)
    throw std::invalid_argument("WorkerPool: threads is " + std::to_string(threads) + ", expected 1 to 256");
  if (threads > 1) arena_ = std::make_shared<Arena>(threads);
}

void WorkerPool::for_each(int n, const std::function<void(int)>& f) const {
  // (A handful of items is not worth waking the workers for.)
  if (!arena_ || n < 2) {
    for (int k = 0; k < n; ++k) f(k);
    return;
  }
  arena_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 1), [&](const tbb::blocked_range<int>& range) {
      for (int k = range.begin(); k != range.end(); ++k) f(k);
    });
  });
}

}  // namespace arphys::dynamics
