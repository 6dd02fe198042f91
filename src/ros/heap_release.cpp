// glibc-specific on purpose, and only here: malloc_trim is a GNU extension (glibc >= 2.8 trims
// every arena, not only the main one). Other C libraries get a no-op.
#include "coral_introspection/ros/heap_release.hpp"

#include <cstdlib>  // defines __GLIBC__ (features.h) on glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace coral_introspection {
namespace ros_adapters {

bool releaseFreeHeap() {
#if defined(__GLIBC__)
  // Pad 0: keep nothing at the top of the main heap. Free chunks of the other arenas are
  // released page-wise with madvise(MADV_DONTNEED); their address space stays reserved.
  malloc_trim(0);
  return true;
#else
  return false;
#endif
}

}  // namespace ros_adapters
}  // namespace coral_introspection
