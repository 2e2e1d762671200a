// Restart of a suspension: phi, B and the elastic force's stage history are
// restored so that the restarted run ends bit-identical to an uninterrupted one.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hdf5_io.hpp"
#include "run.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {
Config suspension(const std::string& dir, std::vector<std::string> extra = {}) {
  std::vector<std::string> o = {"output.dir=\"" + dir + "\"",
                                "output.progress_every=0",
                                "output.series_every=5",
                                "output.fields_every=0",
                                "output.profiles_every=3",
                                "grid.nx=16",
                                "grid.ny=12",
                                "grid.nz=16"};
  o.insert(o.end(), extra.begin(), extra.end());
  Config c = load_config(std::string(SOFTFLOW_SOURCE_DIR) + "/cases/hard/phi033_ca2.toml", o);
  resolve_rank_grid(c, world_size());
  return c;
}
}  // namespace

class RestartParticles : public ::testing::TestWithParam<const char*> {};

TEST_P(RestartParticles, SuspensionRestartIsBitIdentical) {
  // "colours": the implicit step with one colour field per particle
  // (particles.colour_fields), whose fields are restored too; "thin": the
  // implicit step with the thin-particle setting (B's own equation from
  // phi = 0.2 and the debris return, which this coarse dense scene uses)
  const std::string variant = GetParam();
  const std::string scheme = variant == "colours" || variant == "thin" ? "implicit" : variant;
  const std::string tag = variant + "_np" + std::to_string(world_size());
  const std::string visc = "time.viscous=\"" + scheme + "\"",
                    colours = "particles.colour_fields=" + std::string(variant == "colours" ? "1000" : "0");
  const bool thin = variant == "thin";
  const std::string own = "particles.b_solid_phi=" + std::string(thin ? "0.2" : "0.9"),
                    debris = "particles.debris_return=" + std::string(thin ? "true" : "false");
  // the implicit step is longer: run further for the same few steps
  const std::string strain = scheme == "implicit" ? "time.end_strain=1.0" : "time.end_strain=0.06";
  const std::string a = "restart_susp_full_" + tag, b = "restart_susp_split_" + tag;
  fresh_dirs({a, b});
  std::ostringstream log;
  RunResult full = run_case(suspension(a, {visc, strain, colours, own, debris}), MPI_COMM_WORLD, log);
  run_case(suspension(b, {visc, strain, colours, own, debris, "time.max_steps=5"}), MPI_COMM_WORLD, log);
  Config c = suspension(b, {visc, strain, colours, own, debris});
  c.restart = b + "/checkpoint.h5";
  RunResult second = run_case(c, MPI_COMM_WORLD, log);
  EXPECT_EQ(5 + second.steps, full.steps);
  EXPECT_GT(second.steps, 3);
  // every field of the two final checkpoints, bit for bit
  Config probe = suspension(a, {visc, strain, colours, own, debris});
  FlowSolver s(probe, MPI_COMM_WORLD);
  std::vector<std::string> names = {"u", "v", "w", "p", "phi", "Bxx", "Bxy", "Bxz", "Byy", "Byz", "Bzz"};
  for (int m = 0; m < s.solid()->colours().size(); ++m) names.push_back("colour_" + std::to_string(m));
  if (variant == "colours") EXPECT_GT(s.solid()->colours().size(), 1);
  const std::vector<long> diff = checkpoint_differences(s, a + "/checkpoint.h5", b + "/checkpoint.h5", names);
  for (size_t m = 0; m < names.size(); ++m) EXPECT_EQ(diff[m], 0) << names[m] << " differs";
  if (world_rank() == 0) {
    // the time series, the tracked particles and the profile samples continue without a seam
    for (const char* f : {"/series.csv", "/particles.csv", "/profiles_series.csv", "/profiles.csv"}) {
      EXPECT_EQ(read_text(a + f), read_text(b + f)) << f;
      EXPECT_FALSE(read_text(a + f).empty()) << f;
    }
    // the end-of-run objects read the whole series, the restarted run's history
    // included (src/solid_checks.hpp, src/run_averages.hpp)
    const nlohmann::json ja = nlohmann::json::parse(read_text(a + "/summary.json")),
                         jb = nlohmann::json::parse(read_text(b + "/summary.json"));
    ASSERT_TRUE(ja.contains("solid_checks"));
    EXPECT_EQ(ja["solid_checks"], jb["solid_checks"]);
    EXPECT_EQ(ja["averages"], jb["averages"]);
    EXPECT_TRUE(ja["solid_checks"]["solid_volume_drift"]["pass"].get<bool>());
    if (thin) {  // the return ran (else this variant tests nothing new)
      std::istringstream series(read_text(a + "/series.csv"));
      std::string line;
      std::getline(series, line);
      const std::string head = line;
      const std::string key = "debris_returned";
      ASSERT_NE(head.rfind(key), std::string::npos);
      ASSERT_EQ(head.rfind(key) + key.size(), head.size()) << "debris_returned is the last column";
      double returned = 0;
      while (std::getline(series, line)) returned += std::stod(line.substr(line.rfind(',') + 1));
      EXPECT_GT(returned, 0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Viscous, RestartParticles,
                         ::testing::Values("explicit", "implicit", "colours", "thin"));
