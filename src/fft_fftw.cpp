// LineFft on FFTW (host memory). Plans are made with FFTW_ESTIMATE so that the
// same run always takes the same algorithm: a restarted run then reproduces an
// uninterrupted one bit for bit (FFTW_MEASURE picks by timing).
#include <fftw3.h>

#include <mutex>
#include <stdexcept>

#include "fft.hpp"

static_assert(Kokkos::SpaceAccessibility<Kokkos::HostSpace, softflow::MemSpace>::accessible,
              "fft_fftw.cpp needs host-accessible memory; build fft_cufft.cpp for CUDA");

namespace softflow {

struct LineFft::Plans {
  fftw_plan fwd = nullptr, bwd = nullptr;
};

namespace {
std::mutex& planner_mutex() {  // FFTW's planner is not thread-safe
  static std::mutex m;
  return m;
}

// With FFTW's OpenMP library the transforms of a plan are shared among the
// threads Kokkos runs on (the many lines of a pencil split between them);
// the same thread count always makes the same plan.
void use_kokkos_threads() {
#ifdef SOFTFLOW_FFTW_OMP
  static const bool ready = fftw_init_threads() != 0;
  if (ready) fftw_plan_with_nthreads(Kokkos::DefaultHostExecutionSpace().concurrency());
#endif
}
}  // namespace

LineFft::LineFft(int n, long howmany, Array1 data) : plans_(new Plans) {
  if (howmany <= 0) return;
  std::lock_guard<std::mutex> lock(planner_mutex());
  use_kokkos_threads();
  fftw_r2r_kind f = FFTW_R2HC, b = FFTW_HC2R;
  int hm = int(howmany);
  plans_->fwd = fftw_plan_many_r2r(1, &n, hm, data.data(), nullptr, 1, n, data.data(), nullptr, 1, n, &f,
                                   FFTW_ESTIMATE);
  plans_->bwd = fftw_plan_many_r2r(1, &n, hm, data.data(), nullptr, 1, n, data.data(), nullptr, 1, n, &b,
                                   FFTW_ESTIMATE);
  if (!plans_->fwd || !plans_->bwd) throw std::runtime_error("FFTW could not make a plan");
}

LineFft::~LineFft() {
  std::lock_guard<std::mutex> lock(planner_mutex());
  if (plans_->fwd) fftw_destroy_plan(plans_->fwd);
  if (plans_->bwd) fftw_destroy_plan(plans_->bwd);
}

void LineFft::forward() {
  Kokkos::fence("fft_forward");
  if (plans_->fwd) fftw_execute(plans_->fwd);
}

void LineFft::backward() {
  Kokkos::fence("fft_backward");
  if (plans_->bwd) fftw_execute(plans_->bwd);
}

}  // namespace softflow
