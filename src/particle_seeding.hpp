// Where the particles start: N non-overlapping spheres at random positions
// (periodic in x and z, clear of the walls), the same for every rank count.
#pragma once
#include <vector>

#include "config.hpp"

namespace softflow {

struct Sphere {
  double x, y, z;
};

// Number of spheres of the case: count, or round(Phi V_box / (4/3 pi r^3)).
int sphere_count(const Config& cfg);

// Number of colour fields phi is split into (src/colour_fields.hpp): with
// particles.colour_fields = "auto" (the default) one per sphere where there
// are two or more, none for a lone sphere (nothing to fuse with) or another
// shape; otherwise the value given, at most one per sphere.
int colour_count(const Config& cfg);

// lambda_max of a symmetric 3x3 matrix given as (xx, xy, xz, yy, yz, zz)
double largest_stretch(const Real* b);

// The surface gap seeding keeps between spheres and to the walls:
// max(min_gap, min_gap_cells x the cell diagonal), lowered towards min_gap
// (never below) only as far as the packing bound needs.
double seeding_gap(const Config& cfg);

// Deterministic from cfg.particles.seed. Throws InputError when the spheres
// cannot be placed with the requested gap.
std::vector<Sphere> seed_spheres(const Config& cfg);

}  // namespace softflow
