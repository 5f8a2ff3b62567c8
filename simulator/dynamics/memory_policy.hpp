#pragma once
// How a process that steps a World asks the C library's allocator to treat the memory a
// step frees. A 1000-box pile's step builds and frees megabytes of contacts and dense
// contact matrices; glibc hands blocks that large back to the kernel when they are freed
// (munmap, or trimming the heap's top), and every page taken again next step is a page
// fault. On the shared 2-core VMs here, keeping them made the pile's first simulated
// second 27 % faster (10.8 -> 7.9 ms a step; docs/dynamics.md). Keeping freed memory for
// reuse, the usual setting of a real-time control loop, costs the process its peak
// footprint instead.
//
// A process-wide setting, so it is for executables (the simulator, simulate, the
// dynamics benchmark, where it holds for every engine in the run), not something the
// library does behind its user's back. No effect outside glibc. Returns whether it took.
namespace arphys::dynamics {

bool keep_freed_memory_for_reuse();

}  // namespace arphys::dynamics
