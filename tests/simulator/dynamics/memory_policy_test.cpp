#include "simulator/dynamics/memory_policy.hpp"

#include <gtest/gtest.h>

#include <vector>

#include <cstdlib>  // (defines __GLIBC__ under glibc)

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#if defined(__SANITIZE_ADDRESS__)
#define ARPHYS_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ARPHYS_UNDER_ASAN 1
#endif
#endif

namespace arphys::dynamics {
namespace {

#if defined(__GLIBC__)
// Free bytes the allocator holds for reuse (not handed back to the kernel).
std::size_t held_free_bytes() { return mallinfo2().fordblks; }

TEST(MemoryPolicy, AFreedStepSizedBlockIsKeptForTheNextStep) {
  constexpr std::size_t kBlock_bytes = 8 << 20;  // a 1000-box pile's contacts and matrices
#if defined(ARPHYS_UNDER_ASAN)
  GTEST_SKIP() << "AddressSanitizer's allocator ignores mallopt";
#endif
  // (With glibc's defaults, in a fresh process, a block this large is mmapped and
  // unmapped when freed: nothing of it is held.)
  ASSERT_TRUE(keep_freed_memory_for_reuse());
  {
    std::vector<char> block(kBlock_bytes, 1);
  }
  EXPECT_GE(held_free_bytes(), kBlock_bytes);
  // ... and the next block of that size reuses it: the allocator takes nothing new from the kernel.
  const std::size_t arena_bytes = mallinfo2().arena;
  {
    std::vector<char> block(kBlock_bytes, 1);
  }
  EXPECT_EQ(mallinfo2().arena, arena_bytes);
}
#endif

}  // namespace
}  // namespace arphys::dynamics
