#include "colour_boxes.hpp"

#include <algorithm>
#include <stdexcept>

namespace softflow {

int cover_intervals(const int* occ, int n, int m, bool circle, Interval out[2]) {
  const int ng = Grid::ng;
  if (!circle) {
    int first = -1, last = -1;
    for (int s = 0; s < n + 2 * ng; ++s)
      if (occ[s]) {
        if (first < 0) first = s;
        last = s;
      }
    if (first < 0) return 0;
    out[0] = {std::max(first - m, ng), std::min(last + 1 + m, ng + n)};
    return out[0].hi > out[0].lo ? 1 : 0;
  }
  // the longest run of empty interior cells on the circle, and where it ends
  int best = 0, best_end = 0, run = 0, any = 0;
  for (int t = 0; t < 2 * n; ++t) {  // twice round, so a run through the seam counts whole
    if (occ[ng + t % n]) {
      any = 1;
      run = 0;
    } else if (++run > best) {
      best = std::min(run, n);
      best_end = (t + 1) % n;  // the first occupied cell after the run
    }
  }
  if (!any) return 0;
  const int len = n - best + 2 * m;  // the arc, grown by m at both ends
  if (len >= n) {
    out[0] = {ng, ng + n};
    return 1;
  }
  const int a = ((best_end - m) % n + n) % n;
  if (a + len <= n) {
    out[0] = {ng + a, ng + a + len};
    return 1;
  }
  out[0] = {ng + a, ng + n};
  out[1] = {ng, ng + a + len - n};
  return 2;
}

ColourBoxes intersect(const ColourBoxes& b, const Range3& r) {
  ColourBoxes o;
  for (int q = 0; q < b.count; ++q) {
    const Range3 c = grown(b.box[q], 0, r);  // the box clipped to r
    if (!c.empty()) o.box[o.count++] = c;
  }
  return o;
}

ColourBoxes intersect(const ColourBoxes& a, const ColourBoxes& b) {
  ColourBoxes o;
  for (int q = 0; q < b.count; ++q) {
    const ColourBoxes part = intersect(a, b.box[q]);
    for (int p = 0; p < part.count; ++p) {
      if (o.count == int(o.box.size())) throw std::logic_error("intersect: more than 4 boxes");
      o.box[o.count++] = part.box[p];
    }
  }
  return o;
}

ColourBoxes single_box(const Range3& r) {
  ColourBoxes o;
  if (!r.empty()) o.box[o.count++] = r;
  return o;
}

ColourBoxes cover_boxes(const Grid& g, const int* occ, int m, const Range3& within) {
  Interval ix[2], iy[2], iz[2];
  const int nx = cover_intervals(occ, g.nxl, m, g.nxl == g.nx, ix);
  const int ny = cover_intervals(occ + g.sx(), g.ny, m, false, iy);
  const int nz = cover_intervals(occ + g.sx() + g.sy(), g.nzl, m, g.nzl == g.nz, iz);
  ColourBoxes all;
  for (int a = 0; a < nx; ++a)
    for (int b = 0; b < ny; ++b)
      for (int c = 0; c < nz; ++c)
        all.box[all.count++] = {ix[a].lo, ix[a].hi, iy[b].lo, iy[b].hi, iz[c].lo, iz[c].hi};
  return intersect(all, within);
}

}  // namespace softflow
