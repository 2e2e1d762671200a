// A run stopped and restarted from its checkpoint ends bit-identical to an
// uninterrupted run, and its time series continues without a seam.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "hdf5_io.hpp"
#include "run.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {

Config restart_case(const std::string& dir, std::vector<std::string> extra = {}) {
  std::vector<std::string> o = {"initial.type=manufactured", "fluid.mu=0.05",
                                "time.end_time=0.5",         "time.dt_max=0.01",
                                "output.dir=" + dir,         "output.series_every=5",
                                "output.progress_every=0",   "output.checkpoint_every=0"};
  o.insert(o.end(), extra.begin(), extra.end());
  return couette_case(12, 12, 12, o);
}

}  // namespace

class Restart : public ::testing::TestWithParam<const char*> {};

TEST_P(Restart, BitIdenticalToUninterruptedRun) {
  const std::string scheme = GetParam();
  const std::string tag = scheme + "_np" + std::to_string(world_size());
  const std::string a = "restart_full_" + tag, b = "restart_split_" + tag;
  const std::string visc = "time.viscous=\"" + scheme + "\"";
  fresh_dirs({a, b});
  std::ostringstream log;
  RunResult full = run_case(restart_case(a, {visc}), MPI_COMM_WORLD, log);
  RunResult first = run_case(restart_case(b, {visc, "time.max_steps=20"}), MPI_COMM_WORLD, log);
  EXPECT_EQ(first.steps, 20);
  Config c = restart_case(b, {visc});
  c.restart = b + "/checkpoint.h5";
  RunResult second = run_case(c, MPI_COMM_WORLD, log);
  EXPECT_EQ(first.steps + second.steps, full.steps);

  // compare the two final checkpoints bit for bit
  Config probe = restart_case(a, {visc});
  FlowSolver s(probe, MPI_COMM_WORLD);
  FieldFile f(s.decomposition(), s.grid());
  const Grid g = s.grid();
  Field3 x[4], y[4];
  const char* names[4] = {"u", "v", "w", "p"};
  std::vector<H5Item> ia, ib;
  for (int m = 0; m < 4; ++m) {
    x[m] = Field3("x", g.sx(), g.sy(), g.sz());
    y[m] = Field3("y", g.sx(), g.sy(), g.sz());
    ia.push_back({names[m], x[m]});
    ib.push_back({names[m], y[m]});
  }
  auto ta = f.read(a + "/checkpoint.h5", ia, {"time", "step"});
  auto tb = f.read(b + "/checkpoint.h5", ib, {"time", "step"});
  EXPECT_EQ(ta.at("time"), tb.at("time"));
  EXPECT_EQ(ta.at("step"), tb.at("step"));
  for (int m = 0; m < 4; ++m) {
    const long differing = count_differing(g, x[m], y[m]);
    EXPECT_EQ(differing, 0) << names[m] << " differs in " << differing << " cells";
  }
  if (world_rank() == 0) {
    EXPECT_EQ(read_text(a + "/series.csv"), read_text(b + "/series.csv"));
  }
}

INSTANTIATE_TEST_SUITE_P(Viscous, Restart, ::testing::Values("explicit", "implicit"));

TEST(RestartInput, CheckpointOfAnotherGridIsRejected) {
  const std::string dir = "restart_grid_np" + std::to_string(world_size());
  fresh_dirs({dir});
  std::ostringstream log;
  run_case(restart_case(dir, {"time.max_steps=2"}), MPI_COMM_WORLD, log);
  Config c = couette_case(24, 12, 12, {"output.dir=" + dir, "output.progress_every=0"});
  c.restart = dir + "/checkpoint.h5";
  try {
    run_case(c, MPI_COMM_WORLD, log);
    FAIL() << "a 12-cell checkpoint was accepted by a 24-cell case";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the case's grid is 24"), std::string::npos) << e.what();
  }
}
