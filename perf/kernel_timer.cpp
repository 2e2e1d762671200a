#include "kernel_timer.hpp"

#include <Kokkos_Core.hpp>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace softflow::perf {

namespace {

using Clock = std::chrono::steady_clock;

// Kokkos' callbacks are plain function pointers with no user data, so their
// state lives here, the one mutable global in the code; the KernelTimer
// object owns it (only one may exist, and it is not thread-safe: Kokkos
// calls the callbacks from the launching thread).
struct State {
  bool active = false;
  TimerReport report;
  std::vector<std::pair<std::string, Clock::time_point>> open_kernels;  // indexed by kernel id
  std::vector<std::pair<std::string, Clock::time_point>> open_regions;  // a stack
};
State state;

void fence() { Kokkos::fence("perf_timer"); }

// the clock is read right after the fence at the start and the end, so the
// bookkeeping (the name's string, the report's map) is not timed
void begin_kernel(const char* name, uint32_t, uint64_t* id) {
  fence();
  *id = state.open_kernels.size();
  state.open_kernels.emplace_back(name, Clock::time_point{});
  state.open_kernels.back().second = Clock::now();
}

void end_kernel(uint64_t id) {
  fence();
  const Clock::time_point t1 = Clock::now();
  auto& [name, t0] = state.open_kernels.at(id);
  auto& e = state.report.kernels[name];
  e.seconds += std::chrono::duration<double>(t1 - t0).count();
  ++e.calls;
  // kernels do not nest: the last one opened is the one closing
  if (id + 1 == state.open_kernels.size()) state.open_kernels.pop_back();
}

void push_region(const char* name) {
  fence();
  state.open_regions.emplace_back(name, Clock::time_point{});
  state.open_regions.back().second = Clock::now();
}

void pop_region() {
  fence();
  const Clock::time_point t1 = Clock::now();
  if (state.open_regions.empty()) return;
  auto [name, t0] = state.open_regions.back();
  state.open_regions.pop_back();
  auto& e = state.report.regions[name];
  e.seconds += std::chrono::duration<double>(t1 - t0).count();
  ++e.calls;
}

void begin_copy(Kokkos::Tools::SpaceHandle dst, const char*, const void*, Kokkos::Tools::SpaceHandle src,
                const char*, const void*, uint64_t bytes) {
  if (std::strcmp(dst.name, src.name) == 0) return;
  ++state.report.cross_space_copies;
  state.report.cross_space_bytes += bytes;
}

void set_callbacks(bool on) {
  namespace T = Kokkos::Tools::Experimental;
  T::set_begin_parallel_for_callback(on ? begin_kernel : nullptr);
  T::set_end_parallel_for_callback(on ? end_kernel : nullptr);
  T::set_begin_parallel_reduce_callback(on ? begin_kernel : nullptr);
  T::set_end_parallel_reduce_callback(on ? end_kernel : nullptr);
  T::set_begin_parallel_scan_callback(on ? begin_kernel : nullptr);
  T::set_end_parallel_scan_callback(on ? end_kernel : nullptr);
  T::set_push_region_callback(on ? push_region : nullptr);
  T::set_pop_region_callback(on ? pop_region : nullptr);
  T::set_begin_deep_copy_callback(on ? begin_copy : nullptr);
}

}  // namespace

KernelTimer::KernelTimer() {
  if (state.active) throw std::logic_error("KernelTimer: only one may exist");
  state = State{};
  state.active = true;
  set_callbacks(true);
}

KernelTimer::~KernelTimer() {
  set_callbacks(false);
  state.active = false;
}

void KernelTimer::reset() {
  fence();
  state.report = TimerReport{};
  state.open_kernels.clear();
}

TimerReport KernelTimer::report() const { return state.report; }

}  // namespace softflow::perf
