// Helpers shared by the tests: cases built from TOML text, global norms.
#pragma once
#include <mpi.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "config.hpp"
#include "flow_solver.hpp"
#include "hdf5_io.hpp"

namespace softflow::test {

inline int world_size() {
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}
inline int world_rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

// A Couette case (walls at +-1, V_w = 1, nu = mu) on a given grid; further
// keys through overrides.
inline Config couette_case(int nx, int ny, int nz, std::vector<std::string> overrides = {},
                           int nranks = world_size()) {
  const std::string text = R"(
[grid]
nx = )" + std::to_string(nx) +
                           "\nny = " + std::to_string(ny) + "\nnz = " + std::to_string(nz) + R"(
lx = 6.283185307179586
ly = 2.0
lz = 6.283185307179586
[fluid]
rho = 1.0
mu = 1.0
[walls]
velocity = 1.0
[time]
end_time = 1.0
[output]
dir = "test-output"
)";
  Config c = parse_config(text, "test", overrides);
  resolve_rank_grid(c, nranks);
  return c;
}

// max over ranks
inline double global_max(double v, MPI_Comm c = MPI_COMM_WORLD) {
  MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_DOUBLE, MPI_MAX, c);
  return v;
}
inline double global_sum(double v, MPI_Comm c = MPI_COMM_WORLD) {
  MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_DOUBLE, MPI_SUM, c);
  return v;
}

// max |a - b| over a range of two fields of the same shape, on this rank
inline double max_diff(const Field3& a, const Field3& b, const Range3& r) {
  double m = 0;
  par_reduce(
      "test_max_diff", r,
      KOKKOS_LAMBDA(int i, int j, int k, double& x) {
        const double d = Kokkos::fabs(a(i, j, k) - b(i, j, k));
        x = d > x ? d : x;
      },
      Kokkos::Max<double>(m));
  return m;
}

// least-squares slope of log(err) against log(h)
inline double order(const std::vector<double>& h, const std::vector<double>& err) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = double(h.size());
  for (size_t i = 0; i < h.size(); ++i) {
    const double x = std::log(h[i]), y = std::log(err[i]);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// runs to end_time with the solver's stable dt (clipped to land on t_end)
inline void run_to(FlowSolver& s, double t_end, double dt_cap = 1e30) {
  while (s.time < t_end * (1 - 1e-14)) {
    double dt = std::min(s.stable_dt(), dt_cap);
    if (s.time + dt > t_end) dt = t_end - s.time;
    s.advance(dt);
  }
}

}  // namespace softflow::test

namespace softflow::test {

// number of interior cells, over all ranks, where two fields differ in any bit
inline long count_differing(const Grid& g, const Field3& a, const Field3& b) {
  long n = 0;
  par_reduce(
      "test_count_differing", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, long& c) { c += a(i, j, k) != b(i, j, k); }, Kokkos::Sum<long>(n));
  return long(global_sum(double(n)));
}

// per named field, the interior cells (all ranks) where two checkpoints of
// s's case differ in any bit: a restarted run must end as the unbroken one
inline std::vector<long> checkpoint_differences(const FlowSolver& s, const std::string& a,
                                                const std::string& b, const std::vector<std::string>& names) {
  const Grid g = s.grid();
  FieldFile file(s.decomposition(), g);
  std::vector<H5Item> ia, ib;
  std::vector<Field3> fa, fb;
  for (const std::string& n : names) {
    fa.emplace_back("a_" + n, g.sx(), g.sy(), g.sz());
    fb.emplace_back("b_" + n, g.sx(), g.sy(), g.sz());
    ia.push_back({n, fa.back()});
    ib.push_back({n, fb.back()});
  }
  file.read(a, ia, {"time"});
  file.read(b, ib, {"time"});
  std::vector<long> out;
  for (size_t m = 0; m < fa.size(); ++m) out.push_back(count_differing(g, fa[m], fb[m]));
  return out;
}

}  // namespace softflow::test

namespace softflow::test {

// a whole text file ("" if missing)
inline std::string read_text(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace softflow::test

namespace softflow::test {

// empty output folders, made by rank 0 before any rank writes
inline void fresh_dirs(const std::vector<std::string>& dirs) {
  if (world_rank() == 0)
    for (const auto& d : dirs) {
      std::filesystem::remove_all(d);
      std::filesystem::create_directories(d);
    }
  MPI_Barrier(MPI_COMM_WORLD);
}

}  // namespace softflow::test
