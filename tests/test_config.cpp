// Case files: every bad input gets an error that names the problem.
#include <gtest/gtest.h>

#include "config.hpp"
#include "particle_seeding.hpp"

using namespace softflow;

namespace {

const char* good = R"(
[grid]
nx = 16
ny = 8
nz = 12
lx = 1.0
ly = 2.0
lz = 1.0
[fluid]
rho = 1.0
mu = 0.5
[walls]
velocity = 1.0
[time]
end_strain = 2.0
)";

std::string error_of(const std::string& text, std::vector<std::string> overrides = {}, int ranks = 1) {
  try {
    Config c = parse_config(text, "case", overrides);
    resolve_rank_grid(c, ranks);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::string& err, const std::string& fragment) {
  EXPECT_NE(err.find(fragment), std::string::npos) << "error was: '" << err << "'";
}

}  // namespace

TEST(Config, GoodCaseParsesWithDefaults) {
  Config c = parse_config(good, "case", {});
  EXPECT_EQ(c.grid.nx, 16);
  EXPECT_DOUBLE_EQ(c.fluid.mu, 0.5);
  EXPECT_DOUBLE_EQ(c.shear_rate(), 1.0);
  EXPECT_DOUBLE_EQ(c.end_time_resolved(), 2.0);
  EXPECT_EQ(c.initial.type, "rest");
  EXPECT_EQ(c.output.dir, "output");
}

TEST(Config, OverridesSetKeys) {
  Config c = parse_config(good, "case",
                          {"grid.nx=32", "output.dir=elsewhere", "initial.type=couette", "time.cfl=0.5"});
  EXPECT_EQ(c.grid.nx, 32);
  EXPECT_EQ(c.output.dir, "elsewhere");
  EXPECT_EQ(c.initial.type, "couette");
  EXPECT_DOUBLE_EQ(c.time.cfl, 0.5);
}

TEST(Config, UnknownKeysAreNamed) {
  expect_error(error_of(good, {"grid.nxx=3"}), "unknown key 'grid.nxx'");
  expect_error(error_of(std::string(good) + "[solver]\nx = 1\n"), "unknown key 'solver'");
}

TEST(Config, MissingKeysAreNamed) {
  std::string t = good;
  t.erase(t.find("mu = 0.5"), 8);
  expect_error(error_of(t), "missing key 'fluid.mu'");
  std::string u = good;
  u.erase(u.find("end_strain = 2.0"), 16);
  expect_error(error_of(u), "time.end_strain");
}

TEST(Config, NonPositiveValuesAreRejected) {
  expect_error(error_of(good, {"fluid.mu=-1"}), "'fluid.mu' must be positive (got -1)");
  expect_error(error_of(good, {"time.viscous=\"implict\""}),
               "'time.viscous' must be \"explicit\" or \"implicit\" (got \"implict\")");
  expect_error(error_of(good, {"grid.lx=0"}), "'grid.lx' must be positive");
  expect_error(error_of(good, {"grid.nz=-4"}), "'grid.nz' must be positive");
  expect_error(error_of(good, {"fluid.rho=0"}), "'fluid.rho' must be positive");
  expect_error(error_of(good, {"time.cfl=1.5"}), "'time.cfl' must be at most 1");
}

TEST(Config, SolidNumericsOutOfRangeAreRejected) {
  const std::vector<std::string> sphere = {"particles.radius=0.2", "particles.count=1",
                                           "particles.placement=\"centre\"", "particles.shear_modulus=1.0"};
  auto with = [&](const std::string& key, const std::string& key2 = "") {
    std::vector<std::string> o = sphere;
    o.push_back(key);
    if (!key2.empty()) o.push_back(key2);
    return o;
  };
  EXPECT_EQ(error_of(good, with("particles.b_solid_phi=0.9")), "");
  EXPECT_EQ(error_of(good, with("particles.b_solid_phi=0.2", "particles.debris_return=true")), "");
  expect_error(error_of(good, with("particles.b_solid_phi=0.1")),
               "'particles.b_solid_phi' must be in [0.2, 0.99] (got 0.1");
  expect_error(error_of(good, with("particles.b_solid_phi=1")),
               "'particles.b_solid_phi' must be in [0.2, 0.99]");
  expect_error(error_of(good, with("particles.debris_return=true", "particles.b_extension=false")),
               "'particles.debris_return' needs 'particles.b_extension'");
  expect_error(
      error_of(good, with("particles.debris_return=true", "particles.solid_model=\"reference_map\"")),
      "'particles.debris_return' needs 'particles.solid_model = \"phi_b\"'");
  EXPECT_EQ(error_of(good, with("particles.b_extension_stages=\"all\"")), "");
  expect_error(error_of(good, with("particles.b_extension_stages=\"first\"")),
               "'particles.b_extension_stages' must be \"last\" or \"all\" (got \"first\")");
  expect_error(error_of(good, with("particles.thinc_beta=20")),
               "'particles.thinc_beta' must be in [0.5, 10]");
  EXPECT_EQ(error_of(good, with("particles.colour_cut=1e-6")), "");
  expect_error(error_of(good, with("particles.colour_cut=1e-12")),
               "'particles.colour_cut' must be in [1e-10, 1e-3] (got 1e-12)");
  expect_error(error_of(good, with("particles.colour_cut=0.01")),
               "'particles.colour_cut' must be in [1e-10, 1e-3] (got 0.01)");
  expect_error(
      error_of(good, {"particles.radius=0.2", "particles.count=3", "particles.placement=\"lattice\""}),
      "'particles.placement' must be \"stratified\", \"random\" or \"centre\" (got \"lattice\")");
  EXPECT_EQ(error_of(good, with("particles.solid_model=\"reference_map\"")), "");
  expect_error(error_of(good, with("particles.solid_model=\"level_set\"")),
               "'particles.solid_model' must be \"phi_b\" or \"reference_map\" (got \"level_set\")");
  EXPECT_EQ(
      error_of(good, with("particles.solid_model=\"reference_map\"", "particles.map_volume_correction=true")),
      "");
  expect_error(error_of(good, with("particles.map_volume_correction=true")),
               "'particles.map_volume_correction' needs 'particles.solid_model = \"reference_map\"'");
  auto map_with = [&](const std::string& key, bool on) {
    std::vector<std::string> o = with("particles.solid_model=\"reference_map\"", key);
    if (on) o.push_back("particles.map_volume_correction=true");
    return o;
  };
  EXPECT_EQ(error_of(good, map_with("particles.map_correction_passes=3", true)), "");
  expect_error(error_of(good, map_with("particles.map_correction_passes=3", false)),
               "'particles.map_correction_passes' needs 'particles.map_volume_correction = true'");
  expect_error(error_of(good, map_with("particles.map_correction_passes=0", true)),
               "'particles.map_correction_passes' must be in [1, 8] (got 0)");
  expect_error(error_of(good, map_with("particles.map_correction_passes=9", true)),
               "'particles.map_correction_passes' must be in [1, 8] (got 9)");
  // the map is one smooth field: one sphere, undeformed, no colours
  const std::string one_sphere = "is written for one undeformed sphere";
  expect_error(error_of(good, {"particles.radius=0.2", "particles.count=3", "particles.shear_modulus=1.0",
                               "particles.solid_model=\"reference_map\""}),
               one_sphere);
  expect_error(error_of(good, with("particles.solid_model=\"reference_map\"", "particles.colour_fields=1")),
               one_sphere);
  expect_error(error_of(good, with("particles.solid_model=\"reference_map\"",
                                   "particles.initial_b=[1.25, 0.5, 0.0, 1.0, 0.0, 1.0]")),
               one_sphere);
}

// particles.colour_fields: "auto" (the default) gives one colour per sphere
// where there are two or more and none for a lone sphere; a number is kept
// (at most one per sphere); anything else is named
TEST(Config, ColourFieldsAutoIsOnePerSphereFromTwo) {
  auto colours = [](std::vector<std::string> o) {
    o.push_back("particles.shear_modulus=1.0");
    return colour_count(parse_config(good, "case", o));
  };
  const std::string r = "particles.radius=0.1";
  EXPECT_EQ(colours({r, "particles.count=3"}), 3);
  EXPECT_EQ(colours({r, "particles.count=3", "particles.colour_fields=\"auto\""}), 3);
  EXPECT_EQ(colours({r, "particles.count=1", "particles.placement=\"centre\""}), 0);
  EXPECT_EQ(colours({r, "particles.count=3", "particles.colour_fields=0"}), 0);
  EXPECT_EQ(colours({r, "particles.count=3", "particles.colour_fields=2"}), 2);
  EXPECT_EQ(colours({r, "particles.count=3", "particles.colour_fields=1000"}), 3);
  EXPECT_EQ(parse_config(good, "case", {r, "particles.count=3", "particles.shear_modulus=1.0"})
                .particles.colour_fields,
            ParticleConfig::auto_colours);
  expect_error(error_of(good, {r, "particles.count=3", "particles.shear_modulus=1.0",
                               "particles.colour_fields=\"all\""}),
               "'particles.colour_fields' must be an integer >= 0 or \"auto\" (got \"all\")");
  expect_error(
      error_of(good, {r, "particles.count=3", "particles.shear_modulus=1.0", "particles.colour_fields=-2"}),
      "'particles.colour_fields' must not be negative (got -2)");
}

TEST(Config, WrongTypesAreRejected) {
  expect_error(error_of(good, {"grid.nx=1.5"}), "'grid.nx' must be an integer");
  expect_error(error_of(good, {"fluid.mu=\"thick\""}), "'fluid.mu' must be a number");
  expect_error(error_of(good, {"initial.type=vortex"}), "'initial.type' must be");
  expect_error(error_of("[grid\nnx=1"), "invalid TOML at line 1");
  expect_error(error_of(good, {"gridnx=3"}), "must be table.key");
}

TEST(Config, RankGridMustDivideTheGrid) {
  expect_error(error_of(good, {}, 3), "no rank grid px x pz = 3 divides the grid");
  expect_error(error_of(good, {"parallel.px=2", "parallel.pz=1"}, 4), "parallel.px * parallel.pz = 2");
  expect_error(error_of(good, {"grid.nx=18", "parallel.px=4", "parallel.pz=1"}, 4),
               "grid.nx = 18 is not divisible by parallel.px = 4");
  expect_error(error_of(good, {"grid.ny=6", "parallel.px=4", "parallel.pz=1"}, 4),
               "grid.ny = 6 is not divisible by parallel.px = 4");
  expect_error(error_of(good, {"grid.nz=8", "parallel.px=1", "parallel.pz=4"}, 4),
               "grid.nz / parallel.pz = 2 cells per rank in z; at least 3 are needed");
  Config c = parse_config(good, "case", {});
  resolve_rank_grid(c, 4);
  EXPECT_EQ(c.parallel.px * c.parallel.pz, 4);
}

TEST(Config, MissingFileIsNamed) {
  try {
    load_config("/nonexistent/case.toml", {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "cannot open case file '/nonexistent/case.toml'");
  }
}

// particles.initial_b: six numbers, a deformation's B (positive definite,
// det 1 within 1e-3), and a particle that still fits the box
TEST(Config, InitialBIsChecked) {
  const std::string particles = std::string(good) + R"(
[particles]
radius = 0.25
count = 1
placement = "centre"
capillary = 1.0
)";
  expect_error(error_of(particles, {"particles.initial_b=[1.0,0.0,1.0]"}),
               "'particles.initial_b' must be an array of 6 numbers");
  expect_error(error_of(particles, {"particles.initial_b=[1.0,0.0,0.0,1.0,0.0,\"x\"]"}),
               "array of 6 numbers");
  expect_error(error_of(particles, {"particles.initial_b=[1.0,2.0,0.0,1.0,0.0,1.0]"}),
               "must be positive definite");
  expect_error(error_of(particles, {"particles.initial_b=[2.0,0.0,0.0,1.0,0.0,1.0]"}),
               "det B = 1 within 1e-3");
  // 0.25 sqrt(20) = 1.12 across y: more than half the gap (ly = 2)
  expect_error(error_of(particles, {"particles.initial_b=[0.05,0.0,0.0,20.0,0.0,1.0]"}),
               "do not fit between the walls");
  // 0.25 sqrt(5) * 2 = 1.12 along x: wider than lx = 1
  expect_error(error_of(particles, {"particles.initial_b=[5.0,0.0,0.0,0.2,0.0,1.0]"}),
               "wider than the periodic box");
  EXPECT_EQ(error_of(particles, {"particles.initial_b=[1.2,0.1,0.0,0.85,0.0,0.9901]"}), "");
}
