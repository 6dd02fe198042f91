// Reading a libFuzzer input as a stream of typed values: reads past the end give zeros, so
// every byte string is a valid input and short inputs explore the defaults.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace coral_fuzz {

class FuzzInput {
 public:
  FuzzInput(const uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  template <class T>
  T take() {
    T v{};
    uint8_t buf[sizeof(T)] = {};
    const std::size_t n = pos_ < size_ ? (size_ - pos_ < sizeof(T) ? size_ - pos_ : sizeof(T)) : 0;
    if (n > 0) std::memcpy(buf, data_ + pos_, n);
    pos_ += n;
    std::memcpy(&v, buf, sizeof(T));
    return v;
  }
  uint8_t byte() { return take<uint8_t>(); }
  // An integer in [lo, hi] from one byte.
  int range(int lo, int hi) { return lo + byte() % (hi - lo + 1); }
  std::size_t remaining() const { return pos_ < size_ ? size_ - pos_ : 0; }
  const uint8_t* rest() const { return data_ + (pos_ < size_ ? pos_ : size_); }

 private:
  const uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// Aborts (a crash the fuzzer reports) when a postcondition of the code under test fails.
#define CORAL_FUZZ_CHECK(cond)                                                      \
  do {                                                                              \
    if (!(cond)) {                                                                  \
      std::fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
      std::abort();                                                                 \
    }                                                                               \
  } while (0)

}  // namespace coral_fuzz
