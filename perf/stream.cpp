#include "stream.hpp"

#include <algorithm>
#include <chrono>

#include "types.hpp"

namespace softflow::perf {

namespace {
size_t elements_for(size_t bytes) { return std::max<size_t>(bytes / sizeof(Real), 1024); }
}  // namespace

StreamBench::StreamBench(size_t bytes_per_array)
    : a_("stream_a", elements_for(bytes_per_array)),
      b_("stream_b", elements_for(bytes_per_array)),
      c_("stream_c", elements_for(bytes_per_array)) {
  Kokkos::deep_copy(a_, 1.0);
  Kokkos::deep_copy(b_, 2.0);
  Kokkos::deep_copy(c_, 0.5);
}

Bandwidth StreamBench::measure(int reps) {
  using Clock = std::chrono::steady_clock;
  using Range = Kokkos::RangePolicy<ExecSpace>;
  auto a = a_, b = b_, c = c_;
  const long n = long(a.extent(0));
  const Real s = 0.5;
  // (no kernel inside a helper lambda: nvcc forbids nested extended lambdas)
  double tc = 1e300, tt = 1e300;
  for (int r = 0; r < reps; ++r) {
    Kokkos::fence("stream_before");
    auto t0 = Clock::now();
    Kokkos::parallel_for(
        "stream_copy", Range(0, n), KOKKOS_LAMBDA(long i) { b(i) = a(i); });
    Kokkos::fence("stream_after");
    tc = std::min(tc, std::chrono::duration<double>(Clock::now() - t0).count());
    t0 = Clock::now();
    Kokkos::parallel_for(
        "stream_triad", Range(0, n), KOKKOS_LAMBDA(long i) { a(i) = b(i) + s * c(i); });
    Kokkos::fence("stream_after");
    tt = std::min(tt, std::chrono::duration<double>(Clock::now() - t0).count());
  }
  const double bytes = double(n) * sizeof(Real);
  return {2 * bytes / tc, 3 * bytes / tt};
}

}  // namespace softflow::perf
