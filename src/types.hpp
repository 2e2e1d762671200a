// One place for softflow's basic types: the floating-point type, the execution
// space, the View aliases and the labelled loop wrappers (so the loop policy
// can be changed, and measured, in one place).
#pragma once
#include <Kokkos_Core.hpp>

#include "real.hpp"

namespace softflow {

using ExecSpace = Kokkos::DefaultExecutionSpace;
using MemSpace = ExecSpace::memory_space;

// Fields are stored x-fastest (LayoutLeft) on every backend: x lines are
// contiguous, which suits both the CPU's vector units and coalesced GPU access.
using Field3 = Kokkos::View<Real***, Kokkos::LayoutLeft, MemSpace>;
using Array1 = Kokkos::View<Real*, MemSpace>;
using HostField3 = Field3::host_mirror_type;

// Index range [b, e) of storage indices in each direction.
struct Range3 {
  int ib, ie, jb, je, kb, ke;
  long size() const { return long(ie - ib) * (je - jb) * (ke - kb); }
  bool empty() const { return ie <= ib || je <= jb || ke <= kb; }
  KOKKOS_INLINE_FUNCTION bool contains(int i, int j, int k) const {
    return i >= ib && i < ie && j >= jb && j < je && k >= kb && k < ke;
  }
};

// r grown by m cells on every side and clipped to `within`
inline Range3 grown(const Range3& r, int m, const Range3& within) {
  auto lo = [](int a, int b) { return a > b ? a : b; };
  auto hi = [](int a, int b) { return a < b ? a : b; };
  return {lo(r.ib - m, within.ib), hi(r.ie + m, within.ie), lo(r.jb - m, within.jb),
          hi(r.je + m, within.je), lo(r.kb - m, within.kb), hi(r.ke + m, within.ke)};
}

using Policy3 =
    Kokkos::MDRangePolicy<ExecSpace, Kokkos::Rank<3, Kokkos::Iterate::Left, Kokkos::Iterate::Left>>;

inline Policy3 policy(const Range3& r) { return Policy3({r.ib, r.jb, r.kb}, {r.ie, r.je, r.ke}); }

// On host backends a 3-D loop runs one x line per parallel iteration, the line
// itself a plain loop over contiguous memory that the compiler vectorises.
// Kokkos' host MDRange calls the functor point by point through its tile
// loops, which the compiler does not vectorise (measured in perf/README.md).
// GPUs keep the MDRange: one thread per cell, x fastest for coalescing.
// SOFTFLOW_HOST_MDRANGE (the CMake option of that name) makes the host take
// the GPUs' MDRange path too, so that a CPU machine runs and tests it.
#if defined(SOFTFLOW_HOST_MDRANGE)
constexpr bool host_lines = false;
#else
constexpr bool host_lines = std::is_same_v<ExecSpace, Kokkos::DefaultHostExecutionSpace>;
#endif

// The inner loop carries the parallel_for contract (no cell depends on
// another cell's result in the same loop) to the vectoriser; without it the
// compiler gives up on kernels that read and write many arrays (it cannot
// prove them unaliased).
#if defined(_OPENMP)
#define SOFTFLOW_SIMD _Pragma("omp simd")
#elif defined(__GNUC__) && !defined(__clang__)
#define SOFTFLOW_SIMD _Pragma("GCC ivdep")
#else
#define SOFTFLOW_SIMD
#endif

template <class F>
struct XLineLoop {
  F f;
  int ib, ie, jb, nj, kb;
  KOKKOS_INLINE_FUNCTION void operator()(long line) const {
    const int j = jb + int(line % nj), k = kb + int(line / nj);
    SOFTFLOW_SIMD
    for (int i = ib; i < ie; ++i) f(i, j, k);
  }
};

template <class F>
struct XLineReduce {
  F f;
  int ib, ie, jb, nj, kb;
  template <class T>
  KOKKOS_INLINE_FUNCTION void operator()(long line, T& acc) const {
    const int j = jb + int(line % nj), k = kb + int(line / nj);
    for (int i = ib; i < ie; ++i) f(i, j, k, acc);
  }
};

inline Kokkos::RangePolicy<ExecSpace> line_policy(const Range3& r) {
  return Kokkos::RangePolicy<ExecSpace>(0, long(r.je - r.jb) * (r.ke - r.kb));
}

// Labelled 3-D loop over a range. Labels follow `module_action`.
template <class F>
inline void par_for(const char* label, const Range3& r, const F& f) {
  if (r.size() <= 0) return;
  if constexpr (host_lines)
    Kokkos::parallel_for(label, line_policy(r), XLineLoop<F>{f, r.ib, r.ie, r.jb, r.je - r.jb, r.kb});
  else
    Kokkos::parallel_for(label, policy(r), f);
}

// Labelled 3-D reduction with a Kokkos reducer (Max, Sum, ...).
template <class F, class Reducer>
inline void par_reduce(const char* label, const Range3& r, const F& f, const Reducer& red) {
  if (r.size() <= 0) {
    red.init(red.reference());
    return;
  }
  if constexpr (host_lines)
    Kokkos::parallel_reduce(label, line_policy(r), XLineReduce<F>{f, r.ib, r.ie, r.jb, r.je - r.jb, r.kb},
                            red);
  else
    Kokkos::parallel_reduce(label, policy(r), f, red);
}

}  // namespace softflow
