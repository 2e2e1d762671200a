// The solid region (kernels/solid_region.hpp): advancing phi and B, and the
// particles' momentum terms, only around the particles must give the answer
// of the whole box, to round-off (the only change is the order of the sums).
// Likewise B's right-hand side only in its live cells (mark_near with reach 1,
// kernels/solid_transport.hpp) against everywhere.
#include <gtest/gtest.h>

#include "solid_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {

// One off-centre sphere in a sheared box: it translates with the flow and
// deforms, so its region moves and grows; on 2 or 4 ranks it spans ranks.
Config one_sphere(const std::string& scheme, double k, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> o = {
      "particles.radius=0.4",           "particles.count=1",
      "particles.placement=\"random\"", "particles.seed=3",
      "particles.shear_modulus=2.0",    "particles.viscosity_ratio=" + std::to_string(k),
      "initial.type=\"couette\"",       "time.viscous=\"" + scheme + "\""};
  o.insert(o.end(), extra.begin(), extra.end());
  return couette_case(64, 16, 64, o);
}

double worst_difference(FlowSolver& a, FlowSolver& b) {
  const Range3 r = a.grid().interior();
  double worst = 0;
  for (auto f : {&FlowState::u, &FlowState::v, &FlowState::w, &FlowState::p})
    worst = std::max(worst, max_diff(a.state().*f, b.state().*f, r));
  for (int m = 0; m < n_solid_fields; ++m)
    worst = std::max(worst, max_diff(a.solid()->fields().q[m], b.solid()->fields().q[m], r));
  const ReferenceMap& ma = a.solid()->reference_map();
  if (ma.on())
    for (int m = 0; m < 3; ++m)
      worst = std::max(worst, max_diff(ma.xi(m), b.solid()->reference_map().xi(m), r));
  return global_max(worst);
}

}  // namespace

// 10 steps of c around the particles and over the whole box: the same answer
// (share: also that the region is a real saving; the reference map's own box
// is checked by its test)
void expect_region_matches_whole_box(const Config& c, const std::string& what, bool share_checked = true) {
  FlowSolver region(c, MPI_COMM_WORLD), whole(c, MPI_COMM_WORLD);
  whole.solid()->set_region_tracking(false);
  region.initialize();
  whole.initialize();
  for (int n = 0; n < 10; ++n) {
    const Real dt = whole.stable_dt();
    region.advance(dt);
    whole.advance(dt);
  }
  const double d = worst_difference(region, whole);
  const double share = global_sum(double(region.solid()->region().size())) /
                       global_sum(double(region.grid().interior().size()));
  if (world_rank() == 0)
    std::printf("  %s: region %.1f%% of the box, max difference to the whole box %.3e\n", what.c_str(),
                100 * share, d);
  // round-off of O(1) fields over 10 steps (the pressure solve amplifies
  // sum-order differences by the condition number; 1e-11 leaves 10x room)
  EXPECT_LT(d, 1e-11) << what;
  // and the region must be a real saving for one small sphere
  if (share_checked) EXPECT_LT(share, 0.5) << what;
}

class SolidRegion : public ::testing::TestWithParam<std::string> {};

TEST_P(SolidRegion, SameAnswerAsTheWholeBox) {
  const std::string scheme = GetParam();
  // K = 1: the viscous remainder lives near the solid; K = 10 (implicit):
  // nu0 = nu_s, so it is nonzero in the fluid too and runs over the box
  for (double k : {1.0, 10.0}) {
    char what[64];
    std::snprintf(what, sizeof what, "%s, K = %g", scheme.c_str(), k);
    expect_region_matches_whole_box(one_sphere(scheme, k), what);
  }
}

// particles.solid_model = "reference_map", with its volume correction: the
// map's passes in its work box (ReferenceMap::begin_step) against the whole
// box. One sphere at 4 points per radius, off-centre, so that it translates
// with the flow and its box moves; on 2 and 4 ranks it spans ranks, and a
// rank it misses runs none of the map's passes. (The map assumes its
// particle never reaches a wall: one_sphere's sphere starts a cell from
// one, and its map breaks there with or without the box.)
TEST(SolidRegion, ReferenceMapInItsWorkBoxSameAnswerAsTheWholeBox) {
  Config c = couette_case(
      48, 24, 48,
      {"grid.lx=12.0", "grid.ly=6.0", "grid.lz=12.0", "walls.velocity=3.0", "particles.radius=1.0",
       "particles.count=1", "particles.placement=\"random\"", "particles.seed=3",
       "particles.shear_modulus=2.0", "initial.type=\"couette\"", "time.viscous=\"implicit\"",
       "particles.solid_model=\"reference_map\"", "particles.map_volume_correction=true"});
  expect_region_matches_whole_box(c, "reference map, K = 1", false);
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  const double share = global_sum(double(s.solid()->reference_map().work().size())) /
                       global_sum(double(s.grid().interior().size()));
  if (world_rank() == 0) std::printf("  the map's work box: %.1f%% of the box\n", 100 * share);
  EXPECT_LT(share, 0.5);
}

// particles.b_solid_phi = 0.9: the inner band reads the core's logs over the
// region grown by two cells (to the storage's edge on a rank's side)
TEST(SolidRegion, InnerBandFromTheCoreSameAnswerAsTheWholeBox) {
  Config c = one_sphere("implicit", 10.0);
  c.particles.b_solid_phi = 0.9;
  expect_region_matches_whole_box(c, "implicit, K = 10, b_solid_phi 0.9");
}

INSTANTIATE_TEST_SUITE_P(Viscous, SolidRegion, ::testing::Values("explicit", "implicit"));

// B's transport only in live cells skips only values the extension or the
// reset overwrites: the same operations on every value that survives, so the
// same answer to the last bit (asserted to 1e-13, room for any reduction
// whose order could vary between two runs). A dense, deforming scene (Phi =
// 0.12, 4 cells per radius, Ca = 2, 40 implicit steps: the particles move
// by cells), with THINC, MTHINC, and MTHINC with B's own equation from
// phi = 0.2 (b_solid_phi = 0.2, the thin-particle setting: a lower line the
// mask's reach must still cover). With the extension after every stage:
// after the last one only (the default), a dead cell keeps the last step's
// extended B through the step where "everywhere" stretches it by its own
// equation for two stages, so the two differ by design (below 5% of phi
// there, in the stress's weight).
TEST(SolidRegion, BLiveCellsGiveTheAnswerOfBEverywhere) {
  // B's path is the same with WENO5 phi
  for (const auto& [scheme, b_solid_phi] :
       {std::pair{"thinc", "0.9"}, {"mthinc", "0.9"}, {"mthinc", "0.2"}}) {
    Config c = couette_case(
        48, 16, 48,
        {"particles.radius=0.5", "particles.volume_fraction=0.12", "particles.seed=5",
         "particles.shear_modulus=0.5", std::string("particles.phi_scheme=\"") + scheme + "\"",
         std::string("particles.b_solid_phi=") + b_solid_phi, "particles.b_extension_stages=\"all\"",
         "initial.type=\"couette\"", "time.viscous=\"implicit\""});
    FlowSolver live(c, MPI_COMM_WORLD), every(c, MPI_COMM_WORLD);
    every.solid()->set_b_live_cells(false);
    live.initialize();
    every.initialize();
    double t = 0;
    for (int n = 0; n < 40; ++n) {
      const Real dt = every.stable_dt();
      live.advance(dt);
      every.advance(dt);
      t += dt;
    }
    const double d = worst_difference(live, every);
    if (world_rank() == 0)
      std::printf("  %s, b_solid_phi %s, to strain %.2f: max difference %.3e\n", scheme, b_solid_phi, t, d);
    EXPECT_LT(d, 1e-13) << scheme << ", b_solid_phi " << b_solid_phi;
  }
}

// particles.b_extension_stages = "last" (the default) extends B once a step,
// after its last RK3 stage, so every step ends with B constrained: extending
// again there moves B only by what the det B projection did to the core
// after the first pass read it (the second pass reads the projected core:
// 2.6e-8 here). Without the extension at the step's end the band keeps B
// from its own equation, which the mean replaces: 0.29 here with the
// extension never applied. 1e-6 lies between.
TEST(SolidRegion, ExtensionAtTheStepsLastStageLeavesTheStepEndConstrained) {
  Config c = one_sphere("implicit", 1.0);
  ASSERT_EQ(c.particles.b_extension_stages, "last");
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  for (int n = 0; n < 10; ++n) s.advance(s.stable_dt());
  const Range3 r = s.grid().interior();
  std::vector<Field3> before;
  for (int m = 1; m < n_solid_fields; ++m) {
    before.emplace_back("b_before", s.grid().sx(), s.grid().sy(), s.grid().sz());
    Kokkos::deep_copy(before.back(), s.solid()->fields().q[m]);
  }
  s.solid()->constrain_b(true);
  double d = 0;
  for (int m = 1; m < n_solid_fields; ++m)
    d = std::max(d, max_diff(before[m - 1], s.solid()->fields().q[m], r));
  d = global_max(d);
  if (world_rank() == 0) std::printf("  B changed by a second extension at a step's end: %.3e\n", d);
  EXPECT_LT(d, 1e-6);
}
