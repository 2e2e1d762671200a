// particles.solid_model = "reference_map" in a run: a tank-treading sphere
// (Ca = 0.2, K = 1, 4 points per radius, 8r x 6r x 8r box, from the Couette
// profile) keeps its solid volume to round-off and phi in [0, 1], and a run
// restarted from a checkpoint ends bit-identical to an uninterrupted one: the
// map xi and its inside mask are checkpointed, and the map is allocated
// before a restart reads it (round 33: it was built in seed() only, so a
// restarted run silently went on with transported phi and B).
#include <gtest/gtest.h>

#include <sstream>

#include "hdf5_io.hpp"
#include "run.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {
Config map_case(const std::string& dir, std::vector<std::string> extra = {}) {
  std::vector<std::string> o = {"output.dir=\"" + dir + "\"",
                                "output.progress_every=0",
                                "output.series_every=1",
                                "output.fields_every=0",
                                "grid.lx=8.0",
                                "grid.ly=6.0",
                                "grid.lz=8.0",
                                "grid.nx=32",
                                "grid.ny=24",
                                "grid.nz=32",
                                "walls.velocity=3.0",
                                "particles.volume_fraction=0.0109",  // one sphere in the 8r x 6r x 8r box
                                "particles.placement=\"centre\"",
                                "initial.type=\"couette\"",
                                "particles.solid_model=\"reference_map\"",
                                "time.end_strain=0.6"};
  o.insert(o.end(), extra.begin(), extra.end());
  Config c = load_config(std::string(SOFTFLOW_SOURCE_DIR) + "/cases/phi0016_ca02.toml", o);
  resolve_rank_grid(c, world_size());
  return c;
}

// a column of series.csv, row by row
std::vector<double> series_column(const std::string& csv, const std::string& name) {
  std::istringstream in(csv);
  std::string line, cell;
  std::getline(in, line);
  int col = -1, n = 0;
  std::istringstream head(line);
  while (std::getline(head, cell, ',')) {
    if (cell == name) col = n;
    ++n;
  }
  std::vector<double> out;
  if (col < 0) return out;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    for (int m = 0; m <= col && std::getline(row, cell, ','); ++m)
      if (m == col) out.push_back(std::stod(cell));
  }
  return out;
}
}  // namespace

TEST(ReferenceMapRun, TankTreadingSphereKeepsVolumeAndRestartsBitIdentical) {
  const std::string tag = "_np" + std::to_string(world_size());
  const std::string a = "refmap_full" + tag, b = "refmap_split" + tag;
  fresh_dirs({a, b});
  std::ostringstream log;
  const RunResult full = run_case(map_case(a), MPI_COMM_WORLD, log);
  run_case(map_case(b, {"time.max_steps=6"}), MPI_COMM_WORLD, log);
  Config c = map_case(b);
  c.restart = b + "/checkpoint.h5";
  const RunResult second = run_case(c, MPI_COMM_WORLD, log);
  EXPECT_EQ(6 + second.steps, full.steps);
  EXPECT_GT(second.steps, 3);

  Config probe = map_case(a);
  FlowSolver s(probe, MPI_COMM_WORLD);
  const std::vector<std::string> names = {"u",   "v",   "w",   "p",    "phi",  "Bxx",  "Bxy",      "Bxz",
                                          "Byy", "Byz", "Bzz", "xi_x", "xi_y", "xi_z", "xi_inside"};
  const std::vector<long> diff = checkpoint_differences(s, a + "/checkpoint.h5", b + "/checkpoint.h5", names);
  for (size_t m = 0; m < names.size(); ++m) EXPECT_EQ(diff[m], 0) << names[m] << " differs";

  if (world_rank() == 0) {
    const std::string series = read_text(a + "/series.csv");
    EXPECT_EQ(series, read_text(b + "/series.csv"));
    // the map's phi is its share of the reference sphere, its volume error
    // put back in proportion to phi (1 - phi) every stage: the sum to
    // round-off (1e-12 relative, the bound), phi in [0, 1]
    const std::vector<double> v = series_column(series, "solid_volume"),
                              lo = series_column(series, "phi_min"), hi = series_column(series, "phi_max");
    ASSERT_GT(v.size(), 10u);
    for (size_t m = 0; m < v.size(); ++m) {
      EXPECT_LE(std::abs(v[m] / v[0] - 1), 1e-12) << "row " << m;
      EXPECT_GE(lo[m], 0) << "row " << m;
      EXPECT_LE(hi[m], 1) << "row " << m;
    }
  }
}
