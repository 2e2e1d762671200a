// The labelled loop wrappers of src/types.hpp: every cell of a range visited
// exactly once and nothing outside it, whichever loop the backend uses (x
// lines on host backends, the MDRange on GPUs), and reductions over exactly
// the range. Every kernel of the code runs through them.
#include <gtest/gtest.h>

#include "types.hpp"
#include "x_runs.hpp"

namespace softflow {
namespace {

// visits[c] = how many times par_for (over r) or par_for_runs (over runs,
// when given) called the body for cell c
HostField3 count_visits(const Range3& r, int n, const XRuns* runs = nullptr) {
  Field3 visits("visits", n, n, n);
  const auto body = KOKKOS_LAMBDA(int i, int j, int k) { Kokkos::atomic_add(&visits(i, j, k), Real(1)); };
  if (runs)
    par_for_runs("test_count_run_visits", *runs, body);
  else
    par_for("test_count_visits", r, body);
  auto h = Kokkos::create_mirror_view(visits);
  Kokkos::deep_copy(h, visits);
  return h;
}

// sum over the range of a value that tells the cells apart
Real weighted_sum(const Range3& r) {
  Real s = 0;
  par_reduce(
      "test_weighted_sum", r,
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) { a += i + 100.0 * j + 10000.0 * k; },
      Kokkos::Sum<Real>(s));
  return s;
}

bool inside(const Range3& r, int i, int j, int k) {
  return i >= r.ib && i < r.ie && j >= r.jb && j < r.je && k >= r.kb && k < r.ke;
}

}  // namespace

TEST(Loops, ParForVisitsEveryCellOfTheRangeOnce) {
  const int n = 16;
  // odd extents and offsets in every direction, and a one-cell-thick range
  for (const Range3& r : {Range3{2, 13, 1, 8, 3, 10}, Range3{0, n, 0, n, 0, n}, Range3{5, 6, 0, 11, 7, 8}}) {
    const HostField3 v = count_visits(r, n);
    long wrong = 0;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) wrong += v(i, j, k) != (inside(r, i, j, k) ? 1 : 0);
    EXPECT_EQ(wrong, 0) << "range " << r.ib << ".." << r.ie << " x " << r.jb << ".." << r.je << " x " << r.kb
                        << ".." << r.ke;
  }
}

TEST(Loops, ParReduceCoversExactlyTheRange) {
  const Range3 r{2, 13, 1, 8, 3, 10};
  double expected = 0;  // summed on the host, integers: exact in any order
  for (int k = r.kb; k < r.ke; ++k)
    for (int j = r.jb; j < r.je; ++j)
      for (int i = r.ib; i < r.ie; ++i) expected += i + 100.0 * j + 10000.0 * k;
  EXPECT_EQ(weighted_sum(r), expected);
}

TEST(Loops, EmptyRangesRunNothing) {
  const Range3 empty{4, 4, 0, 8, 0, 8};
  const HostField3 v = count_visits(empty, 8);
  Real total = 0;
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) total += v(i, j, k);
  EXPECT_EQ(total, 0);
  EXPECT_EQ(weighted_sum(empty), 0);  // the reducer's identity
}

// par_for_runs (src/x_runs.hpp): the marked cells of each x line visited once
// each and nothing unmarked, while a line has at most XRuns::max_runs runs;
// past that, every marked cell still once, and the unmarked ones visited
// only between the line's first and last marks (the stretched last run).
// A pattern with 0 to 12 runs per line: runs of 1 to 3 cells every 3 to 13
// cells, none where k is a multiple of 7. A functor, not a lambda: nvcc
// forbids extended lambdas in gtest's private TestBody.
struct TestMarks {
  KOKKOS_INLINE_FUNCTION bool operator()(int i, int j, int k) const {
    const int period = 3 + (j + k) % 5 + (k % 3 == 0 ? 0 : 6), len = 1 + (i + j) % 3;
    return k % 7 != 0 && (i + 2 * j) % period < len;
  }
};

TEST(Loops, RunsVisitTheMarkedCellsOnce) {
  const int n = 40;
  const Range3 r{1, n - 1, 2, n - 3, 3, n - 5};
  const TestMarks mark;
  XRuns runs("test_runs", n, n);
  find_runs("test_find_runs", r, mark, runs);
  const HostField3 v = count_visits(r, n, &runs);
  long wrong = 0, lines_over = 0, stretched_visits = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j) {
      bool line_in = j >= r.jb && j < r.je && k >= r.kb && k < r.ke;
      int count = 0, first = -1, last = -1;
      for (int i = r.ib; i < r.ie && line_in; ++i) {
        const bool m = mark(i, j, k), before = i > r.ib && mark(i - 1, j, k);
        count += m && !before;
        if (m && first < 0) first = i;
        if (m) last = i;
      }
      const bool over = count > XRuns::max_runs;
      lines_over += over;
      for (int i = 0; i < n; ++i) {
        const bool m = line_in && inside(r, i, j, k) && mark(i, j, k);
        if (m) {
          wrong += v(i, j, k) != 1;
        } else if (over && i > first && i < last) {
          wrong += v(i, j, k) > 1;
          stretched_visits += v(i, j, k) == 1;
        } else {
          wrong += v(i, j, k) != 0;
        }
      }
    }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(lines_over, 0) << "the pattern must exercise the run limit";
  EXPECT_GT(stretched_visits, 0);
}

}  // namespace softflow
