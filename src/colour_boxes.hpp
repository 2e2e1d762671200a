// The boxes one colour field occupies: at most two index intervals per
// periodic direction, so a particle that straddles a periodic boundary costs
// its own size, not the box's length.
//
// Why: a plain bounding box of a particle that crosses x = 0 spans the whole
// x extent (its cells sit at both ends), and every per-colour pass over it
// (the MTHINC planes and fluxes, the update, the redistribution) then runs
// over a slab of the domain. In the dense bench scene that took MTHINC's
// colour fluxes from 25 to 88 ms per step (results/README.md, round 19).
// In a direction that is periodic and held whole by this rank (x or z not
// split over ranks), the occupied cells form an arc of the circle of cells:
// it is the complement of the longest run of empty cells, and, grown by the
// margin, one interval or two (one at each end). Elsewhere (y between the
// walls, or x / z split over ranks) it is the plain [first, last] interval
// over the storage, ghosts included, as kernels/solid_region.hpp's box.
#pragma once
#include <array>

#include "grid.hpp"

namespace softflow {

struct Interval {
  int lo = 0, hi = 0;  // storage indices [lo, hi)
};

// Occupied storage indices along one direction of storage length
// n + 2 Grid::ng (occ[s] != 0: some cell of index s holds the colour),
// grown by m cells, as intervals inside the interior [ng, ng + n).
// `circle`: the direction is periodic and whole on this rank, so ghosts
// (copies of the far end's cells) are ignored and the arc may wrap.
// Returns 0, 1 or 2 intervals in out.
int cover_intervals(const int* occ, int n, int m, bool circle, Interval out[2]);

// Boxes: the products of each direction's intervals (at most 2 x 1 x 2),
// each clipped to `within`; empty ones dropped.
struct ColourBoxes {
  int count = 0;
  std::array<Range3, 4> box{};
};

// occ holds three directions' flags one after the other (sx, sy, sz long)
ColourBoxes cover_boxes(const Grid& g, const int* occ, int m, const Range3& within);

// boxes and r's intersections (pairwise disjoint boxes stay disjoint)
ColourBoxes intersect(const ColourBoxes& b, const Range3& r);
// the pairwise intersections of two sets of boxes; a cover within a larger
// one (a later stage's support in its step's boxes) gives at most 4, as
// each of its intervals lies in one of the larger cover's (std::logic_error
// if more)
ColourBoxes intersect(const ColourBoxes& a, const ColourBoxes& b);
ColourBoxes single_box(const Range3& r);

}  // namespace softflow
