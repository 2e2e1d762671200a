// Loops over a sparse set of cells. par_for's host path runs each x line as
// one plain loop the compiler vectorises; a kernel that skips most cells with
// a test at its top loses that (the test is a branch around the whole body),
// so skipping 70% of the cells saved nothing (B's masked WENO5 fluxes, dense
// scene: 2.14 ms a field against 2.0 unmasked, perf/results/solid_cost).
// Here the marked cells of each x line are first gathered into runs [lo, hi),
// and the kernel then loops over each run without a test: the runs' bodies
// vectorise as a full line's do.
//
// A line holds at most XRuns::max_runs runs; beyond that its last run is
// stretched over the rest of the line's marks, so a kernel run by
// par_for_runs must give the same answer on an unmarked cell between two
// runs as if it had been skipped (a face flux nobody reads, a right-hand side
// it re-tests). On GPUs par_for_runs is the MDRange with a membership test
// against the same runs: one thread per cell, as par_for.
#pragma once
#include "types.hpp"

namespace softflow {

struct XRuns {
  static constexpr int max_runs = 8;
  // per x line of the range (line = (j - jb) + nj (k - kb)): the count, then
  // lo, hi of each run
  Kokkos::View<int**, Kokkos::LayoutRight, MemSpace> at;
  Range3 r{};  // the range the runs were found in
  XRuns() = default;
  // storage for any range of a grid of sy x sz lines
  XRuns(const std::string& name, int sy, int sz) : at(name, long(sy) * sz, 1 + 2 * max_runs) {}
  bool allocated() const { return at.data() != nullptr; }
};

// The x line of cell (j, k) in runs found over r (line_policy's order), and
// back
KOKKOS_INLINE_FUNCTION long x_line(const Range3& r, int j, int k) {
  return long(j - r.jb) + long(r.je - r.jb) * (k - r.kb);
}
KOKKOS_INLINE_FUNCTION void line_jk(const Range3& r, long line, int& j, int& k) {
  const int nj = r.je - r.jb;
  j = r.jb + int(line % nj), k = r.kb + int(line / nj);
}

template <class P>
struct FindRuns {
  P marked;
  Kokkos::View<int**, Kokkos::LayoutRight, MemSpace> at;
  Range3 r;
  KOKKOS_INLINE_FUNCTION void operator()(long line) const {
    int j, k;
    line_jk(r, line, j, k);
    int n = 0;
    bool open = false;
    for (int i = r.ib; i < r.ie; ++i) {
      const bool m = marked(i, j, k);
      if (m && !open) {
        if (n < XRuns::max_runs) {
          at(line, 1 + 2 * n) = i;
          ++n;
        }  // else: the last run is stretched over this one
        open = true;
      } else if (!m && open) {
        at(line, 2 * n) = i;
        open = false;
      }
    }
    if (open) at(line, 2 * n) = r.ie;
    at(line, 0) = n;
  }
};

// The runs of cells of r where marked(i, j, k) holds, one line per thread;
// runs must have been allocated for r's grid
template <class P>
inline void find_runs(const char* label, const Range3& r, const P& marked, XRuns& runs) {
  runs.r = r;
  if (r.size() <= 0) return;
  Kokkos::parallel_for(label, line_policy(r), FindRuns<P>{marked, runs.at, r});
}

template <class F>
struct XRunsLoop {
  F f;
  Kokkos::View<int**, Kokkos::LayoutRight, MemSpace> at;
  Range3 r;
  KOKKOS_INLINE_FUNCTION void operator()(long line) const {
    int j, k;
    line_jk(r, line, j, k);
    const int n = at(line, 0);
    for (int s = 0; s < n; ++s) {
      const int lo = at(line, 1 + 2 * s), hi = at(line, 2 + 2 * s);
      SOFTFLOW_SIMD
      for (int i = lo; i < hi; ++i) f(i, j, k);
    }
  }
};

template <class F>
struct XRunsCells {
  F f;
  Kokkos::View<int**, Kokkos::LayoutRight, MemSpace> at;
  Range3 r;
  KOKKOS_INLINE_FUNCTION void operator()(int i, int j, int k) const {
    const long line = x_line(r, j, k);
    const int n = at(line, 0);
    for (int s = 0; s < n; ++s)
      if (i >= at(line, 1 + 2 * s) && i < at(line, 2 + 2 * s)) {
        f(i, j, k);
        return;
      }
  }
};

// Labelled loop over the cells of the runs (find_runs)
template <class F>
inline void par_for_runs(const char* label, const XRuns& runs, const F& f) {
  const Range3& r = runs.r;
  if (r.size() <= 0) return;
  if constexpr (host_lines)
    Kokkos::parallel_for(label, line_policy(r), XRunsLoop<F>{f, runs.at, r});
  else
    Kokkos::parallel_for(label, policy(r), XRunsCells<F>{f, runs.at, r});
}

}  // namespace softflow
