// The machine's memory bandwidth, measured in the same run as the kernels it
// is compared with: STREAM's copy (b = a) and triad (a = b + s c) as Kokkos
// kernels in the default execution space, on arrays far larger than the
// caches. Bytes counted as STREAM does: 2 and 3 Reals per element.
#pragma once
#include "types.hpp"

namespace softflow::perf {

struct Bandwidth {
  double copy = 0;  // bytes per second, best of the repetitions
  double triad = 0;
};

class StreamBench {
 public:
  explicit StreamBench(size_t bytes_per_array);
  Bandwidth measure(int reps);  // allocation-free; fenced
  size_t elements() const { return a_.extent(0); }

 private:
  Array1 a_, b_, c_;
};

}  // namespace softflow::perf
