// The answer does not depend on the rank count or the rank grid: every rank
// compares its block with the same case solved on one rank (MPI_COMM_SELF).
#include <gtest/gtest.h>

#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {

Config case_for(int px, int pz, int nranks, const std::string& scheme) {
  return couette_case(24, 16, 12,
                      {"initial.type=manufactured", "initial.amplitude=2.0", "fluid.mu=0.05",
                       "parallel.px=" + std::to_string(px), "parallel.pz=" + std::to_string(pz),
                       "time.viscous=\"" + scheme + "\""},
                      nranks);
}

void run_steps(FlowSolver& s, int n) {
  s.initialize();
  for (int k = 0; k < n; ++k) s.advance(s.stable_dt());
}

// max |parallel - serial| over this rank's block, for one field
double block_diff(const FlowSolver& par, const Field3& a, const Field3& serial) {
  const Grid g = par.grid();
  const int ox = g.x0, oz = g.z0;
  double m = 0;
  par_reduce(
      "test_block_diff", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& x) {
        x = Kokkos::fmax(x, Kokkos::fabs(a(i, j, k) - serial(i + ox, j, k + oz)));
      },
      Kokkos::Max<double>(m));
  return m;
}

}  // namespace

class RankGrids : public ::testing::TestWithParam<const char*> {};

TEST_P(RankGrids, SameFieldsOnEveryRankGrid) {
  const std::string scheme = GetParam();
  const int n = world_size();
  if (n == 1) GTEST_SKIP() << "needs more than one rank";
  std::vector<std::pair<int, int>> grids = {{n, 1}, {1, n}};
  if (n == 4) grids.push_back({2, 2});
  Config cs = case_for(1, 1, 1, scheme);
  FlowSolver serial(cs, MPI_COMM_SELF);
  run_steps(serial, 12);
  for (auto [px, pz] : grids) {
    Config c = case_for(px, pz, n, scheme);
    FlowSolver par(c, MPI_COMM_WORLD);
    run_steps(par, 12);
    EXPECT_EQ(par.step, serial.step);
    EXPECT_DOUBLE_EQ(par.time, serial.time);
    double worst = 0;
    auto& a = par.state();
    auto& b = serial.state();
    for (auto f : {&FlowState::u, &FlowState::v, &FlowState::w, &FlowState::p})
      worst = std::max(worst, block_diff(par, a.*f, b.*f));
    worst = global_max(worst);
    if (world_rank() == 0)
      std::printf("  %s viscosity, %d x %d ranks: max difference to 1 rank %.3e\n", scheme.c_str(), px, pz,
                  worst);
    EXPECT_LT(worst, 1e-12) << px << " x " << pz;
  }
}

// a dense suspension (Phi = 0.33, 32 particles): transport, mixture stress,
// elastic force and the global phi redistribution must not depend on the
// decomposition; with `colours` one colour field per particle, whose boxes,
// redistribution and ghosts (filled only near a rank's edge,
// src/colour_fields.cpp) must not either
void same_suspension_on_every_rank_grid(const std::string& scheme, int colours, int steps) {
  const int n = world_size();
  const std::string file = std::string(SOFTFLOW_SOURCE_DIR) + "/cases/hard/phi033_ca2.toml";
  auto make = [&](int px, int pz, int ranks) {
    Config c = load_config(
        file, {"parallel.px=" + std::to_string(px), "parallel.pz=" + std::to_string(pz),
               "time.viscous=\"" + scheme + "\"", "particles.colour_fields=" + std::to_string(colours)});
    resolve_rank_grid(c, ranks);
    return c;
  };
  Config cs = make(1, 1, 1);
  FlowSolver serial(cs, MPI_COMM_SELF);
  run_steps(serial, steps);
  std::vector<std::pair<int, int>> grids = {{n, 1}, {1, n}};
  for (auto [px, pz] : grids) {
    Config c = make(px, pz, n);
    FlowSolver par(c, MPI_COMM_WORLD);
    run_steps(par, steps);
    double worst = 0;
    for (auto f : {&FlowState::u, &FlowState::v, &FlowState::w, &FlowState::p})
      worst = std::max(worst, block_diff(par, par.state().*f, serial.state().*f));
    for (int m = 0; m < n_solid_fields; ++m)
      worst = std::max(worst, block_diff(par, par.solid()->fields().q[m], serial.solid()->fields().q[m]));
    worst = global_max(worst);
    if (world_rank() == 0)
      std::printf("  suspension, %s viscosity, %d colours, %d x %d ranks: max difference to 1 rank %.3e\n",
                  scheme.c_str(), colours, px, pz, worst);
    EXPECT_LT(worst, 1e-12) << px << " x " << pz;
  }
}

TEST_P(RankGrids, SameSuspensionOnEveryRankGrid) {
  if (world_size() == 1) GTEST_SKIP() << "needs more than one rank";
  same_suspension_on_every_rank_grid(GetParam(), 0, 6);
}

TEST_P(RankGrids, SameColouredSuspensionOnEveryRankGrid) {
  if (world_size() == 1) GTEST_SKIP() << "needs more than one rank";
  same_suspension_on_every_rank_grid(GetParam(), 32, 12);
}

INSTANTIATE_TEST_SUITE_P(Viscous, RankGrids, ::testing::Values("explicit", "implicit"));
