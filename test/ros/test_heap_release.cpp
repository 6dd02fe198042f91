// releaseFreeHeap gives freed memory of another thread's malloc arena back to the system
// (the case that kept the Oxford soak's RSS 8 % up), and HeapReleaseTimer limits its rate.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <thread>
#include <vector>

#include "coral_introspection/ros/heap_release.hpp"

using coral_introspection::ros_adapters::HeapReleaseTimer;
using coral_introspection::ros_adapters::releaseFreeHeap;

namespace {

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CORAL_HEAP_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define CORAL_HEAP_ASAN 1
#endif

#if !defined(CORAL_HEAP_ASAN) && defined(__GLIBC__)
// Resident set size of this process [bytes] (/proc/self/statm, second field in pages).
double rssBytes() {
  std::ifstream f("/proc/self/statm");
  double size = 0.0, resident = 0.0;
  f >> size >> resident;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE));
}
#endif

}  // namespace

TEST(HeapRelease, ReturnsFreedImagesOfAnotherThreadsArena) {
#if defined(CORAL_HEAP_ASAN) || !defined(__GLIBC__)
  GTEST_SKIP() << "needs glibc's own allocator (ASan replaces it)";
#else
  constexpr std::size_t kImage = 400 * 3779;  // one Oxford polar image
  constexpr int kImages = 12;
  std::vector<void*> keep;  // small blocks between the images stay allocated
  double before_release = 0.0;
  std::thread t([&] {
    // The first freed mmapped image raises glibc's mmap threshold above its size: later
    // images come from this thread's heap, as in a long-running nodelet manager.
    std::free(std::memset(std::malloc(kImage), 1, kImage));
    std::vector<void*> images;
    for (int i = 0; i < kImages; ++i) {
      images.push_back(std::memset(std::malloc(kImage), 1, kImage));
      keep.push_back(std::malloc(64));  // no image merges with its neighbour or the top
    }
    for (void* p : images) std::free(p);
    before_release = rssBytes();
  });
  t.join();
  ASSERT_TRUE(releaseFreeHeap());
  const double released = before_release - rssBytes();
  for (void* p : keep) std::free(p);
  // The images are free but resident until released; at least 10 of the 12 come back.
  EXPECT_GT(released, 10.0 * kImage) << "released " << released / 1e6 << " MB";
#endif
}

TEST(HeapRelease, TimerAllowsOneReleasePerInterval) {
  HeapReleaseTimer t;
  EXPECT_TRUE(t.due(100.0, 10.0));  // the first scan
  EXPECT_FALSE(t.due(105.0, 10.0));
  EXPECT_FALSE(t.due(109.9, 10.0));
  EXPECT_TRUE(t.due(110.0, 10.0));
  EXPECT_FALSE(t.due(115.0, 10.0));
  EXPECT_TRUE(t.due(115.0, 5.0));  // a shorter interval applies at once
  HeapReleaseTimer off;
  EXPECT_FALSE(off.due(0.0, 0.0));
  EXPECT_FALSE(off.due(1e6, 0.0));
}
