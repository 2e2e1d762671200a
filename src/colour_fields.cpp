#include "colour_fields.hpp"

#include "../kernels/solid_region.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace softflow {

ColourFields::ColourFields(const Grid& g, int n)
    : stride_(g.sx() + g.sy() + g.sz()),
      occ_("colour_occupancy", std::size_t(n) * stride_),
      occ_host_(Kokkos::create_mirror_view(occ_)) {
  for (int c = 0; c < n; ++c) {
    const std::string s = std::to_string(c);
    c_.emplace_back("colour_" + s, g.sx(), g.sy(), g.sz());
    now_.emplace_back("colour_rhs_now_" + s, g.sx(), g.sy(), g.sz());
    before_.emplace_back("colour_rhs_before_" + s, g.sx(), g.sy(), g.sz());
  }
  step_.assign(n, single_box(g.interior()));
  scan_.assign(n, ColourBoxes{});
  near_edge_.assign(n, 1);  // until the first step's boxes are known
  sums_.assign(2 * std::size_t(n), 0);
  ghost_list_.reserve(n);
}

// One pass per colour over its scan_ boxes flags every x, y and z index
// that holds it, in its own slice of occ_; one copy brings all the flags to
// the host, where cover() turns them into boxes (src/colour_boxes.hpp).
void ColourFields::scan_all(const Grid& g) {
  const auto occ = occ_;
  Kokkos::deep_copy(occ, 0);
  for (int c = 0; c < size(); ++c) {
    const Field3 q = c_[c];
    const long x0 = long(c) * stride_, y0 = x0 + g.sx(), z0 = y0 + g.sy();
    for (int b = 0; b < scan_[c].count; ++b)
      par_for(
          "colour_occupancy", scan_[c].box[b], KOKKOS_LAMBDA(int i, int j, int k) {
            if (q(i, j, k) == 0) return;
            Kokkos::atomic_store(&occ(x0 + i), 1);
            Kokkos::atomic_store(&occ(y0 + j), 1);
            Kokkos::atomic_store(&occ(z0 + k), 1);
          });
  }
  Kokkos::deep_copy(occ_host_, occ);
}

ColourBoxes ColourFields::cover(const Grid& g, int c, int m, const Range3& within) const {
  return cover_boxes(g, occ_host_.data() + std::size_t(c) * stride_, m, within);
}

// Where to look for each colour: with x and z whole on this rank, nothing
// enters from elsewhere, so the last step's boxes hold its interior cells
// (its ghosts are copies of them, which the seam cover ignores); otherwise
// the whole storage, as a neighbour's particle can enter this rank's ghosts.
//
// Whose ghosts to fill: a colour whose step boxes, grown by the 3 cells of
// the stencil, stay inside the interior of every rank never reads its ghosts
// this step, and holds 0 in the interior cells next to the edges (its
// support is 12 cells in), so its ghosts, filled when it last came near an
// edge, hold 0 and stay right. Filling only the others saves most of the
// halo copies of a dense box (one colour per particle).
void ColourFields::begin_step(const Grid& g, const Range3& region, MPI_Comm comm) {
  const bool whole = g.nxl == g.nx && g.nzl == g.nz;
  const Range3 in = g.interior();
  for (int c = 0; c < size(); ++c) scan_[c] = whole ? step_[c] : single_box(g.all());
  scan_all(g);
  for (int c = 0; c < size(); ++c) {
    step_[c] = cover(g, c, solid_region_margin, region);
    near_edge_[c] = 0;
    for (int b = 0; b < step_[c].count; ++b) {
      const Range3 r = grown(step_[c].box[b], 3, g.all());
      near_edge_[c] |=
          r.ib < in.ib || r.ie > in.ie || r.jb < in.jb || r.je > in.je || r.kb < in.kb || r.ke > in.ke;
    }
  }
  if (size() > 0) MPI_Allreduce(MPI_IN_PLACE, near_edge_.data(), size(), MPI_INT, MPI_MAX, comm);
}

// Each colour holds one particle (or a few), so its work is confined to its
// own boxes instead of the whole solid region: the right-hand side to the
// colour's support grown by 3 cells (as phi's `active`; a tenth of a dense
// box at 4 points per radius), the update and the redistribution to the
// step's boxes (its support at the step's start grown by the solid region's
// margin, which hold every stage's support). The support is looked for
// within the step's boxes, grown by 3 where x or z is split over ranks (a
// neighbour's cells in the ghosts the stencil reads).
// All of it is a function of the state alone, so a restarted run repeats
// the sums bit for bit. The stage-0 update reads the last step's r_before
// times zeta_0 = 0 (RK3), which adds nothing.
void ColourFields::advance_stage(const Grid& g, const FlowState& flow, const FaceFluxes& flux,
                                 const PhiScheme& scheme, Real gdt, Real zdt,
                                 const std::function<void(Real*, int)>& allreduce_sum) {
  const bool whole = g.nxl == g.nx && g.nzl == g.nz;
  for (int c = 0; c < size(); ++c) {
    scan_[c] = step_[c];  // ghosts matter only in a direction split over ranks
    if (!whole)
      for (int b = 0; b < scan_[c].count; ++b) scan_[c].box[b] = grown(scan_[c].box[b], 3, g.all());
  }
  scan_all(g);
  for (int c = 0; c < size(); ++c) {
    const Field3 q = c_[c], r = now_[c], rb = before_[c];
    const ColourBoxes& step = step_[c];
    const ColourBoxes active = intersect(cover(g, c, 3, g.interior()), step);
    for (int b = 0; b < step.count; ++b)
      par_for(
          "colour_rhs_clear", step.box[b], KOKKOS_LAMBDA(int i, int j, int k) { r(i, j, k) = 0; });
    for (int a = 0; a < active.count; ++a) phi_transport_rhs(g, flow, q, r, flux, active.box[a], scheme);
    for (int b = 0; b < step.count; ++b)
      par_for(
          "colour_rk3_update", step.box[b],
          KOKKOS_LAMBDA(int i, int j, int k) { q(i, j, k) += gdt * r(i, j, k) + zdt * rb(i, j, k); });
    phi_redistribution_sums(q, step.box.data(), step.count, &sums_[2 * c]);
    std::swap(now_[c], before_[c]);
  }
  // every colour's redistribution sums in one collective (every rank, empty
  // boxes or not)
  if (size() > 0) allreduce_sum(sums_.data(), 2 * size());
  for (int c = 0; c < size(); ++c)
    phi_redistribute(c_[c], &sums_[2 * c], step_[c].box.data(), step_[c].count);
}

void ColourFields::sum_into(const Field3& phi, const Range3& where) const {
  par_for(
      "colour_sum_clear", where, KOKKOS_LAMBDA(int i, int j, int k) { phi(i, j, k) = 0; });
  for (int c = 0; c < size(); ++c) {
    const Field3 q = c_[c];
    const ColourBoxes on = intersect(step_[c], where);
    for (int b = 0; b < on.count; ++b)
      par_for(
          "colour_sum", on.box[b], KOKKOS_LAMBDA(int i, int j, int k) { phi(i, j, k) += q(i, j, k); });
  }
}

void ColourFields::fill_ghosts(Halo& halo, const Grid& g) const {
  ghost_list_.clear();
  for (int c = 0; c < size(); ++c)
    if (near_edge_[c]) ghost_list_.push_back(c_[c]);  // the same list on every rank
  const int n = int(ghost_list_.size());
  for (int c = 0; c < n; c += Halo::max_fields)
    halo.exchange(ghost_list_.data() + c, std::min(n - c, Halo::max_fields));
  const int ng = Grid::ng, ny = g.ny;
  for (const Field3& a : ghost_list_)
    par_for(
        "walls_colour", Range3{0, g.sx(), 0, ng, 0, g.sz()}, KOKKOS_LAMBDA(int i, int m, int k) {
          a(i, ng - 1 - m, k) = a(i, ng + m, k);
          a(i, ng + ny + m, k) = a(i, ng + ny - 1 - m, k);
        });
}

}  // namespace softflow
