// Giving the allocator's free memory back to the system from a long-running nodelet.
//
// Why: glibc serves each thread from its own malloc arena and, once a large block (an
// Oxford polar image is 1.4 MB) has been freed, raises its mmap threshold above that size,
// so later images come from the heap of whichever thread (roscpp's, the manager's callback
// threads, the worker) allocates them. Each heap keeps the most images it ever held at once:
// RSS rises in image-sized steps when scheduling lets images pile up and never comes back
// (+8 % over a 30-minute Oxford soak, doc/testing.md). This happens in any nodelet manager,
// so it is handled in code rather than with MALLOC_MMAP_THRESHOLD_ in a launch file (which
// maps and faults in every image afresh: ~800 page faults and ~10 ms of kernel time per
// Oxford scan). It releases part of it only (see releaseFreeHeap).
#pragma once

namespace coral_introspection {
namespace ros_adapters {

// Returns the whole free pages of every malloc arena's free lists and the top of the main
// heap to the system (glibc malloc_trim(0)). Not the free top chunk of the other threads'
// arenas: glibc trims those only at a free in that arena (up to about 2 images stay per
// arena; doc/testing.md, soak run 3).
// Returns false where that is not available (non-glibc C library): then it does nothing.
// Cost: a walk over the free lists of all arenas, then page faults when the released pages
// are used again; call it rarely (HeapReleaseTimer), never per allocation.
bool releaseFreeHeap();

// Rate limit of releaseFreeHeap: due() is true at most once per `interval_s` seconds of
// the given clock (seconds, monotonic); interval 0 = never.
class HeapReleaseTimer {
 public:
  bool due(double now_s, double interval_s) {
    if (interval_s <= 0.0) return false;
    if (has_last_ && now_s - last_ < interval_s) return false;
    last_ = now_s;
    has_last_ = true;
    return true;
  }

 private:
  double last_ = 0.0;
  bool has_last_ = false;
};

}  // namespace ros_adapters
}  // namespace coral_introspection
