// Per-kernel and per-region wall times through Kokkos' tool callbacks: every
// labelled parallel_for/reduce/scan and every profiling region (poisson_solve,
// transpose, fft, halo_exchange) is timed between two fences, so an
// asynchronous backend (CUDA) is timed for the work itself. Also counts the
// deep copies between different memory spaces (host <-> device), which the
// time loop must not do except for the diagnostics' small reductions.
//
// The callbacks fence around every kernel, which slows the step a little:
// the harness times the whole step separately, with the timer detached.
#pragma once
#include <cstdint>
#include <map>
#include <string>

namespace softflow::perf {

struct TimedEntry {
  double seconds = 0;
  long calls = 0;
};

struct TimerReport {
  std::map<std::string, TimedEntry> kernels;
  std::map<std::string, TimedEntry> regions;  // inclusive of the kernels inside
  long cross_space_copies = 0;                // deep copies between memory spaces
  uint64_t cross_space_bytes = 0;
};

class KernelTimer {
 public:
  // registers the callbacks (after Kokkos::initialize); one timer at a time
  KernelTimer();
  ~KernelTimer();  // unregisters them
  KernelTimer(const KernelTimer&) = delete;
  KernelTimer& operator=(const KernelTimer&) = delete;

  void reset();
  TimerReport report() const;
};

}  // namespace softflow::perf
