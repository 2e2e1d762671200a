// Particle identity for diagnostics: tracked centroids and shapes.
//
// Each particle keeps a centroid and its last measured ellipsoid, replicated
// on every rank. With one colour field per particle (particles.colour_fields,
// the default for two or more), a particle is the cells of its own colour
// within its reach (below), with the colour as its fraction there. Otherwise
// a cell with phi > 0 belongs to the particle it is nearest
// to in that particle's own metric: the ellipsoid of its core (phi > 0.5)
// with each semi-axis grown by r / 2 (the diffuse band), and a cell is within
// reach below 4/3 of it.
// For the seeded sphere that is the nearest centroid within 2 r; a particle
// stretched to a = 2.6 r (dilute Ca = 2) reaches 4.1 r along its long axis
// and 1.1 r across its thin one, so its tips are kept and a neighbour's are
// not taken (a fixed 2 r cut both ways). Near contact this splits two
// particles where their ellipsoids meet instead of merging them (as
// connected components of phi > 0.5 would), it does not care about periodic
// or rank boundaries, and it costs one pass over the cells per update.
// update() moves each centroid to the phi-weighted centre of its cells and
// measures the second moments there, from which the ellipsoid axes follow:
// for a uniform ellipsoid the covariance eigenvalues are a^2/5, b^2/5, c^2/5.
// Updates must come often enough that no particle moves or stretches by more
// than about a radius between them (the driver updates at every series row).
#pragma once
#include <vector>

#include "flow_solver.hpp"

namespace softflow {

struct ParticleShape {
  double x = 0, y = 0, z = 0;  // centroid
  double volume = 0;           // sum of phi dV of its cells
  double a = 0, b = 0, c = 0;  // semi-axes from the 3-D second moments, a >= b >= c,
                               // scaled so that (4/3) pi a b c = volume
  double axes_scale = 1;       // that scale (the moments' inflation by the diffuse interface, inverted)
  double a_xy = 0, b_xy = 0;   // semi-axes of the x-y section (the x-y block of the moments)
  double taylor = 0;           // (a_xy - b_xy) / (a_xy + b_xy)
  double angle = 0;            // inclination of the x-y major axis to x, radians
  double taylor_b = 0;         // T of the x-y section of the ellipsoid x^T <B>^-1 x = r^2, <B> the
                               // phi-weighted mean of B over the particle's cells
  double angle_b = 0;          // that ellipsoid's inclination, radians
  // the assignment metric M (xx, xy, xz, yy, yz, zz): a cell at offset d
  // from the centroid is within reach if d^T M d < 1; all 0 until the first
  // update, which then uses the seeded sphere's (2 r)
  double reach[6] = {0, 0, 0, 0, 0, 0};
};

class ParticleTracker {
 public:
  ParticleTracker(FlowSolver& s, const std::vector<ParticleShape>& start);
  // centroids from the seeded spheres; a deformed start's (initial_b) reach
  // from its ellipsoid
  static std::vector<ParticleShape> from_spheres(const std::vector<Sphere>& s, const ParticleConfig& p);
  void update();
  const std::vector<ParticleShape>& shapes() const { return shapes_; }

 private:
  FlowSolver& s_;
  std::vector<ParticleShape> shapes_;
  Kokkos::View<Real* [3], Kokkos::LayoutRight, MemSpace> centres_;
  Kokkos::View<Real* [6], Kokkos::LayoutRight, MemSpace> reach_;
  // per particle: sum f, f x, f x x (6), f B (6), then sum f, f x, f x x
  // over the core (phi > 0.5); row m contiguous
  static constexpr int n_moments = 26;
  Kokkos::View<Real* [n_moments], Kokkos::LayoutRight, MemSpace> moments_;
  // their host copies, made once (update() runs at every series row)
  decltype(Kokkos::create_mirror_view(centres_)) centres_host_;
  decltype(Kokkos::create_mirror_view(reach_)) reach_host_;
  decltype(Kokkos::create_mirror_view(moments_)) moments_host_;
};

}  // namespace softflow
