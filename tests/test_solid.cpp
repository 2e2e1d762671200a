// The solid phase: seeding, a solid at rest, rigid rotation, and LeVeque's
// reversing deformation flow.
#include <gtest/gtest.h>

#include <array>

#include "../kernels/solid_transport.hpp"
#include "diagnostics.hpp"
#include "particle_seeding.hpp"
#include "particle_tracker.hpp"
#include "solid_util.hpp"

using namespace softflow;
using namespace softflow::test;

TEST(Seeding, VolumeFractionIsExactToOnePartInAThousand) {
  for (int ppr : {4, 8}) {  // points per radius
    Config c = couette_case(
        8 * ppr, 5 * ppr, 8 * ppr,
        {"grid.lx=8.0", "grid.ly=5.0", "grid.lz=8.0", "walls.velocity=2.5", "particles.radius=1.0",
         "particles.volume_fraction=0.2", "particles.capillary=0.1", "particles.seed=7"});
    FlowSolver s(c, MPI_COMM_WORLD);
    s.initialize();
    const int n = int(s.solid()->spheres().size());
    const double exact = n * 4.0 / 3.0 * M_PI;
    FlowScalars f = Diagnostics(s).scalars();
    if (world_rank() == 0)
      std::printf("  %d points per radius: %d spheres, phi volume %.6f, exact %.6f\n", ppr, n, f.solid_volume,
                  exact);
    EXPECT_NEAR(f.solid_volume / exact, 1.0, 1e-3);
    EXPECT_EQ(n, sphere_count(c));
    EXPECT_GE(f.phi_min, 0.0);
    EXPECT_LE(f.phi_max, 1.0);
  }
}

TEST(Seeding, SpheresDoNotOverlapAndAvoidTheWalls) {
  Config c = couette_case(
      16, 10, 16,
      {"grid.lx=16.0", "grid.ly=10.0", "grid.lz=16.0", "walls.velocity=5.0", "particles.radius=1.0",
       "particles.volume_fraction=0.33", "particles.capillary=0.02", "particles.min_gap=0.1"});
  auto s = seed_spheres(c);
  EXPECT_EQ(int(s.size()), 202);
  double dmin = 1e9;
  for (size_t a = 0; a < s.size(); ++a) {
    EXPECT_LE(std::abs(s[a].y), 5 - 1 - 0.1 + 1e-12);
    for (size_t b = a + 1; b < s.size(); ++b) {
      double dx = s[b].x - s[a].x, dy = s[b].y - s[a].y, dz = s[b].z - s[a].z;
      dx -= 16 * std::round(dx / 16), dz -= 16 * std::round(dz / 16);
      dmin = std::min(dmin, std::sqrt(dx * dx + dy * dy + dz * dz));
    }
  }
  EXPECT_GE(dmin, 2.1 - 1e-9);
  // a cell diagonal (sqrt 3 here) does not pack Phi = 0.33: the gap is
  // lowered towards min_gap, only as far as needed, and kept
  const double gap = seeding_gap(c);
  EXPECT_GT(gap, 0.1);
  EXPECT_LT(gap, std::sqrt(3.0));
  EXPECT_GE(dmin, 2 + gap - 1e-9);
  // deterministic: the same seed gives the same spheres
  auto again = seed_spheres(c);
  EXPECT_EQ(s[17].x, again[17].x);
  EXPECT_EQ(s[101].z, again[101].z);
}

// The default placement puts one sphere in each of n equal y strata before the
// relaxation. Independent draws (placement = "random") leave the centre of the
// spheres' y off mid-gap by ylim / sqrt(3 n) rms (the mean of n uniform draws
// on [-ylim, ylim]); strata cut that by a factor n, the relaxation's pushes
// add some back. Asserted: over 20 seeds of the dense Phi = 0.11 box (10
// spheres), the stratified rms is under a third of the independent draws'
// theory, which the random placement itself does not meet. One sphere is
// placed exactly as "random" places it.
TEST(Seeding, StratifiedPlacementSpreadsSpheresAcrossTheGap) {
  auto dense = [](const std::string& placement, int seed) {
    return couette_case(
        32, 24, 32,
        {"grid.lx=8.0", "grid.ly=6.0", "grid.lz=8.0", "walls.velocity=3.0", "particles.radius=1.0",
         "particles.volume_fraction=0.11", "particles.capillary=0.02",
         "particles.placement=\"" + placement + "\"", "particles.seed=" + std::to_string(seed)});
  };
  const int n = sphere_count(dense("random", 1));
  ASSERT_EQ(n, 10);
  const double ylim = 3 - 1 - seeding_gap(dense("random", 1)), theory = ylim / std::sqrt(3.0 * n);
  double ms[2] = {0, 0};
  const char* names[2] = {"stratified", "random"};
  for (int k = 0; k < 2; ++k) {
    for (int seed = 1; seed <= 20; ++seed) {
      double mean = 0;
      for (const Sphere& q : seed_spheres(dense(names[k], seed))) mean += q.y / n;
      ms[k] += mean * mean / 20;
    }
    if (world_rank() == 0)
      std::printf("  %s: rms of the spheres' mean y %.3f r (independent draws: %.3f r)\n", names[k],
                  std::sqrt(ms[k]), theory);
  }
  EXPECT_LT(std::sqrt(ms[0]), theory / 3);
  EXPECT_GT(std::sqrt(ms[1]), theory / 3);
  // one sphere: the same place as "random" gives it
  const auto one = [](const std::string& placement) {
    return couette_case(16, 12, 16,
                        {"grid.lx=8.0", "grid.ly=6.0", "grid.lz=8.0", "walls.velocity=3.0",
                         "particles.radius=1.0", "particles.count=1", "particles.capillary=0.2",
                         "particles.placement=\"" + placement + "\"", "particles.seed=5"});
  };
  const Sphere a = seed_spheres(one("stratified"))[0], b = seed_spheres(one("random"))[0];
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.z, b.z);
}

// Two spheres closer than a cell diagonal share cells, and their phi bands
// touch above 1/2 from the start (at 4 points per radius the study's 0.1 r is
// 0.23 of a diagonal). The default gap is at least one diagonal: in the
// dense box at 4 points per radius every pair's surfaces, and every surface
// and wall, are a diagonal apart, over 10 seeds; with min_gap_cells = 0 the
// gap is min_gap, and some pair sits closer than a diagonal.
TEST(Seeding, GapIsAtLeastACellDiagonal) {
  const double diag = 0.25 * std::sqrt(3.0);  // 32 x 24 x 32 cells on 8 x 6 x 8
  const auto closest = [](const std::vector<Sphere>& s, double& wall) {
    double d = 1e9;
    wall = 1e9;
    for (size_t a = 0; a < s.size(); ++a) {
      wall = std::min(wall, 3 - 1 - std::abs(s[a].y));
      for (size_t b = a + 1; b < s.size(); ++b) {
        double dx = s[b].x - s[a].x, dy = s[b].y - s[a].y, dz = s[b].z - s[a].z;
        dx -= 8 * std::round(dx / 8), dz -= 8 * std::round(dz / 8);
        d = std::min(d, std::sqrt(dx * dx + dy * dy + dz * dz) - 2);
      }
    }
    return d;
  };
  double fewest = 1e9, fewest_wall = 1e9, old_fewest = 1e9;
  for (int seed = 1; seed <= 10; ++seed) {
    const auto dense = [seed](const std::string& cells) {
      return couette_case(
          32, 24, 32,
          {"grid.lx=8.0", "grid.ly=6.0", "grid.lz=8.0", "walls.velocity=3.0", "particles.radius=1.0",
           "particles.volume_fraction=0.11", "particles.capillary=0.2", "particles.min_gap_cells=" + cells,
           "particles.seed=" + std::to_string(seed)});
    };
    EXPECT_NEAR(seeding_gap(dense("1.0")), diag, 1e-12);
    EXPECT_EQ(seeding_gap(dense("0.0")), 0.1);
    double wall = 0;
    fewest = std::min(fewest, closest(seed_spheres(dense("1.0")), wall));
    fewest_wall = std::min(fewest_wall, wall);
    old_fewest = std::min(old_fewest, closest(seed_spheres(dense("0.0")), wall));
  }
  if (world_rank() == 0)
    std::printf(
        "  closest surfaces: %.4f r (to a wall %.4f r); with min_gap alone %.4f r; a diagonal %.4f r\n",
        fewest, fewest_wall, old_fewest, diag);
  EXPECT_GE(fewest, diag - 1e-9);
  EXPECT_GE(fewest_wall, diag - 1e-9);
  EXPECT_LT(old_fewest, diag);
}

// A small dense box jams the relaxation below the packing bound (30 spheres,
// Phi = 0.33, 8r x 6r x 8r at 4 points per radius: a diagonal, 0.433 r, and
// the bound's largest gap, 0.333 r, both jam): the gap is lowered towards
// min_gap in steps, not below it, and the spheres keep the gap used.
TEST(Seeding, AJammedGapIsLoweredTowardsMinGap) {
  const Config c = couette_case(32, 24, 32,
                                {"grid.lx=8.0", "grid.ly=6.0", "grid.lz=8.0", "walls.velocity=3.0",
                                 "particles.radius=1.0", "particles.count=30", "particles.capillary=0.2"});
  const double gap = seeding_gap(c);
  const auto s = seed_spheres(c);
  double closest = 1e9;
  for (size_t a = 0; a < s.size(); ++a)
    for (size_t b = a + 1; b < s.size(); ++b) {
      double dx = s[b].x - s[a].x, dy = s[b].y - s[a].y, dz = s[b].z - s[a].z;
      dx -= 8 * std::round(dx / 8), dz -= 8 * std::round(dz / 8);
      closest = std::min(closest, std::sqrt(dx * dx + dy * dy + dz * dz) - 2);
    }
  if (world_rank() == 0) std::printf("  gap used %.4f r, closest surfaces %.4f r\n", gap, closest);
  EXPECT_GE(gap, 0.1);
  EXPECT_LT(gap, 0.25 * std::sqrt(3.0));
  EXPECT_GE(closest, gap - 1e-9);
}

TEST(Seeding, ImpossibleVolumeFractionIsRejected) {
  Config c =
      couette_case(16, 10, 16,
                   {"grid.lx=16.0", "grid.ly=10.0", "grid.lz=16.0", "walls.velocity=5.0",
                    "particles.radius=1.0", "particles.volume_fraction=0.55", "particles.capillary=0.1"});
  try {
    seed_spheres(c);
    FAIL() << "Phi = 0.55 was packed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot place"), std::string::npos) << e.what();
  }
}

TEST(Solid, ParticleAtRestStaysAtRestWithoutStress) {
  Config c = couette_case(16, 16, 16,
                          solid_keys({"walls.velocity=0.0", "grid.lx=2.0", "grid.lz=2.0",
                                      "particles.radius=0.5", "particles.viscosity_ratio=10.0"}));
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  for (int n = 0; n < 10; ++n) s.advance(s.stable_dt());
  FlowScalars f = Diagnostics(s).scalars();
  EXPECT_LT(f.max_speed, 1e-13);
  EXPECT_DOUBLE_EQ(f.detb_min, 1.0);
  EXPECT_DOUBLE_EQ(f.detb_max, 1.0);
}

namespace {
struct Rotation {
  double omega, xc, zc;
  KOKKOS_INLINE_FUNCTION Vec3 operator()(double x, double y, double, double) const {
    return {-omega * y, omega * (x - xc), 0.0};
  }
};
}  // namespace

namespace {
// Device loops of the tests below live outside the TEST bodies: nvcc forbids
// extended (KOKKOS_LAMBDA) lambdas in gtest's private TestBody.
// phi of a cylinder along z of radius r about (x0, y0), 4 x 4 sub-samples per cell
void fill_cylinder(const Grid& g, const Field3& phi, double r, double x0, double y0) {
  par_for(
      "test_sphere", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        int in = 0;
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b) {
            const double x = g.xc(i) + g.dx * ((a + 0.5) / 4 - 0.5) - x0,
                         y = g.yc(j) + g.dy * ((b + 0.5) / 4 - 0.5) - y0;
            in += x * x + y * y < r * r;  // a cylinder along z, the box is thin in z
          }
        phi(i, j, k) = in / 16.0;
      });
}
double constant_error(const Grid& g, const Field3& a, double value) {
  return max_error(
      g, a, KOKKOS_LAMBDA(int, int, int) { return value; });
}
}  // namespace

TEST(Solid, RigidRotationKeepsBIdentityAndMovesTheParticle) {
  // a sphere off the axis of a rigid rotation about z: B must stay I (no
  // spurious stress), det B = 1, and the centroid must turn with the flow
  Config c = couette_case(
      32, 32, 8, solid_keys({"walls.velocity=0.0", "grid.lx=2.0", "grid.lz=0.5", "particles.radius=0.3"}));
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  // move the phi of the centred sphere 0.5 to the +x side by re-seeding with a shifted centre
  const Grid g = s.grid();
  auto phi = s.solid()->fields().phi();
  const double r = 0.3, x0 = 1.5, y0 = 0.0;
  fill_cylinder(g, phi, r, x0, y0);
  s.solid()->fill_ghosts();
  const Rotation rot{1.0, 1.0, 0.25};
  ParticleTracker tr(s, {{ParticleShape{x0, y0, 0.25}}});
  tr.update();
  const double T = M_PI / 2;  // a quarter turn: (1.5, 0) -> (1.0, 0.5)
  const int steps = 200;
  for (int n = 0; n < steps; ++n) {
    transport_step(s, rot, T / steps);
    if (n % 10 == 9) tr.update();  // the centroid must not outrun the tracker
  }
  const SolidViews q(s.solid()->fields());
  double berr = 0;
  for (int m = 0; m < 6; ++m) {
    const double id = (m == 0 || m == 3 || m == 5) ? 1 : 0;
    berr = std::max(berr, constant_error(g, q.field(1 + m), id));
  }
  EXPECT_LT(berr, 1e-12);
  FlowScalars f = Diagnostics(s).scalars();
  EXPECT_NEAR(f.detb_min, 1.0, 1e-12);
  EXPECT_NEAR(f.detb_max, 1.0, 1e-12);
  tr.update();
  const auto& p = tr.shapes()[0];
  if (world_rank() == 0)
    std::printf("  centroid after a quarter turn: (%.4f, %.4f), expected (1, 0.5)\n", p.x, p.y);
  EXPECT_NEAR(p.x, 1.0, 0.5 * g.dx);
  EXPECT_NEAR(p.y, 0.5, 0.5 * g.dy);
}

namespace {
// LeVeque (SINUM 1996) 3-D deformation on the unit cube, y shifted to [-1/2, 1/2]
struct LeVeque {
  double T;
  KOKKOS_INLINE_FUNCTION Vec3 operator()(double x, double y, double z, double t) const {
    const double yy = y + 0.5, c = Kokkos::cos(M_PI * t / T);
    const double sx = Kokkos::sin(M_PI * x), sy = Kokkos::sin(M_PI * yy), sz = Kokkos::sin(M_PI * z);
    return {2 * sx * sx * Kokkos::sin(2 * M_PI * yy) * Kokkos::sin(2 * M_PI * z) * c,
            -Kokkos::sin(2 * M_PI * x) * sy * sy * Kokkos::sin(2 * M_PI * z) * c,
            -Kokkos::sin(2 * M_PI * x) * Kokkos::sin(2 * M_PI * yy) * sz * sz * c};
  }
};
}  // namespace

namespace {
// Device loops of the tests below live outside the TEST bodies: nvcc forbids
// extended (KOKKOS_LAMBDA) lambdas in gtest's private TestBody.
// The fraction of cell (i, j, k)'s 4^3 sub-samples at which inside(x, y, z)
// holds, (x, y, z) relative to (x0, y0, z0): the sampled phi of a body.
template <class Inside>
KOKKOS_INLINE_FUNCTION double sampled_fraction(const Grid& g, int i, int j, int k, double x0, double y0,
                                               double z0, const Inside& inside) {
  int in = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      for (int e = 0; e < 4; ++e)
        in += inside(g.xc(i) + g.dx * ((a + 0.5) / 4 - 0.5) - x0, g.yc(j) + g.dy * ((b + 0.5) / 4 - 0.5) - y0,
                     g.zc(k) + g.dz * ((e + 0.5) / 4 - 0.5) - z0);
  return in / 64.0;
}
// x^T M x < r^2 for M = [[xx, xy, 0], [xy, yy, 0], [0, 0, 1]] (a ball for M = I)
struct InsideEllipsoid {
  double xx, xy, yy, r2;
  KOKKOS_INLINE_FUNCTION bool operator()(double x, double y, double z) const {
    return xx * x * x + 2 * xy * x * y + yy * y * y + z * z < r2;
  }
};
// phi of the sphere of radius 0.15 about (0.35, -0.15, 0.35)
void fill_leveque_sphere(const Grid& g, const Field3& phi) {
  const InsideEllipsoid ball{1, 0, 1, 0.15 * 0.15};
  par_for(
      "test_leveque_sphere", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        phi(i, j, k) = sampled_fraction(g, i, j, k, 0.35, -0.15, 0.35, ball);
      });
}
// sum of |phi - phi0| over the local interior
double local_l1_difference(const Grid& g, const Field3& phi, const Field3& phi0) {
  double l1 = 0;
  par_reduce(
      "test_l1", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) { a += Kokkos::fabs(phi(i, j, k) - phi0(i, j, k)); },
      Kokkos::Sum<double>(l1));
  return l1;
}

// Interface thickness in cells: the volume of the cells with 0.01 < phi < 0.99
// over the surface area (sum |grad phi| dV, central differences) times dx
double interface_thickness(const Grid& g, const Field3& phi) {
  double area = 0;
  par_reduce(
      "test_area", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) {
        const double gx = (phi(i + 1, j, k) - phi(i - 1, j, k)) / (2 * g.dx);
        const double gy = (phi(i, j + 1, k) - phi(i, j - 1, k)) / (2 * g.dy);
        const double gz = (phi(i, j, k + 1) - phi(i, j, k - 1)) / (2 * g.dz);
        a += Kokkos::sqrt(gx * gx + gy * gy + gz * gz);
      },
      Kokkos::Sum<double>(area));
  return interface_cells(g, phi) / global_sum(area) / g.dx;
}

struct LeVequeResult {
  double l1, thickness;
};
LeVequeResult run_leveque(int n, const std::string& scheme) {
  const LeVeque flow{1.5};  // half the classic period: resolvable at 16^3 and 32^3
  Config c = couette_case(n, n, n,
                          solid_keys({"walls.velocity=0.0", "grid.lx=1.0", "grid.ly=1.0", "grid.lz=1.0",
                                      "particles.radius=0.15", "particles.phi_scheme=" + scheme}));
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  const Grid g = s.grid();
  auto phi = s.solid()->fields().phi();
  fill_leveque_sphere(g, phi);
  s.solid()->fill_ghosts();
  Field3 phi0("phi0", g.sx(), g.sy(), g.sz());
  Kokkos::deep_copy(phi0, phi);
  const double v0 = Diagnostics(s).scalars().solid_volume;
  const int steps = 8 * n;  // CFL about 0.4 at the peak speed 2
  for (int k = 0; k < steps; ++k) transport_step(s, flow, flow.T / steps);
  FlowScalars f = Diagnostics(s).scalars();
  double l1 = local_l1_difference(g, phi, phi0);
  l1 = global_sum(l1) * g.dx * g.dy * g.dz;
  const double th = interface_thickness(g, phi);
  if (world_rank() == 0)
    std::printf(
        "  %s n = %d  L1 shape error %.3e  volume drift %.2e  phi in [%.2e, %.6f]  thickness %.2f cells\n",
        scheme.c_str(), n, l1, f.solid_volume / v0 - 1, f.phi_min, f.phi_max, th);
  EXPECT_NEAR(f.solid_volume / v0, 1.0, 1e-12);
  EXPECT_GE(f.phi_min, 0.0);
  EXPECT_LE(f.phi_max, 1.0);
  return {l1, th};
}
}  // namespace

// Both phi schemes return the sphere, conserve its volume to round-off and
// keep phi in [0, 1]. The L1 error of a sharp (0 to 1) profile converges at
// most at first order (ratio 0.5 per halving); 16^3 resolves the sphere's
// radius by 2.4 cells only.
TEST(Solid, LeVequeDeformationReturnsTheSphereAndConservesVolume) {
  for (const std::string scheme : {"weno5", "thinc", "mthinc"}) {
    const LeVequeResult a = run_leveque(16, scheme), b = run_leveque(32, scheme);
    const double q = std::log(a.l1 / b.l1) / std::log(2.0);
    if (world_rank() == 0) std::printf("  %s: observed L1 order %.2f\n", scheme.c_str(), q);
    EXPECT_LT(b.l1, 0.75 * a.l1) << scheme << ": the shape error must decrease under refinement";
    // the bound: below 3 cells after the deformation (at rest, the
    // sampled sphere's band is about 1.3 cells)
    if (scheme != "weno5") EXPECT_LT(b.thickness, 3.0);
  }
}

namespace {
// Device loop outside the TEST body (nvcc). A sphere of radius r about c,
// deformed homogeneously by F = R(theta) diag(s, 1/s, 1): phi is the fraction
// of the ellipsoid x^T Bt^-1 x < r^2 (4^3 sub-samples per cell), and the
// stored B is b everywhere (Bt the true deformation, b what the solid records).
struct Ellipse2 {
  double xx, xy, yy;  // x-y block of a symmetric matrix, zz = 1, no z coupling
};
Ellipse2 stretched(double s, double theta) {
  const double c = std::cos(theta), n = std::sin(theta), a = s * s, b = 1 / (s * s);
  return {a * c * c + b * n * n, (a - b) * c * n, a * n * n + b * c * c};
}
void fill_ellipsoid(const Grid& g, const SolidViews& q, Ellipse2 bt, Ellipse2 b, double r, double x0,
                    double y0, double z0) {
  const double det = bt.xx * bt.yy - bt.xy * bt.xy;
  const InsideEllipsoid body{bt.yy / det, -bt.xy / det, bt.xx / det, r * r};  // Bt^-1, x-y block
  par_for(
      "test_ellipsoid", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        q.phi(i, j, k) = sampled_fraction(g, i, j, k, x0, y0, z0, body);
        q.b0(i, j, k) = b.xx, q.b1(i, j, k) = b.xy, q.b2(i, j, k) = 0;
        q.b3(i, j, k) = b.yy, q.b4(i, j, k) = 0, q.b5(i, j, k) = 1;
      });
}
}  // namespace

// The tracker's two measures of a particle's shape: the second moments of
// phi, and the ellipsoid x^T <B>^-1 x = r^2 the solid's recorded deformation
// implies. On a homogeneously deformed sphere (stretch 1.25 at 30 degrees:
// T = (s^2 - 1) / (s^2 + 1) = 0.2195) both give the exact T and inclination;
// when the stored B says "undeformed" (B = I) while phi is stretched, the
// B measure reads 0 and the gap between the two is the drift it reports.
// Tolerances: the B measure is exact for uniform B (round-off). The phi
// moments see a staircase ellipsoid (6.4 points per radius, 4^3 sub-samples
// per cell: 26 sub-samples per radius), whose moments are off by up to
// O(h_sub / r) = 4% (1.1% measured on T, 0.04 degrees on the inclination):
// the phi T must be within the 5% for T, its angle within 0.1 degree.
TEST(Solid, TrackerShapeFromPhiAndFromBAgreeOnAHomogeneousDeformation) {
  Config c = couette_case(32, 32, 32, solid_keys({"walls.velocity=0.0", "grid.lx=2.0", "grid.lz=2.0"}));
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  const Grid g = s.grid();
  const SolidViews q(s.solid()->fields());
  const double r = 0.4, st = 1.25, th = M_PI / 6, exact = (st * st - 1) / (st * st + 1);
  const Ellipse2 bt = stretched(st, th);
  for (bool consistent : {true, false}) {
    fill_ellipsoid(g, q, bt, consistent ? bt : Ellipse2{1, 0, 1}, r, 1.0, 0.0, 1.0);
    ParticleTracker tr(s, {{ParticleShape{1.0, 0.0, 1.0}}});
    tr.update();
    const auto& p = tr.shapes()[0];
    if (world_rank() == 0)
      std::printf("  B %s: T from phi %.5f at %.3f deg, from B %.5f at %.3f deg; exact %.5f at 30 deg\n",
                  consistent ? "consistent" : "= I     ", p.taylor, p.angle * 180 / M_PI, p.taylor_b,
                  p.angle_b * 180 / M_PI, exact);
    EXPECT_NEAR(p.taylor, exact, 0.05 * exact);
    EXPECT_NEAR(p.angle, th, 0.1 * M_PI / 180);
    if (consistent) {
      EXPECT_NEAR(p.taylor_b, exact, 1e-12);
      EXPECT_NEAR(p.angle_b, th, 1e-12);
    } else {
      EXPECT_NEAR(p.taylor_b, 0.0, 1e-12);
    }
  }
}

namespace {
// Device loop outside the TEST body (nvcc): phi of body a about ca, plus
// body b about cb when b.r2 > 0 (the two do not overlap)
void fill_two_bodies(const Grid& g, const Field3& phi, const InsideEllipsoid& a, const double ca[3],
                     const InsideEllipsoid& b, const double cb[3]) {
  const double ax = ca[0], ay = ca[1], az = ca[2], bx = cb[0], by = cb[1], bz = cb[2];
  par_for(
      "test_two_bodies", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        double f = sampled_fraction(g, i, j, k, ax, ay, az, a);
        if (b.r2 > 0) f += sampled_fraction(g, i, j, k, bx, by, bz, b);
        phi(i, j, k) = f;
      });
}
// adds phi = value to the cells whose centre lies within 0.6 dx of the
// segment from c + from e to c + to e (e a unit vector): a thread of solid
// shed into the fluid, thinner than a cell
void add_wisp(const Grid& g, const Field3& phi, const double c[3], const double e[3], double from, double to,
              double value) {
  const double cx = c[0], cy = c[1], cz = c[2], ex = e[0], ey = e[1], ez = e[2];
  par_for(
      "test_wisp", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        const double dx = g.xc(i) - cx, dy = g.yc(j) - cy, dz = g.zc(k) - cz;
        const double t = dx * ex + dy * ey + dz * ez;
        const double px = dx - t * ex, py = dy - t * ey, pz = dz - t * ez;
        if (t > from && t < to && px * px + py * py + pz * pz < 0.36 * g.dx * g.dx) phi(i, j, k) += value;
      });
}
}  // namespace

// The tracker's reach follows each particle's shape. A sphere stretched to
// the dilute Ca = 2 shape (semi-axes 2.6 r, r / 2.6, r, at 20 degrees: T =
// 0.742) has its tips beyond the seeded sphere's 2 r. The first update,
// which still uses that reach, cuts them: an ellipsoid's caps beyond
// x = t a hold (1 - t)^2 (2 + t) / 4 of its volume each, 7.4% for both at
// t = 2 / 2.6, and T then reads 5.6% low, outside the 5%. After two
// more updates the reach (the measured ellipsoid, grown) holds the whole
// particle. Then a sphere is put 1.2 r beyond its tip: the nearest-centroid
// split of the first update gives the sphere the caps beyond the bisector at
// 1.9 r (4.9% of a volume); the ellipsoid metric gives each particle its own
// cells. Tolerances: the staircase moments at 8 points per radius, 4^3
// sub-samples per cell, are good to O(h_sub / r) = 3% (the homogeneous-
// deformation test above; 0.6% measured here), so T within the 5%;
// each volume within 1% (the sampled volume is good to 0.1%). Last, a thin
// thread of solid (phi = 0.05) runs on from the tip to 5.5 r: the reach
// comes from the core (phi > 0.5), so it takes in the thread up to ~4 r and
// stays there (a reach from all the cells would widen with the thread and
// take in more of it at every update).
TEST(Solid, TrackerReachFollowsALongParticleAndSplitsNeighboursWhereTheirEllipsoidsMeet) {
  const double r = 0.25, st = 2.6, th = 20 * M_PI / 180, exact = (st * st - 1) / (st * st + 1);
  Config c = couette_case(96, 48, 64,
                          solid_keys({"walls.velocity=0.0", "grid.lx=3.0", "grid.ly=1.5", "grid.lz=2.0",
                                      "particles.radius=0.25"}));
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  const Grid g = s.grid();
  const SolidViews q(s.solid()->fields());
  const Ellipse2 bt = stretched(st, th);
  const double det = bt.xx * bt.yy - bt.xy * bt.xy, v0 = 4.0 / 3.0 * M_PI * r * r * r;
  const InsideEllipsoid body{bt.yy / det, -bt.xy / det, bt.xx / det, r * r}, ball{1, 0, 1, r * r};
  const double cl[3] = {1.0, 0.0, 1.0}, dist = (st + 1.2) * r;
  const double cb[3] = {1.0 + dist * std::cos(th), dist * std::sin(th), 1.0};
  for (bool neighbour : {false, true}) {
    fill_two_bodies(g, q.phi, body, cl, neighbour ? ball : InsideEllipsoid{1, 0, 1, 0}, cb);
    std::vector<ParticleShape> start = {ParticleShape{cl[0], cl[1], cl[2]}};
    if (neighbour) start.push_back(ParticleShape{cb[0], cb[1], cb[2]});
    ParticleTracker tr(s, start);
    double first_T = 0, first_v = 0;  // the first update's T of the long particle, volume of the last
    for (int n = 0; n < 3; ++n) {
      tr.update();
      if (n == 0) first_T = tr.shapes()[0].taylor, first_v = tr.shapes().back().volume;
    }
    const auto& p = tr.shapes();
    if (world_rank() == 0)
      std::printf(
          "  %s: first update T %.4f, %s volume %.4f v0; third T %.4f (exact %.4f), volumes %.4f, %.4f v0\n",
          neighbour ? "with a sphere beyond the tip" : "alone", first_T, neighbour ? "sphere" : "long",
          first_v / v0, p[0].taylor, exact, p[0].volume / v0, p.back().volume / v0);
    EXPECT_NEAR(p[0].taylor, exact, 0.05 * exact);
    EXPECT_NEAR(p[0].volume, v0, 0.01 * v0);
    if (neighbour) {
      EXPECT_NEAR(p.back().volume, v0, 0.01 * v0);
      EXPECT_GT(first_v, 1.03 * v0) << "the first update (nearest centroid) should give the sphere the tip";
    } else {
      EXPECT_LT(first_v, 0.95 * v0) << "the first update (2 r reach) should cut the tips";
      EXPECT_LT(first_T, 0.95 * exact) << "the first update (2 r reach) should cut the tips";
    }
  }
  fill_two_bodies(g, q.phi, body, cl, InsideEllipsoid{1, 0, 1, 0}, cb);
  const double axis[3] = {std::cos(th), std::sin(th), 0.0};
  add_wisp(g, q.phi, cl, axis, st * r, 5.5 * r, 0.05);
  s.solid()->fill_ghosts();
  const double total = Diagnostics(s).scalars().solid_volume;
  ParticleTracker tr(s, {{ParticleShape{cl[0], cl[1], cl[2]}}});
  std::vector<double> vol;
  for (int n = 0; n < 6; ++n) tr.update(), vol.push_back(tr.shapes()[0].volume);
  if (world_rank() == 0)
    std::printf(
        "  with a thread to 5.5 r: volume after 3 updates %.5f v0, after 6 %.5f v0, all solid %.5f v0\n",
        vol[2] / v0, vol[5] / v0, total / v0);
  EXPECT_EQ(vol[5], vol[2]) << "the reach must not widen with the thread";
  EXPECT_GT(vol[2], v0) << "the thread's start belongs to the particle";
  EXPECT_LT(vol[2], total) << "the thread's far end is beyond reach";
}

// With one colour field per particle the tracker measures each particle from
// its own colour (within its reach), so a particle touching another keeps
// its whole shape: the long particle of the test above with the sphere
// against its tip (surfaces touching), where splitting the summed phi by the
// nearest reach hands part of one to the other.
TEST(Solid, TrackerWithColoursMeasuresEachParticleFromItsOwnColour) {
  const double r = 0.25, st = 2.6, th = 20 * M_PI / 180, exact = (st * st - 1) / (st * st + 1);
  const double v0 = 4.0 / 3.0 * M_PI * r * r * r;
  const Ellipse2 bt = stretched(st, th);
  const double det = bt.xx * bt.yy - bt.xy * bt.xy;
  const InsideEllipsoid body{bt.yy / det, -bt.xy / det, bt.xx / det, r * r}, ball{1, 0, 1, r * r};
  const double cl[3] = {1.0, 0.0, 1.0}, dist = (st + 1.0) * r;
  const double cb[3] = {1.0 + dist * std::cos(th), dist * std::sin(th), 1.0};
  auto measure = [&](int colours) {
    Config c = couette_case(96, 48, 64,
                            solid_keys({"walls.velocity=0.0", "grid.lx=3.0", "grid.ly=1.5", "grid.lz=2.0",
                                        "particles.radius=0.25"}));
    c.particles.count = 2;
    c.particles.placement = "random";
    c.particles.colour_fields = colours;
    FlowSolver s(c, MPI_COMM_WORLD);
    s.initialize();
    const Grid g = s.grid();
    const SolidViews q(s.solid()->fields());
    const InsideEllipsoid none{1, 0, 1, 0};
    if (colours > 0) {
      fill_two_bodies(g, s.solid()->colours().colour(0), body, cl, none, cb);
      fill_two_bodies(g, s.solid()->colours().colour(1), ball, cb, none, cb);
    }
    fill_two_bodies(g, q.phi, body, cl, ball, cb);
    ParticleTracker tr(s, {ParticleShape{cl[0], cl[1], cl[2]}, ParticleShape{cb[0], cb[1], cb[2]}});
    for (int n = 0; n < 3; ++n) tr.update();
    return tr.shapes();
  };
  const auto own = measure(2), split = measure(0);
  if (world_rank() == 0)
    std::printf(
        "  touching: colours T %.4f (exact %.4f), volumes %.4f, %.4f v0; summed phi split: T %.4f, "
        "volumes %.4f, %.4f v0\n",
        own[0].taylor, exact, own[0].volume / v0, own[1].volume / v0, split[0].taylor, split[0].volume / v0,
        split[1].volume / v0);
  // each colour's sampled volume is v0 to 4e-4 (the lone body above): 5x
  // that, where the split moves 0.9% of the sphere's volume between them
  EXPECT_NEAR(own[0].taylor, exact, 0.05 * exact);
  EXPECT_NEAR(own[0].volume, v0, 0.002 * v0);
  EXPECT_NEAR(own[1].volume, v0, 0.002 * v0);
  EXPECT_NEAR(own[1].taylor, 0.0, 0.01);
}

namespace {
// phi carried by THINC alone: a 6 x 6 x 6 box at 4 points per radius
// (r = 1), walls at rest, for the prescribed-velocity tests below
Config thinc_transport_box(const std::string& scheme = "thinc") {
  return couette_case(24, 24, 24,
                      solid_keys({"walls.velocity=0.0", "grid.lx=6.0", "grid.ly=6.0", "grid.lz=6.0",
                                  "particles.radius=1.0", "particles.phi_scheme=\"" + scheme + "\""}));
}
}  // namespace

// phi alone, carried by THINC and by MTHINC in the velocity of a steady
// tank-treading particle (stretch 1.25 at 32 degrees, T = 0.22, the dilute
// Ca = 0.2 shape; material turning at gamma / 2 = 0.5 for 50 time units, the
// strain of the issue-12 stationarity windows) at 4 points per radius, and a
// sphere in rigid rotation. The transport by itself is stationary: the shape
// settles within ~10 time units to its discrete form and T then agrees over
// [10, 30) and [30, 50) within the 1%; the rotating sphere stays a
// sphere (T < 1e-3). Settled T against the sampled one: THINC 3.8% below,
// MTHINC 0.4% below. This flow has no z component; turned about a tilted
// axis, THINC does drift (the tests at the end of this file), and so does the
// coupled run, along z.
TEST(Solid, ThincShapeIsStationaryInASteadyTankTreadingFlow) {
  for (const std::string scheme : {"thinc", "mthinc"})
    for (const double st : {1.25, 1.0}) {
      Config c = thinc_transport_box(scheme);
      FlowSolver s(c, MPI_COMM_WORLD);
      s.initialize();
      const Grid g = s.grid();
      const SolidViews q(s.solid()->fields());
      const double th = 32 * M_PI / 180;
      fill_ellipsoid(g, q, stretched(st, th), Ellipse2{1, 0, 1}, 1.0, 3.0, 0.0, 3.0);
      s.solid()->fill_ghosts();
      const double v0 = Diagnostics(s).scalars().solid_volume;
      const TankTreading flow{0.5, st, 1 / st, std::cos(th), std::sin(th), 3.0};
      ParticleTracker tr(s, {{ParticleShape{3.0, 0.0, 3.0}}});
      tr.update();
      const double T0 = tr.shapes()[0].taylor;  // the sampled shape's (2.7% below the exact 0.2195)
      const double dt = 0.05;                   // CFL 0.3 at the box corners
      double w1 = 0, w2 = 0, tmax = 0;
      int n1 = 0, n2 = 0;
      for (int n = 1; n <= 1000; ++n) {
        transport_step(s, flow, dt);
        if (n % 10) continue;
        tr.update();
        const double T = tr.shapes()[0].taylor, t = n * dt;
        tmax = std::max(tmax, T);
        if (t > 10 && t <= 30) w1 += T, ++n1;
        if (t > 30) w2 += T, ++n2;
      }
      w1 /= n1, w2 /= n2;
      const FlowScalars f = Diagnostics(s).scalars();
      if (world_rank() == 0)
        std::printf(
            "  %s stretch %.2f: T at 0 %.4f, over (10, 30] %.4f, over (30, 50] %.4f, max %.2e, volume drift "
            "%.1e\n",
            scheme.c_str(), st, T0, w1, w2, tmax, f.solid_volume / v0 - 1);
      EXPECT_NEAR(f.solid_volume / v0, 1.0, 1e-12);
      if (st > 1) {
        EXPECT_NEAR(w2, w1, 0.01 * w2);
        EXPECT_NEAR(w2, T0, 0.05 * T0);  // the settling: within the 5% for T
      } else {
        EXPECT_LT(tmax, 1e-3);
      }
    }
}

namespace {
// Rigid rotation at rate w about the unit axis (ax, 0, az) through (xc, 0, zc)
struct TiltedRotation {
  double w, ax, az, xc, zc;
  KOKKOS_INLINE_FUNCTION Vec3 operator()(double x, double y, double z, double) const {
    const double X = x - xc, Z = z - zc;
    return {-w * az * y, w * (az * X - ax * Z), w * ax * y};
  }
};
}  // namespace

namespace {
// A sphere (4 points per radius) turned rigidly by `scheme` at rate 0.5 about
// an axis tilted 45 degrees from z, for 50 time units (4 turns): the
// anisotropy (a - c) / (a + c) of its 3-D axes at the end
double tilted_turn_anisotropy(const std::string& scheme) {
  Config c = thinc_transport_box(scheme);
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  const Grid g = s.grid();
  const SolidViews q(s.solid()->fields());
  const double cb[3] = {0, 0, 0};
  fill_two_bodies(g, q.phi, InsideEllipsoid{1, 0, 1, 1.0}, std::array<double, 3>{3.0, 0.0, 3.0}.data(),
                  InsideEllipsoid{1, 0, 1, 0}, cb);
  s.solid()->fill_ghosts();
  const double tilt = M_PI / 4;
  const TiltedRotation flow{0.5, std::sin(tilt), std::cos(tilt), 3.0, 3.0};
  for (int n = 0; n < 1000; ++n) transport_step(s, flow, 0.05);
  ParticleTracker tr(s, {{ParticleShape{3.0, 0.0, 3.0}}});
  tr.update();
  const auto& p = tr.shapes()[0];
  const double aniso = (p.a - p.c) / (p.a + p.c);
  if (world_rank() == 0)
    std::printf("  %s: axes %.4f %.4f %.4f: (a - c) / (a + c) = %.4f\n", scheme.c_str(), p.a, p.b, p.c,
                aniso);
  return aniso;
}
}  // namespace

// phi's transport must not change a shape by turning it (issue 12): the
// sphere above must stay round, (a - c) / (a + c) below 1% (about z,
// ThincShapeIsStationary... above, it stays below 1e-3). MTHINC gives 0.0017
// (0.0020 at beta 2.5, 0.0018 at beta 5), one step across each interface
// cell along its normal.
TEST(Solid, MthincKeepsASphereRoundTurningAboutATiltedAxis) {
  EXPECT_LT(tilted_turn_anisotropy("mthinc"), 0.01);
}

// The same with THINC direction by direction, disabled because it fails:
// each direction's step has the steepness beta whatever the interface's
// orientation, so the compression is anisotropic. Measured at t = 50: THINC
// beta 3.5 0.056 (it grows steadily: 0.010, 0.022, 0.031, 0.042 at t =
// 10..40); with beta scaled in each direction by the interface normal's
// component (tried in round 6, not kept) 0.032; THINC beta 3.0 0.015, beta
// 2.5 0.0015, beta 2 0.003, WENO5 0.008; beta 3.5 at 8 points per radius
// 0.017. This is the transport's part of the coupled runs' shape drift
// (results/README.md, "Where phi's shape goes"). Run it with
// --gtest_also_run_disabled_tests.
TEST(Solid, DISABLED_ThincKeepsASphereRoundTurningAboutATiltedAxis) {
  EXPECT_LT(tilted_turn_anisotropy("thinc"), 0.01);
}

namespace {
// the share of phi's volume in cells with phi < 0.1 (the issue-12 measure)
double low_phi_share(const Grid& g, const Field3& phi) {
  double low = 0, all = 0;
  par_reduce(
      "test_low_phi", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) { a += phi(i, j, k) < 0.1 ? phi(i, j, k) : 0.0; },
      Kokkos::Sum<double>(low));
  par_reduce(
      "test_all_phi", g.interior(), KOKKOS_LAMBDA(int i, int j, int k, double& a) { a += phi(i, j, k); },
      Kokkos::Sum<double>(all));
  return global_sum(low) / global_sum(all);
}
void fill_blade(const Grid& g, const Field3& phi, InsideEllipsoid e, double x0, double z0) {
  par_for(
      "test_blade", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k) { phi(i, j, k) = sampled_fraction(g, i, j, k, x0, 0.0, z0, e); });
}

// A velocity of the flat-layer odd-even mode added to a flow: u + A (-1)^j
// (divergence-free: u varies with y only), j the cell row from the lower wall
template <class F>
struct WithOddEvenU {
  F flow;
  double amplitude, dy, ly;
  KOKKOS_INLINE_FUNCTION Vec3 operator()(double x, double y, double z, double t) const {
    Vec3 q = flow(x, y, z, t);
    const int j = int(Kokkos::floor((y + ly / 2) / dy));
    q.u += (j % 2 ? amplitude : -amplitude);
    return q;
  }
};
// The dilute Ca = 2 particle (K = 1, the exact steady shape of
// shared/spec/dilute_theory.csv: semi-axes 2.6054 and 0.3459 r in the shear
// plane at 7.56 degrees, 1.1097 r along z), and the rate w = 1 / (a / b +
// b / a) at which its material turns when its interior vorticity is gamma = 1
struct Ca2Blade {
  double a = 2.6054, b = 0.3459, cz = 1.1097, co = std::cos(7.5622 * M_PI / 180),
         si = std::sin(7.5622 * M_PI / 180), w = 1 / (a / b + b / a);
};
// phi's scheme alone in an lx x 6r x 6r box at `ppr` points per radius,
// walls at rest, with the blade sampled about (lx / 2, 0, 3)
std::unique_ptr<FlowSolver> blade_box(const std::string& scheme, int ppr, double lx) {
  const Ca2Blade k;
  Config cfg = couette_case(
      int(lx) * ppr, 6 * ppr, 6 * ppr,
      solid_keys({"walls.velocity=0.0", "grid.lx=" + std::to_string(lx), "grid.ly=6.0", "grid.lz=6.0",
                  "particles.radius=1.0", "particles.phi_scheme=\"" + scheme + "\""}));
  auto s = std::make_unique<FlowSolver>(cfg, MPI_COMM_WORLD);
  s->initialize();
  // inside: c^2 R diag(1/a^2, 1/b^2) R^T (x-y block) + z^2 < c^2
  const double ia = k.cz * k.cz / (k.a * k.a), ib = k.cz * k.cz / (k.b * k.b);
  const InsideEllipsoid e{ia * k.co * k.co + ib * k.si * k.si, (ia - ib) * k.co * k.si,
                          ia * k.si * k.si + ib * k.co * k.co, k.cz * k.cz};
  fill_blade(s->grid(), s->solid()->fields().phi(), e, lx / 2, 3.0);
  s->solid()->fill_ghosts();
  return s;
}
// the share of the solid in phi < 0.1 cells every 10 time units from t = 0
// to t_end, advancing by step(dt) with dt = 0.1 / ppr (Courant number 0.4
// at the 8r box's corners in the tank-treading flow)
template <class Step>
std::vector<double> low_phi_shares(FlowSolver& s, int ppr, double t_end, const Step& step) {
  const double dt = 0.1 / ppr;
  const int every = int(std::lround(10 / dt)), steps = int(std::lround(t_end / dt));
  std::vector<double> shares;
  for (int n = 0; n <= steps; ++n) {
    if (n % every == 0) shares.push_back(low_phi_share(s.grid(), s.solid()->fields().phi()));
    if (n < steps) step(dt);
  }
  return shares;
}
// the blade carried by `scheme` in its own tank-treading flow (8r box), with
// the flat-layer mode's velocity odd_even added
std::vector<double> blade_low_phi_shares(const std::string& scheme, int ppr, double t_end,
                                         double odd_even = 0) {
  const Ca2Blade k;
  auto s = blade_box(scheme, ppr, 8.0);
  const Grid g = s->grid();
  const WithOddEvenU<TankTreading> flow{{k.w, k.a, k.b, k.co, k.si, 4.0}, odd_even, g.dy, g.ly};
  return low_phi_shares(*s, ppr, t_end, [&](double dt) { transport_step(*s, flow, dt); });
}
}  // namespace

// Issue 12's dilute Ca = 2 run at 4 ppr ends with 10.4% of its elastic
// stress in phi < 0.1 cells (bound 5%), while the exact particle sampled on
// that grid has 1.2% there (scripts/exact_share.py). Is it phi's transport?
// Carried alone in the particle's own steady flow, MTHINC's share settles
// within 10 time units (its tanh profile against the sampled cut) and then
// stays below the 5% with no growth: 0.96% at 0, then 3.11%, 3.33%,
// 3.21% at 10, 20, 30 (3.1-4.1% to 50). So the coupled run's loss is not
// the transport of the blade by itself. The bound can fail: THINC's share
// (one plane per direction) grows, 5.02%, 6.68%, 7.31%, and WENO5's faster
// (8.0% to 14.7%). Tolerances: 5% is the bound; growth from t = 10
// to 30 below 20% (MTHINC 3%, THINC 46%).
TEST(Solid, MthincHoldsTheCa2BladeInItsOwnTankTreadingFlow) {
  const std::vector<double> m = blade_low_phi_shares("mthinc", 4, 30),
                            t = blade_low_phi_shares("thinc", 4, 30);
  if (world_rank() == 0)
    std::printf(
        "  share in phi < 0.1 cells at t = 0, 10, 20, 30: MTHINC %.2f%% %.2f%% %.2f%% %.2f%%, THINC %.2f%% "
        "%.2f%% %.2f%% %.2f%%\n",
        100 * m[0], 100 * m[1], 100 * m[2], 100 * m[3], 100 * t[0], 100 * t[1], 100 * t[2], 100 * t[3]);
  ASSERT_EQ(m.size(), 4u);
  for (std::size_t k = 1; k < m.size(); ++k) EXPECT_LT(m[k], 0.05) << "t = " << 10 * k;
  EXPECT_LT(m[3], 1.2 * m[1]) << "MTHINC's share must not grow once settled";
  EXPECT_GT(t[3], 0.05) << "THINC's share was expected above the bound (the test's contrast)";
}

// All three schemes to t = 50 (about 1 minute on one thread)
TEST(Solid, DISABLED_BladeInItsOwnTankTreadingFlowEveryScheme) {
  for (const std::string scheme : {"weno5", "thinc", "mthinc"}) {
    const std::vector<double> sh = blade_low_phi_shares(scheme, 4, 50);
    std::printf("  %s, 4 ppr, share in phi < 0.1 cells at t = 0, 10, ...:", scheme.c_str());
    for (double v : sh) std::printf(" %.2f%%", 100 * v);
    std::printf("\n");
  }
}

// MTHINC's share with the flat-layer mode's velocity added, amplitudes 0,
// 4.4e-3 (the coupled Ca = 2 blade's at strain 10) and 8.8e-3
TEST(Solid, DISABLED_BladeWithAnOddEvenVelocity) {
  for (const double amp : {0.0, 4.4e-3, 8.8e-3}) {
    const std::vector<double> sh = blade_low_phi_shares("mthinc", 4, 50, amp);
    std::printf("  mthinc, 4 ppr, odd-even u %.1e: share at t = 0, 10, ...:", amp);
    for (double v : sh) std::printf(" %.2f%%", 100 * v);
    std::printf("\n");
  }
}

namespace {
// A steady 2-D flow with the blade's surface as a streamline: inside, the
// blade's tank-treading (stream function psi = W rho^2 / 2, rho^2 =
// X^2/a^2 + Y^2/b^2 in the body frame, W = w a b, turning with the shear);
// outside, open streamlines that become simple shear u = y away from it,
// psi = W/2 + (rho^2 - 1) [W/2 chi + (1 - chi) y^2 / (2 rho^2)], chi =
// exp(-(rho - 1) / 0.5): psi and the velocity are continuous at the
// surface. u and v come from psi at the cell corners (u = d psi / dy,
// v = -d psi / dx), so the discrete divergence is zero.
struct OpenBladeFlow {
  double W, a, b, c, n, xc;
  KOKKOS_INLINE_FUNCTION double psi(double x, double y) const {
    const double X = c * (x - xc) + n * y, Y = -n * (x - xc) + c * y;
    const double r2 = X * X / (a * a) + Y * Y / (b * b);
    if (r2 <= 1) return 0.5 * W * r2;
    const double chi = Kokkos::exp(-(Kokkos::sqrt(r2) - 1) / 0.5);
    return 0.5 * W + (r2 - 1) * (0.5 * W * chi + (1 - chi) * y * y / (2 * r2));
  }
};
void set_open_blade_velocity(FlowSolver& s, const OpenBladeFlow& f) {
  const Grid g = s.grid();
  auto u = s.state().u, v = s.state().v, w = s.state().w;
  par_for(
      "test_open_blade_velocity", g.all(), KOKKOS_LAMBDA(int i, int j, int k) {
        u(i, j, k) = (f.psi(g.xf(i), g.yf(j)) - f.psi(g.xf(i), g.yf(j - 1))) / g.dy;
        v(i, j, k) = -(f.psi(g.xf(i), g.yf(j)) - f.psi(g.xf(i - 1), g.yf(j))) / g.dx;
        w(i, j, k) = 0;
      });
}
}  // namespace

// MTHINC carrying the blade in that flow: open streamlines outside it, as
// in the coupled run, against the closed ones of its own tank-treading
TEST(Solid, DISABLED_BladeWithOpenStreamlinesOutside) {
  const Ca2Blade k;
  auto s = blade_box("mthinc", 4, 16.0);
  const OpenBladeFlow flow{k.w * k.a * k.b, k.a, k.b, k.co, k.si, 8.0};
  const std::vector<double> sh = low_phi_shares(*s, 4, 50, [&](double dt) {
    s->solid()->begin_step();
    for (int st = 0; st < Rk3::stages; ++st) {
      set_open_blade_velocity(*s, flow);
      impermeable_walls(*s);
      s->solid()->advance_stage(s->state(), Rk3::gamma[st] * dt, Rk3::zeta[st] * dt, st == Rk3::stages - 1);
      s->solid()->end_stage();
    }
  });
  std::printf("  mthinc, 4 ppr, open streamlines outside: share at t = 0, 10, ...:");
  for (double v : sh) std::printf(" %.2f%%", 100 * v);
  std::printf("\n");
}
