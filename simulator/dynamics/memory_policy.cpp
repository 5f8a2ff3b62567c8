#include "simulator/dynamics/memory_policy.hpp"

#include <cstdlib>  // (defines __GLIBC__ under glibc)

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace arphys::dynamics {

bool keep_freed_memory_for_reuse() {
#if defined(__GLIBC__)
  // Blocks up to 32 MiB (glibc's largest mmap threshold) come from the heap, not from
  // mmap, and the heap's free top is kept up to 1 GiB instead of trimmed at 128 KiB.
  constexpr int kHeapBlocksUpTo_bytes = 32 << 20;
  constexpr int kKeepFreeTopUpTo_bytes = 1 << 30;
  return mallopt(M_MMAP_THRESHOLD, kHeapBlocksUpTo_bytes) == 1 && mallopt(M_TRIM_THRESHOLD, kKeepFreeTopUpTo_bytes) == 1;
#else
  return false;
#endif
}

}  // namespace arphys::dynamics
