// The solid phase's conditions (src/solid_checks.hpp): over a series, each
// condition's extreme value and the first row that broke it; while a run
// goes, one warning per broken condition, the first time.
#include <gtest/gtest.h>

#include <sstream>

#include "diagnostics.hpp"
#include "solid_checks.hpp"

using namespace softflow;

namespace {
// count of the lines of `log` that start with "warning:"
int warnings(const std::string& log) {
  std::istringstream in(log);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) n += line.rfind("warning:", 0) == 0;
  return n;
}
}  // namespace

TEST(SolidChecks, SeriesGivesExtremesAndTheFirstRowThatBrokeEachBound) {
  // four rows: det B leaves [0.97, 1.03] at the third (step 10), the share
  // passes 5% at the fourth (step 15), the volume moves by 1e-15 relative
  std::map<std::string, std::vector<double>> s = {{"step", {0, 5, 10, 15}},
                                                  {"strain", {0, 0.5, 1.0, 1.5}},
                                                  {"detb_raw_min", {1.0, 0.99, 0.96, 0.98}},
                                                  {"detb_raw_max", {1.0, 1.01, 1.02, 1.031}},
                                                  {"elastic_share_lowphi", {0.01, 0.02, 0.049, 0.06}},
                                                  {"solid_volume", {2.0, 2.0 + 2e-15, 2.0 - 2e-15, 2.0}}};
  const nlohmann::json j = solid_checks(s);
  const nlohmann::json& d = j["detb_raw_phi_above_half"];
  EXPECT_FALSE(d["pass"].get<bool>());
  EXPECT_EQ(d["first_fail"]["step"].get<long>(), 10);
  EXPECT_DOUBLE_EQ(d["first_fail"]["strain"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(d["range"][0].get<double>(), 0.96);
  EXPECT_DOUBLE_EQ(d["range"][1].get<double>(), 1.031);
  const nlohmann::json& e = j["elastic_share_lowphi"];
  EXPECT_FALSE(e["pass"].get<bool>());
  EXPECT_EQ(e["first_fail"]["step"].get<long>(), 15);
  EXPECT_DOUBLE_EQ(e["max"].get<double>(), 0.06);
  const nlohmann::json& v = j["solid_volume_drift"];
  EXPECT_TRUE(v["pass"].get<bool>());
  EXPECT_TRUE(v["first_fail"].is_null());
  EXPECT_NEAR(v["max"].get<double>(), 1e-15,
              2.3e-16);  // 2 +- 2e-15 rounds to a neighbouring double (ulp 4.4e-16)
  // a series without the solid's columns (no particles): nothing to check
  EXPECT_TRUE(solid_checks({{"step", {0, 5}}, {"strain", {0, 1}}}).is_null());
}

TEST(SolidChecks, WatchWarnsOncePerBrokenCondition) {
  SolidWatch watch;
  std::ostringstream log;
  FlowScalars f;
  f.solid_volume = 2;
  watch.row(f, 0, 0.0, log);  // det B = 1, share 0: nothing
  EXPECT_EQ(warnings(log.str()), 0);
  f.detb_raw_min = 0.95;
  watch.row(f, 5, 0.5, log);
  watch.row(f, 10, 1.0, log);  // the same condition again: no second line
  EXPECT_EQ(warnings(log.str()), 1);
  EXPECT_NE(log.str().find("at step 5 (strain 0.5)"), std::string::npos) << log.str();
  f.elastic_share_lowphi = 0.12;
  f.solid_volume = 2 * (1 + 1e-9);
  watch.row(f, 15, 1.5, log);
  EXPECT_EQ(warnings(log.str()), 3) << log.str();
  EXPECT_NE(log.str().find("carry 12% of the elastic shear stress"), std::string::npos) << log.str();
}
