// Multiple markers (particles.colour_fields, src/colour_fields.hpp): phi is
// the sum of the colours, each particle's volume is in its own colour, each
// colour is conserved and bounded on its own, and one colour transports
// phi as phi's own transport does (with phi's own cut of 1e-10 for the tails;
// the colours' default cut is higher, particles.colour_cut).
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <vector>

#include "diagnostics.hpp"
#include "particle_seeding.hpp"
#include "solid_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {

// a dense sheared box, 4 points per radius: 6 spheres of radius 1 close
// enough to meet within a few strain units
Config dense_case(int colours) {
  return couette_case(
      24, 20, 24,
      {"grid.lx=6.0", "grid.ly=5.0", "grid.lz=6.0", "walls.velocity=2.5", "initial.type=couette",
       "particles.radius=1.0", "particles.count=6", "particles.capillary=0.05", "particles.seed=3",
       "particles.colour_fields=" + std::to_string(colours)});
}

// sum of f over r on this rank
double sum_on(const Field3& f, const Range3& r) {
  double s = 0;
  par_reduce(
      "test_field_sum", r, KOKKOS_LAMBDA(int i, int j, int k, double& a) { a += f(i, j, k); },
      Kokkos::Sum<double>(s));
  return s;
}

double field_sum(const Grid& g, const Field3& f) { return global_sum(sum_on(f, g.interior())); }

// the cells of r on this rank whose value lies strictly between lo and hi
long count_between(const Field3& f, const Range3& r, double lo, double hi) {
  long n = 0;
  par_reduce(
      "test_count_between", r,
      KOKKOS_LAMBDA(int i, int j, int k, long& a) { a += f(i, j, k) > lo && f(i, j, k) < hi; },
      Kokkos::Sum<long>(n));
  return n;
}

// the range [min, max] of f over the interior, on all ranks
std::array<double, 2> range_of(const Grid& g, const Field3& f) {
  double lo = 0, hi = 0;
  par_reduce(
      "test_field_min", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) { a = Kokkos::fmin(a, f(i, j, k)); },
      Kokkos::Min<double>(lo));
  par_reduce(
      "test_field_max", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) { a = Kokkos::fmax(a, f(i, j, k)); },
      Kokkos::Max<double>(hi));
  return {-global_max(-lo), global_max(hi)};
}

// max |phi - sum of the colours| and the colours' range, over the interior
struct ColourCheck {
  double sum_error = 0, min = 1e300, max = -1e300, phi_max = 0;
};
ColourCheck check_colours(FlowSolver& s) {
  const Grid g = s.grid();
  const ColourFields& c = s.solid()->colours();
  const Field3 phi = s.solid()->fields().phi();
  ColourCheck r;
  Field3 sum("test_colour_sum", g.sx(), g.sy(), g.sz());
  c.sum_into(sum, g.interior());
  r.sum_error = max_diff(phi, sum, g.interior());
  for (int m = 0; m < c.size(); ++m) {
    const auto [lo, hi] = range_of(g, c.colour(m));
    r.min = std::min(r.min, lo);
    r.max = std::max(r.max, hi);
  }
  r.sum_error = global_max(r.sum_error);
  r.phi_max = range_of(g, phi)[1];
  return r;
}

// a unit sphere at (x0, y0, z0) with a tanh edge of width w into q, its
// tails cut below 1e-4 and above 1 - 1e-6 (a function of its own: nvcc
// rejects a device lambda in a test's private TestBody)
void diffuse_sphere(const Grid& g, const Field3& q, Real x0, Real y0, Real z0, Real w) {
  par_for(
      "test_colour_sphere", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        const Real dx = g.xc(i) - x0, dy = g.yc(j) - y0, dz = g.zc(k) - z0;
        const Real d = Kokkos::sqrt(dx * dx + dy * dy + dz * dz);
        const Real v = 0.5 * (1 - Kokkos::tanh((d - 1) / w));
        q(i, j, k) = v < 1e-4 ? 0 : (v > 1 - 1e-6 ? 1 : v);
      });
}

}  // namespace

// Seeded: one particle per colour, each with a sphere's volume (to the
// seeding's 1e-3, test_solid.cpp), phi their sum and equal to the one-field
// seeding (the spheres do not overlap)
TEST(ColourFields, SeedOneParticlePerColour) {
  FlowSolver one(dense_case(0), MPI_COMM_WORLD), many(dense_case(6), MPI_COMM_WORLD);
  one.initialize();
  many.initialize();
  const Grid g = many.grid();
  const ColourFields& c = many.solid()->colours();
  ASSERT_EQ(c.size(), 6);
  for (int m = 0; m < c.size(); ++m)
    EXPECT_NEAR(field_sum(g, c.colour(m)) * g.dx * g.dy * g.dz / (4.0 / 3.0 * M_PI), 1.0, 1e-3) << m;
  EXPECT_LT(check_colours(many).sum_error, 1e-15);
  EXPECT_LT(global_max(max_diff(one.solid()->fields().phi(), many.solid()->fields().phi(), g.interior())),
            1e-15);
  // more colours than particles: one per particle
  Config c9 = dense_case(9);
  FlowSolver nine(c9, MPI_COMM_WORLD);
  EXPECT_EQ(nine.solid()->colours().size(), 6);
}

// Sheared for 2 strain units, particles meeting: every colour keeps its
// volume to round-off and stays in [0, 1], phi is their sum and at most 1
// (ColourFields::bound_sum; SumBoundKeepsEachVolumeAndTheSumAtMostOne tests
// it where colours overlap, which these stiff spheres do not yet), and with one
// colour phi moves as without colours (the same scheme on the same field;
// only the order of the redistribution's sums differs: 1e-12)
TEST(ColourFields, ConservedBoundedAndSummed) {
  FlowSolver many(dense_case(6), MPI_COMM_WORLD);
  many.initialize();
  const Grid g = many.grid();
  const ColourFields& c = many.solid()->colours();
  std::vector<double> v0;
  for (int m = 0; m < c.size(); ++m) v0.push_back(field_sum(g, c.colour(m)));
  run_to(many, 2.0);
  for (int m = 0; m < c.size(); ++m) EXPECT_NEAR(field_sum(g, c.colour(m)) / v0[m], 1.0, 1e-12) << m;
  const ColourCheck k = check_colours(many);
  if (world_rank() == 0)
    std::printf("  after %ld steps: |phi - sum| %.1e, colours in [%.1e, %.17g], phi at most 1 + %.1e\n",
                many.step, k.sum_error, k.min, k.max, k.phi_max - 1);
  EXPECT_LT(k.sum_error, 1e-15);
  EXPECT_LE(k.phi_max, 1 + 1e-14);
  EXPECT_GE(k.min, 0.0);
  EXPECT_LE(k.max, 1.0);

  auto one_particle = [](int colours) {
    Config c = dense_case(colours);
    c.particles.count = 1;
    c.particles.placement = "centre";
    c.particles.colour_cut = 1e-10;  // phi's own cut: the same transport
    return c;
  };
  FlowSolver plain(one_particle(0), MPI_COMM_WORLD), coloured(one_particle(1), MPI_COMM_WORLD);
  plain.initialize();
  coloured.initialize();
  run_to(plain, 2.0);
  run_to(coloured, 2.0);
  ASSERT_EQ(plain.step, coloured.step);
  const double d =
      global_max(max_diff(plain.solid()->fields().phi(), coloured.solid()->fields().phi(), g.interior()));
  if (world_rank() == 0)
    std::printf("  one particle, one colour against none: max |phi difference| %.1e\n", d);
  EXPECT_LT(d, 1e-12);
}

// ColourFields::bound_sum on two diffuse spheres overlapping by 0.3 r (1.2
// cells at 4 points per radius; their sum reaches ~2 there, as two colours
// filling the cell between two particles do): afterwards the sum is at
// most 1 (to round-off), each colour is still in [0, 1] with its volume
// kept to round-off, and cells far from the overlap change only where there
// is room, at the interfaces (the cores, sum 1, are untouched).
TEST(ColourFields, SumBoundKeepsEachVolumeAndTheSumAtMostOne) {
  FlowSolver s(dense_case(0), MPI_COMM_WORLD);
  const Grid g = s.grid();
  ColourFields cf(g, 2);
  const Real w = 0.3 * g.dx;  // a tanh edge about a cell wide
  const Real cx[2] = {2.2, 3.9}, cy = 0.0, cz = 3.0;
  for (int m = 0; m < 2; ++m) diffuse_sphere(g, cf.colour(m), cx[m], cy, cz, w);
  Field3 phi("test_colour_phi", g.sx(), g.sy(), g.sz());
  cf.sum_into(phi, g.interior());
  double v0[2], before[2];
  for (int m = 0; m < 2; ++m) v0[m] = field_sum(g, cf.colour(m));
  const double phi_max0 = range_of(g, phi)[1];
  ASSERT_GT(phi_max0, 1.5);  // the set-up overlaps
  // a core cell of colour 0 far from the overlap, and one of its far interface
  // (global indices; the rank holding it gives its value)
  auto value_at = [&](int m, int gi, int gj, int gk) {
    const int i = gi - g.x0 + Grid::ng, j = gj + Grid::ng, k = gk - g.z0 + Grid::ng;
    const Range3 in = g.interior();
    double v = 0;
    if (in.contains(i, j, k)) {
      auto h =
          Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kokkos::subview(cf.colour(m), i, j, k));
      v = h();
    }
    return global_sum(v);
  };
  const int gi = int(cx[0] / g.dx), gj = g.ny / 2, gk = int(cz / g.dz), edge_i = gi - int(1.0 / g.dx);
  before[0] = value_at(0, gi, gj, gk);
  before[1] = value_at(0, edge_i, gj, gk);
  ASSERT_EQ(before[0], 1.0);
  ASSERT_GT(before[1], 0.05);
  ASSERT_LT(before[1], 0.95);
  const auto allreduce_sum = [](Real* x, int n) {
    MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  };
  ASSERT_TRUE(cf.bound_sum(phi, allreduce_sum));
  cf.sum_into(phi, g.interior());
  const double phi_max = range_of(g, phi)[1];
  double lo = 1, hi = 0;
  for (int m = 0; m < 2; ++m) {
    const auto [l, h] = range_of(g, cf.colour(m));
    lo = std::min(lo, l);
    hi = std::max(hi, h);
    EXPECT_NEAR(field_sum(g, cf.colour(m)) / v0[m], 1.0, 1e-13) << m;
  }
  const double core = value_at(0, gi, gj, gk), edge = value_at(0, edge_i, gj, gk);
  if (world_rank() == 0)
    std::printf("  sum max %.3f -> 1 + %.1e; colours in [%.1e, 1 + %.1e]; far interface cell %.4f -> %.4f\n",
                phi_max0, phi_max - 1, lo, hi - 1, before[1], edge);
  EXPECT_LE(phi_max, 1 + 1e-14);
  EXPECT_GE(lo, 0.0);
  EXPECT_LE(hi, 1 + 1e-14);
  EXPECT_EQ(core, before[0]);
  EXPECT_GT(edge, before[1]);  // the overlap's volume went back to the interfaces
}

// The cover of occupied indices (src/colour_boxes.hpp): an arc on a
// periodic direction held whole, the plain interval elsewhere
TEST(ColourBoxes, CoverIntervals) {
  const int n = 20, ng = Grid::ng;
  auto flags = [&](std::initializer_list<int> storage) {
    std::vector<int> o(n + 2 * ng, 0);
    for (int s : storage) o[s] = 1;
    return o;
  };
  Interval iv[2];
  // inside: interior 5..8 grown by 2
  auto o = flags({ng + 5, ng + 8});
  ASSERT_EQ(cover_intervals(o.data(), n, 2, true, iv), 1);
  EXPECT_EQ(iv[0].lo, ng + 3);
  EXPECT_EQ(iv[0].hi, ng + 11);
  // across the seam: interior 18, 19, 0, 1 (and their ghost copies, ignored)
  o = flags({ng + 18, ng + 19, ng + 0, ng + 1, 0, 1, 2, ng + n, ng + n + 1});
  ASSERT_EQ(cover_intervals(o.data(), n, 2, true, iv), 2);
  EXPECT_EQ(iv[0].lo, ng + 16);
  EXPECT_EQ(iv[0].hi, ng + n);
  EXPECT_EQ(iv[1].lo, ng);
  EXPECT_EQ(iv[1].hi, ng + 4);
  // a gap of 3 cells grown over by 2 on each side: the whole circle
  std::vector<int> most(n + 2 * ng, 1);
  for (int p = 7; p < 10; ++p) most[ng + p] = 0;
  ASSERT_EQ(cover_intervals(most.data(), n, 2, true, iv), 1);
  EXPECT_EQ(iv[0].lo, ng);
  EXPECT_EQ(iv[0].hi, ng + n);
  // nothing
  o = flags({});
  EXPECT_EQ(cover_intervals(o.data(), n, 2, true, iv), 0);
  // not a circle (walls, or split over ranks): ghosts count, clipped to the interior
  o = flags({1, ng + 2});
  ASSERT_EQ(cover_intervals(o.data(), n, 2, false, iv), 1);
  EXPECT_EQ(iv[0].lo, ng);
  EXPECT_EQ(iv[0].hi, ng + 5);
  // the seam case as a plain interval spans the direction
  o = flags({ng + 18, ng + 1});
  ASSERT_EQ(cover_intervals(o.data(), n, 0, false, iv), 1);
  EXPECT_EQ(iv[0].hi - iv[0].lo, 18);
}

// A particle across the periodic x or z boundary: its colour's step boxes
// are split at the seam and span the particle grown by the step's margin
// (phi's support, ~15 cells at 4 points per radius with MTHINC's tails, plus
// 2 x 9: ~33 cells), not the box's whole length (96 cells, what one bounding
// box across the seam spans), and each stage's work spans the particle
// grown by 1 (MTHINC's reach); after half a strain unit it has moved as phi
// does without colours (1e-12: only the order of the redistribution's sums
// differs)
TEST(ColourFields, ParticleAcrossTheSeamCostsItsSize) {
  auto one_particle = [](int colours, unsigned long seed) {
    Config c =
        couette_case(96, 12, 96,
                     {"grid.lx=24.0", "grid.ly=3.0", "grid.lz=24.0", "walls.velocity=1.5",
                      "initial.type=couette", "particles.radius=1.0", "particles.count=1",
                      "particles.capillary=0.2", "particles.colour_fields=" + std::to_string(colours)});
    c.particles.seed = seed;
    c.particles.colour_cut = 1e-10;  // phi's own cut: the same transport, and round 20's box lengths
    return c;
  };
  // the first seed whose sphere crosses x = 0 or z = 0 (deterministic)
  unsigned long seed = 1;
  for (;; ++seed) {
    const Sphere s = seed_spheres(one_particle(1, seed))[0];
    if (s.x < 1 || s.x > 23 || s.z < 1 || s.z > 23) break;
    ASSERT_LT(seed, 1000u);
  }
  FlowSolver plain(one_particle(0, seed), MPI_COMM_WORLD), coloured(one_particle(1, seed), MPI_COMM_WORLD);
  plain.initialize();
  coloured.initialize();
  const Grid g = coloured.grid();
  const double v0 = field_sum(g, coloured.solid()->colours().colour(0));
  run_to(plain, 0.5);
  run_to(coloured, 0.5);
  // the x and z lengths boxes cover (split boxes: the seam's two sides)
  auto lengths = [](const ColourBoxes& b) {
    int lx = 0, lz = 0;
    for (int q = 0; q < b.count; ++q) {
      bool new_x = true, new_z = true;
      for (int p = 0; p < q; ++p) {
        new_x = new_x && (b.box[p].ib != b.box[q].ib);
        new_z = new_z && (b.box[p].kb != b.box[q].kb);
      }
      if (new_x) lx += b.box[q].ie - b.box[q].ib;
      if (new_z) lz += b.box[q].ke - b.box[q].kb;
    }
    return std::array<int, 2>{int(global_max(lx)), int(global_max(lz))};
  };
  const ColourFields& cf = coloured.solid()->colours();
  const ColourBoxes& b = cf.step_boxes(0);
  const auto [lx, lz] = lengths(b);
  const auto [ux, uz] = lengths(cf.update_boxes(0));
  if (world_rank() == 0)
    std::printf(
        "  seed %lu: %d step boxes, x and z lengths %d and %d of %d; last stage's update boxes %d and %d\n",
        seed, b.count, lx, lz, g.nx, ux, uz);
  EXPECT_LE(lx, g.nx / 2);
  EXPECT_LE(lz, g.nz / 2);
  if (g.nxl == g.nx && g.nzl == g.nz) EXPECT_GE(b.count, 2);  // one rank: x and z are circles
  // the update boxes (the support at the last stage's start and the one
  // before, grown by MTHINC's reach of 1) are the step's less its margin of
  // 9 a side, plus at most 2 stages' motion of 1 cell a side: at least 12
  // cells shorter. They hold the whole colour (phi = the colours summed there).
  if (g.nxl == g.nx && g.nzl == g.nz) {
    EXPECT_LE(ux, lx - 12);
    EXPECT_LE(uz, lz - 12);
  }
  double inside = 0;
  for (int q = 0; q < cf.update_boxes(0).count; ++q)
    inside += sum_on(cf.colour(0), cf.update_boxes(0).box[q]);
  EXPECT_NEAR(global_sum(inside) / field_sum(g, cf.colour(0)), 1.0, 1e-14);
  EXPECT_NEAR(field_sum(g, coloured.solid()->colours().colour(0)) / v0, 1.0, 1e-12);
  ASSERT_EQ(plain.step, coloured.step);
  EXPECT_LT(
      global_max(max_diff(plain.solid()->fields().phi(), coloured.solid()->fields().phi(), g.interior())),
      1e-12);
}

// particles.colour_cut: a colour's values below it go to 0 after every stage
// and their volume back to its interface (as phi's below 1e-10), so each
// colour still keeps its volume to round-off and stays in [0, 1], holds no
// value in (0, cut), and its tails, which set the boxes it is worked on,
// end sooner: fewer cells in its update boxes than with phi's cut.
TEST(ColourFields, AHigherCutShrinksTheBoxesAndKeepsTheVolume) {
  auto run = [](double cut) {
    Config c = dense_case(6);
    c.particles.colour_cut = cut;
    auto s = std::make_unique<FlowSolver>(c, MPI_COMM_WORLD);
    s->initialize();
    return s;
  };
  auto fine = run(1e-10), coarse = run(1e-6);
  const Grid g = coarse->grid();
  const ColourFields &cf = fine->solid()->colours(), &cc = coarse->solid()->colours();
  std::vector<double> v0;
  for (int m = 0; m < cc.size(); ++m) v0.push_back(field_sum(g, cc.colour(m)));
  run_to(*fine, 1.0);
  run_to(*coarse, 1.0);
  auto cells = [](const ColourFields& c) {
    long n = 0;
    for (int m = 0; m < c.size(); ++m)
      for (int q = 0; q < c.update_boxes(m).count; ++q) n += c.update_boxes(m).box[q].size();
    return double(global_sum(double(n)));
  };
  long tiny = 0;
  for (int m = 0; m < cc.size(); ++m) {
    EXPECT_NEAR(field_sum(g, cc.colour(m)) / v0[m], 1.0, 1e-12) << m;
    tiny += count_between(cc.colour(m), g.interior(), 0, 1e-6);
  }
  const ColourCheck k = check_colours(*coarse);
  const double n_fine = cells(cf), n_coarse = cells(cc);
  const double d =
      global_max(max_diff(fine->solid()->fields().phi(), coarse->solid()->fields().phi(), g.interior()));
  if (world_rank() == 0)
    std::printf("  update-box cells %.0f (cut 1e-10) and %.0f (1e-6); max |phi difference| %.1e\n", n_fine,
                n_coarse, d);
  EXPECT_EQ(global_sum(double(tiny)), 0.0);
  EXPECT_GE(k.min, 0.0);
  EXPECT_LE(k.max, 1.0);
  EXPECT_LT(k.sum_error, 1e-15);
  EXPECT_LT(n_coarse, 0.8 * n_fine);
}

// On a rank that holds x and z whole, fill_ghosts fills a colour's periodic
// ghosts only where its next stage reads them (src/colour_fields.cpp,
// add_periodic_ghosts). Sheared for 2 strain units with particles crossing
// the seams: the answer is the one of the halo's full periodic copy, bit
// for bit, and stays so when every ghost the fill leaves out is set to NaN
// before each fill (a read of one would carry the NaN into the colours, or
// through the redistribution's clip into their volumes). With x or z split
// over ranks the halo fills every ghost in all three runs.
TEST(ColourFields, GhostsFilledWhereReadGiveTheFullCopysAnswer) {
  using GhostFill = ColourFields::GhostFill;
  // the steps at which some colour's boxes are split at a seam (it crosses it)
  int split = 0;
  auto run = [&split](GhostFill f) {
    auto s = std::make_unique<FlowSolver>(dense_case(6), MPI_COMM_WORLD);
    ColourFields& c = s->solid()->colours();
    c.set_ghost_fill(f);
    s->initialize();
    split = 0;
    while (s->time < 2.0 * (1 - 1e-14)) {  // run_to's steps
      s->advance(std::min(s->stable_dt(), 2.0 - s->time));
      bool any = false;
      for (int m = 0; m < c.size(); ++m) any = any || c.update_boxes(m).count > 1;
      split += any;
    }
    return s;
  };
  auto full = run(GhostFill::full), reads = run(GhostFill::reads), poisoned = run(GhostFill::reads_poisoned);
  const Grid g = full->grid();
  const ColourFields& c = full->solid()->colours();
  double d = 0, dp = 0;
  long finite = 0;
  for (int m = 0; m < c.size(); ++m) {
    const Field3 p = poisoned->solid()->colours().colour(m);
    d = std::max(d, max_diff(c.colour(m), reads->solid()->colours().colour(m), g.interior()));
    dp = std::max(dp, max_diff(c.colour(m), p, g.interior()));  // blind to NaN (max of comparisons)
    finite += count_between(p, g.interior(), -1e300, 1e300);    // NaN is not between
  }
  d = global_max(d);
  dp = global_max(dp);
  if (world_rank() == 0)
    std::printf(
        "  %ld steps, %d with a colour split at a seam: max |colour difference| %.1e, poisoned %.1e\n",
        full->step, split, d, dp);
  if (g.nxl == g.nx && g.nzl == g.nz) EXPECT_GE(global_max(split), 1);
  EXPECT_EQ(d, 0.0);
  EXPECT_EQ(dp, 0.0);
  EXPECT_EQ(global_sum(double(finite)), double(c.size()) * g.nx * g.ny * g.nz);
  EXPECT_EQ(full->step, poisoned->step);
}
