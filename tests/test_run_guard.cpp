// A run that goes bad stops cleanly: a collapsing time step or a non-finite
// field ends it with a message naming the step, the strain and the limit,
// and the last good checkpoint is kept, never overwritten by the bad state.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <sstream>

#include "run.hpp"
#include "run_guard.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {

double checkpoint_step(const std::string& path) {
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return -1;
  double step = -1;
  hid_t a = H5Aopen(f, "step", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_DOUBLE, &step);
  H5Aclose(a);
  H5Fclose(f);
  return step;
}

Config unstable_case(const std::string& dir, std::vector<std::string> extra) {
  std::vector<std::string> o = {"initial.type=couette",       "time.end_time=100",
                                "output.dir=\"" + dir + "\"", "output.progress_every=0",
                                "output.profiles_every=0",    "output.checkpoint_every=10",
                                "output.checkpoint_minutes=0"};
  o.insert(o.end(), extra.begin(), extra.end());
  return couette_case(12, 12, 12, o);
}

// runs the case with `hook` after each step; returns the RunFailure message ("" if none)
std::string run_until_failure(const Config& c, const AfterStep& hook) {
  std::ostringstream log;
  try {
    run_case(c, MPI_COMM_WORLD, log, hook);
  } catch (const RunFailure& e) {
    return e.what();
  }
  return "";
}

// The faults the tests plant, outside their TEST bodies: nvcc forbids
// extended (KOKKOS_LAMBDA) lambdas in gtest's private TestBody.
// every velocity component times 4
void blow_up_velocity(FlowSolver& s) {
  FlowState& st = s.state();
  par_for(
      "test_blow_up", s.grid().all(), KOKKOS_LAMBDA(int i, int j, int k) {
        st.u(i, j, k) *= 4;
        st.v(i, j, k) *= 4;
        st.w(i, j, k) *= 4;
      });
}

// u = NaN in the first interior cell
void plant_nan(FlowSolver& s) {
  FlowState& st = s.state();
  const int n = Grid::ng + 1;
  const double nan = std::nan("");
  par_for(
      "test_nan", Range3{n, n + 1, n, n + 1, n, n + 1},
      KOKKOS_LAMBDA(int i, int j, int k) { st.u(i, j, k) = nan; });
}

}  // namespace

TEST(RunGuard, StepGuardFlagsOnlyACollapse) {
  StepGuard g;
  for (int n = 1; n <= 150; ++n) g.check(n, 0.01 * n, n % 2 ? 1e-2 : 2e-2, DtLimit::viscous);
  // a tenfold drop, a step cut short to meet the end time: not collapses
  EXPECT_NO_THROW(g.check(151, 1.5, 1e-3, DtLimit::advective));
  EXPECT_NO_THROW(g.check(152, 1.5, 1e-12, DtLimit::end_time));
  try {
    g.check(153, 1.5, 5e-6, DtLimit::elastic);  // below 1e-3 x the median 1e-2 or 2e-2
    ADD_FAILURE() << "no collapse reported";
  } catch (const RunFailure& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("collapsed at step 153"), std::string::npos) << m;
    EXPECT_NE(m.find("strain 1.5"), std::string::npos) << m;
    EXPECT_NE(m.find("elastic limit"), std::string::npos) << m;
  }
  StepGuard fresh;
  EXPECT_THROW(fresh.check(1, 0, std::nan(""), DtLimit::advective), RunFailure);
  EXPECT_THROW(fresh.check(1, 0, 0.0, DtLimit::advective), RunFailure);
  EXPECT_NO_THROW(fresh.check(1, 0, 1e-30, DtLimit::advective));  // no history yet: no verdict
}

// the velocity grows fourfold per step from step 25 on: the advective limit
// collapses a few steps later; the checkpoint of step 30 stays
TEST(RunGuard, CollapsingStepStopsTheRun) {
  const std::string dir = "run_guard_collapse_np" + std::to_string(world_size());
  fresh_dirs({dir});
  const Config c = unstable_case(dir, {"output.series_every=10"});
  const std::string msg = run_until_failure(c, [](FlowSolver& s) {
    if (s.step >= 25) blow_up_velocity(s);
  });
  ASSERT_FALSE(msg.empty()) << "the run did not stop";
  if (world_rank() == 0) std::printf("  %s\n", msg.c_str());
  EXPECT_NE(msg.find("the time step collapsed at step 3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("(strain "), std::string::npos) << msg;
  EXPECT_NE(msg.find("advective limit"), std::string::npos) << msg;
  EXPECT_NE(msg.find(dir + "/checkpoint.h5 (step 30), is kept"), std::string::npos) << msg;
  EXPECT_EQ(checkpoint_step(dir + "/checkpoint.h5"), 30);
  EXPECT_FALSE(std::filesystem::exists(dir + "/summary.json"));
}

// a NaN appears at step 25; without series rows the next checkpoint (step 30)
// is where it is found: that checkpoint is not written, step 20's stays
TEST(RunGuard, NonFiniteFieldNeverReachesTheCheckpoint) {
  const std::string dir = "run_guard_nan_np" + std::to_string(world_size());
  fresh_dirs({dir});
  const Config c = unstable_case(dir, {"output.series_every=0"});
  const std::string msg = run_until_failure(c, [](FlowSolver& s) {
    if (s.step == 25 && world_rank() == 0) plant_nan(s);
  });
  ASSERT_FALSE(msg.empty()) << "the run did not stop";
  if (world_rank() == 0) std::printf("  %s\n", msg.c_str());
  EXPECT_NE(msg.find("at step "), std::string::npos) << msg;
  EXPECT_NE(msg.find("(strain "), std::string::npos) << msg;
  EXPECT_NE(msg.find("limit"), std::string::npos) << msg;
  EXPECT_NE(msg.find("finite"), std::string::npos) << msg;
  EXPECT_NE(msg.find(dir + "/checkpoint.h5 (step 20), is kept"), std::string::npos) << msg;
  EXPECT_EQ(checkpoint_step(dir + "/checkpoint.h5"), 20);
}

// checkpoints by wall time: with a tiny interval one is written after every
// step, so at step 4 the checkpoint on disk is step 3's
TEST(RunGuard, CheckpointsByWallTime) {
  const std::string dir = "run_guard_wall_np" + std::to_string(world_size());
  fresh_dirs({dir});
  const Config c = couette_case(12, 12, 12,
                                {"time.end_time=0.1", "output.dir=\"" + dir + "\"", "output.progress_every=0",
                                 "output.checkpoint_every=0", "output.checkpoint_minutes=1e-9"});
  std::ostringstream log;
  double on_disk_at_4 = -1;
  run_case(c, MPI_COMM_WORLD, log, [&](FlowSolver& s) {
    if (s.step == 4) on_disk_at_4 = checkpoint_step(dir + "/checkpoint.h5");
  });
  EXPECT_EQ(on_disk_at_4, 3);
  if (world_rank() == 0)
    EXPECT_NE(log.str().find("checkpoint at step 3 (every 1e-09 min of wall time)"), std::string::npos)
        << log.str();
}
