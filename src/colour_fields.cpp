#include "colour_fields.hpp"

#include "../kernels/solid_region.hpp"

#include <algorithm>
#include <array>
#include <vector>
#include <string>
#include <utility>

namespace softflow {

ColourFields::ColourFields(const Grid& g, int n, Real cut)
    : cut_(cut),
      stride_(g.sx() + g.sy() + g.sz()),
      occ_("colour_occupancy", std::size_t(n) * stride_),
      occ_host_(Kokkos::create_mirror_view(occ_)),
      // a pass's tasks: each colour's boxes (at most 4), or 4 ghost slabs of each
      batch_(g, 16 * n + 16),
      batch_before_(g, 4 * n + 4) {
  for (int c = 0; c < n; ++c) {
    const std::string s = std::to_string(c);
    c_.emplace_back("colour_" + s, g.sx(), g.sy(), g.sz());
    now_.emplace_back("colour_rhs_now_" + s, g.sx(), g.sy(), g.sz());
    before_.emplace_back("colour_rhs_before_" + s, g.sx(), g.sy(), g.sz());
  }
  step_.assign(n, single_box(g.interior()));
  update_.assign(n, single_box(g.interior()));  // until the first stage's boxes are known
  active_.assign(n, ColourBoxes{});
  wall_reads_.assign(n, single_box(g.all()));
  scan_.assign(n, ColourBoxes{});
  near_halo_.assign(n, 1);
  near_wall_.assign(n, 1);
  sums_.assign(4 * std::size_t(n), 0);
  coef_.assign(n, 0);  // sized here, so that no stage allocates it
  occ_last_.assign(std::size_t(n) * stride_, 0);
  occ_both_.assign(stride_, 0);
  ghost_list_.reserve(n);
}

// A flag is raised once and then read by the rest of its line: a load first
// skips the store, a locked instruction on x86 (an unconditional store per
// cell and axis was 3% of the dense step)
KOKKOS_INLINE_FUNCTION void raise_flag(int* f) {
  if (Kokkos::atomic_load(f) == 0) Kokkos::atomic_store(f, 1);
}

// One pass per colour over its scan_ boxes flags every x, y and z index
// that holds it, in its own slice of occ_; one copy brings all the flags to
// the host, where cover() turns them into boxes (src/colour_boxes.hpp).
void ColourFields::scan_all(const Grid& g) {
  const auto occ = occ_;
  Kokkos::deep_copy(occ, 0);
  batch_.clear();
  for (int c = 0; c < size(); ++c)
    for (int b = 0; b < scan_[c].count; ++b) batch_.add(scan_[c].box[b], c, 0, c_[c]);
  const CellOffset at = batch_.offset();
  const long stride = long(stride_), sx = g.sx(), sxy = g.sx() + g.sy();
  par_for_boxes(
      "colour_occupancy", batch_, KOKKOS_LAMBDA(const BoxTask& t, int i, int j, int k) {
        if (t.f[0][at(i, j, k)] == 0) return;
        const long x0 = t.tag * stride;
        raise_flag(&occ(x0 + i));
        raise_flag(&occ(x0 + sx + j));
        raise_flag(&occ(x0 + sxy + k));
      });
  Kokkos::deep_copy(occ_host_, occ);
}

ColourBoxes ColourFields::cover(const Grid& g, int c, int m, const Range3& within) const {
  return cover_boxes(g, occ_host_.data() + std::size_t(c) * stride_, m, within);
}

// Where to look for each colour: with x and z whole on this rank, nothing
// enters from elsewhere, so the last stage's update boxes hold it (its
// ghosts are copies of its interior cells, which the seam cover ignores);
// otherwise the whole storage, as a neighbour's particle can enter this
// rank's ghosts.
void ColourFields::begin_step(const Grid& g, const Range3& region) {
  const bool whole = g.nxl == g.nx && g.nzl == g.nz;
  for (int c = 0; c < size(); ++c) scan_[c] = whole ? update_[c] : single_box(g.all());
  scan_all(g);
  for (int c = 0; c < size(); ++c) step_[c] = cover(g, c, solid_region_margin, region);
}

// Each colour holds one particle (or a few), so its work is confined to
// boxes about its own support S (the cells where it is nonzero at the
// stage's start), a few cells wider than the particle:
//   - the right-hand side on S grown by the scheme's reach (THINC and MTHINC
//     take a face's value from its upwind cell alone, so -div(u c) vanishes
//     beyond 1 cell of S; WENO5's stencil reaches 3);
//   - c += gdt r_now on those cells, and c += zdt r_before on the previous
//     stage's (RK3's zeta_0 = 0: none at a step's first stage);
//   - the bounded redistribution, and later the sum into phi, on the update
//     boxes: S and the previous stage's support, grown by the reach, which
//     hold every cell the stage changed and the support it leaves.
// Where x or z is split over ranks the support is looked for in the step's
// boxes grown by 3 instead (a neighbour's cells can enter the ghosts the
// stencil reads; begin_step scanned the whole storage for them).
// Whose ghosts to fill after the stage: on a rank that holds x and z whole, a
// colour whose update boxes, grown by what the next stage reads around them
// (the reach, and the reconstruction's stencil beyond), stay inside the
// interior never reads its ghosts in that stage (the next stage's support
// lies in those boxes, and its scans stay in the interior), so stale ghosts
// are never read. Split ranks scan the step's boxes grown by 3 into the
// ghosts: there the colours whose step boxes, grown by 3, reach some rank's
// edge are filled; the others hold 0 in every cell their ghosts copy (their
// support is 12 cells in, and it was so when they were last filled). The
// others' are not filled (fill_ghosts).
// All of it is a function of the state alone (the previous stage's support
// enters only after a step's first stage), so a restarted run repeats the
// sums bit for bit.
void ColourFields::advance_stage(const Grid& g, const FlowState& flow, const FaceFluxes& flux,
                                 const PhiScheme& scheme, Real gdt, Real zdt,
                                 const std::function<void(Real*, int)>& allreduce_sum) {
  const bool whole = g.nxl == g.nx && g.nzl == g.nz, first_stage = zdt == 0;
  const int reach = scheme.thinc() ? 1 : 3, reads = reach + (scheme.thinc() ? 2 : 3);
  for (int c = 0; c < size(); ++c) {
    scan_[c] = whole ? update_[c] : step_[c];
    if (!whole)
      for (int b = 0; b < scan_[c].count; ++b) scan_[c].box[b] = grown(scan_[c].box[b], 3, g.all());
  }
  scan_all(g);
  const Range3 in = g.interior();
  const int n = size();
  // each colour's right-hand side on its own (the transport's scratch is
  // shared); its updates, redistribution sums and redistribution batched
  // over the colours after (box_batch.hpp): c += gdt r_now, then
  // c += zdt r_before, in that order in every cell, as one colour alone
  batch_.clear();
  batch_before_.clear();
  for (int c = 0; c < n; ++c) {
    const Field3 q = c_[c], r = now_[c], rb = before_[c];
    const ColourBoxes& step = step_[c];
    const int* flags = occ_host_.data() + std::size_t(c) * stride_;
    const ColourBoxes active = intersect(cover_boxes(g, flags, reach, in), step);
    // the update boxes: this stage's support and the last's, grown by the reach
    if (!first_stage) {
      const int* last = occ_last_.data() + std::size_t(c) * stride_;
      for (std::size_t s = 0; s < stride_; ++s) occ_both_[s] = flags[s] | last[s];
      flags = occ_both_.data();
    }
    update_[c] = intersect(cover_boxes(g, flags, reach, in), step);
    for (int a = 0; a < active.count; ++a) {
      phi_transport_rhs(g, flow, q, r, flux, active.box[a], scheme);
      batch_.add(active.box[a], c, gdt, q, r);
    }
    if (!first_stage)
      for (int a = 0; a < active_[c].count; ++a) batch_before_.add(active_[c].box[a], c, zdt, q, rb);
    active_[c] = active;
    // split ranks scan the step's boxes grown by 3, ghosts included, so
    // their ghosts must hold the truth wherever those boxes reach
    const ColourBoxes& reads_from = whole ? update_[c] : step;
    const int around = whole ? reads : 3;
    int halo = 0, wall = 0;
    wall_reads_[c] = reads_from;
    for (int b = 0; b < reads_from.count; ++b) {
      const Range3 e = grown(reads_from.box[b], around, g.all());
      halo |= e.ib < in.ib || e.ie > in.ie || e.kb < in.kb || e.ke > in.ke;
      wall |= e.jb < in.jb || e.je > in.je;
      wall_reads_[c].box[b] = e;
    }
    sums_[2 * n + c] = halo;
    sums_[3 * n + c] = wall;
    std::swap(now_[c], before_[c]);
  }
  const CellOffset at = batch_.offset();
  par_for_boxes(
      "colour_rk3_update", batch_, KOKKOS_LAMBDA(const BoxTask& t, int i, int j, int k) {
        t.f[0][at(i, j, k)] += t.s * t.f[1][at(i, j, k)];
      });
  par_for_boxes(
      "colour_rk3_update_before", batch_before_, KOKKOS_LAMBDA(const BoxTask& t, int i, int j, int k) {
        t.f[0][at(i, j, k)] += t.s * t.f[1][at(i, j, k)];
      });
  // the bounded redistribution's sums {e, W} of each colour (phi's,
  // kernels/solid_transport.hpp) over its update boxes
  batch_.clear();
  for (int c = 0; c < n; ++c)
    for (int b = 0; b < update_[c].count; ++b) batch_.add(update_[c].box[b], c, 0, c_[c]);
  const Real cut = cut_;
  par_reduce2_boxes(
      "colour_redistribution_sums", batch_,
      KOKKOS_LAMBDA(const BoxTask& t, int i, int j, int k, Real& e, Real& w) {
        const Real p = t.f[0][at(i, j, k)];
        e += clipped_excess(p, cut);
        w += interface_weight(p, cut);
      });
  per_colour_sums(n);
  std::copy(occ_host_.data(), occ_host_.data() + occ_last_.size(), occ_last_.begin());
  // every colour's redistribution sums and near-edge flags in one
  // collective (every rank, empty boxes or not)
  if (n > 0) allreduce_sum(sums_.data(), 4 * n);
  for (int c = 0; c < n; ++c) {
    near_halo_[c] = sums_[2 * n + c] > 0;
    near_wall_[c] = sums_[3 * n + c] > 0;
  }
  set_coefficients(n, true);
  par_for_boxes(
      "colour_redistribute", batch_, KOKKOS_LAMBDA(const BoxTask& t, int i, int j, int k) {
        Real& q = t.f[0][at(i, j, k)];
        q = redistributed_phi(q, t.s, cut);
      });
}

// sums_[2c], sums_[2c + 1]: the batch's pairs of sums added per colour, box
// by box in the batch's order (the tasks' tags)
void ColourFields::per_colour_sums(int n) {
  for (int c = 0; c < 2 * n; ++c) sums_[c] = 0;
  const auto& s = batch_.sums_on_host();
  for (int b = 0; b < batch_.size(); ++b) {
    const int c = batch_.tag(b);
    sums_[2 * c] += s(b, 0);
    sums_[2 * c + 1] += s(b, 1);
  }
}

// each task's scalar: its colour's coefficient a = e / W from sums_, clipped
// to [-1, 1] for the redistribution (`signed_a`) or to [0, 1] for the bound
void ColourFields::set_coefficients(int n, bool signed_a) {
  std::vector<Real>& a = coef_;
  a.assign(n, 0);
  for (int c = 0; c < n; ++c)
    a[c] = redistribution_coefficient(sums_[2 * c], sums_[2 * c + 1], signed_a ? -1 : 0);
  for (int b = 0; b < batch_.size(); ++b) batch_.set_scalar(b, a[batch_.tag(b)]);
}

void ColourFields::sum_into(const Field3& phi, const Range3& where) const {
  par_for(
      "colour_sum_clear", where, KOKKOS_LAMBDA(int i, int j, int k) { phi(i, j, k) = 0; });
  for (int c = 0; c < size(); ++c) {
    const Field3 q = c_[c];
    const ColourBoxes on = intersect(update_[c], where);
    for (int b = 0; b < on.count; ++b)
      par_for(
          "colour_sum", on.box[b], KOKKOS_LAMBDA(int i, int j, int k) { phi(i, j, k) += q(i, j, k); });
  }
}

// Two particles' colours overlap where they come within a cell of each
// other: each colour's reconstruction fills the cell between them on its own
// (MTHINC compresses each towards 1), and nothing in one colour's transport
// sees the other. The exact transport keeps the sum at most 1 (a volume
// fraction moved by one velocity), so the overlap is a discretisation error,
// and the mixture, which reads min(phi, 1), loses its volume. The bound: where
// the sum S > 1, every colour is scaled by 1 / S (the cell is then exactly
// full); the volume this takes from colour c, e_c = sum c (1 - 1 / S), goes
// back to it where S < 1, in proportion to c (1 - S), the room its share of
// the cell leaves: c <- c + (e_c / W_c) c (1 - S), W_c = sum c (1 - S). With
// e_c <= W_c (the rest is dropped, as phi_redistribute does, and would show
// in the volume diagnostic) a cell gains at most (1 - S) S <= 1 - S, so the
// sum stays at most 1, each colour in [0, 1], and each colour's volume is
// conserved to round-off. It is the multi-material VOF's "the fractions sum
// to one", applied as phi's own bounded redistribution
// (kernels/solid_transport.hpp) applies [0, 1] to one field. Colour c is 0
// outside its update boxes, so only they are visited.
bool ColourFields::bound_sum(const Field3& phi, const std::function<void(Real*, int)>& allreduce_sum) {
  const int n = size();
  if (n == 0) return false;
  batch_.clear();
  for (int c = 0; c < n; ++c)
    for (int b = 0; b < update_[c].count; ++b) batch_.add(update_[c].box[b], c, 0, c_[c]);
  const CellOffset at = batch_.offset();
  par_reduce2_boxes(
      "colour_overlap_sums", batch_, KOKKOS_LAMBDA(const BoxTask& t, int i, int j, int k, Real& e, Real& w) {
        const Real sum = phi(i, j, k), q = t.f[0][at(i, j, k)];
        if (sum > 1) e += q * (1 - 1 / sum);
        if (sum < 1) w += q * (1 - sum);
      });
  per_colour_sums(n);
  allreduce_sum(sums_.data(), 2 * n);
  bool any = false;
  for (int c = 0; c < n; ++c) any |= sums_[2 * c] > 0;
  if (!any) return false;
  set_coefficients(n, false);
  par_for_boxes(
      "colour_overlap_bound", batch_, KOKKOS_LAMBDA(const BoxTask& t, int i, int j, int k) {
        const Real sum = phi(i, j, k);
        Real& q = t.f[0][at(i, j, k)];
        if (sum > 1)
          q /= sum;
        else
          q += t.s * q * (1 - sum);
      });
  return true;
}

// With x and z whole on this rank (the periodic copy), each colour's ghosts
// are filled only over the boxes the next stage reads (wall_reads_, what
// advance_stage found it reads: the full storage until then), from the
// periodic image of the interior, in one batch; the halo's full planes cost
// 21 us a colour in the dense scene for a few hundred cells read. Split
// ranks exchange the colours' whole planes through the halo.
void ColourFields::fill_ghosts(Halo& halo, const Grid& g) const {
  const int ng = Grid::ng, nx = g.nx, ny = g.ny, nz = g.nz;
  const bool whole = g.nxl == g.nx && g.nzl == g.nz;
  if (whole && ghost_fill_ != GhostFill::full) {
    if (ghost_fill_ == GhostFill::reads_poisoned) {
      // every x and z ghost of the colours about to be filled to NaN first:
      // a stage that read a ghost this fill leaves out would carry it
      batch_.clear();
      const std::array<Range3, 4> slabs = ghost_slabs(g);
      for (int c = 0; c < size(); ++c)
        if (near_halo_[c])
          for (const Range3& r : slabs) batch_.add(r, c, 0, c_[c]);
      const CellOffset at = batch_.offset();
      par_for_boxes(
          "colour_ghosts_poison", batch_, KOKKOS_LAMBDA(const BoxTask& t, int i, int j, int k) {
            t.f[0][at(i, j, k)] = Kokkos::Experimental::quiet_NaN_v<Real>;
          });
    }
    batch_.clear();
    for (int c = 0; c < size(); ++c)
      if (near_halo_[c]) add_periodic_ghosts(g, c);
    const CellOffset at = batch_.offset();
    par_for_boxes(
        "colour_periodic_ghosts", batch_, KOKKOS_LAMBDA(const BoxTask& t, int i, int j, int k) {
          const int si = i < ng ? i + nx : (i >= ng + nx ? i - nx : i);
          const int sk = k < ng ? k + nz : (k >= ng + nz ? k - nz : k);
          t.f[0][at(i, j, k)] = t.f[0][at(si, j, sk)];
        });
  } else {
    ghost_list_.clear();
    for (int c = 0; c < size(); ++c)
      if (near_halo_[c]) ghost_list_.push_back(c_[c]);  // the same list on every rank
    const int n = int(ghost_list_.size());
    for (int c = 0; c < n; c += Halo::max_fields)
      halo.exchange(ghost_list_.data() + c, std::min(n - c, Halo::max_fields));
  }
  // the wall ghosts (y) after the halo's, over the x-z extent the next stage
  // can read (the whole plane until the first stage's boxes are known, and
  // in the reference fill GhostFill::full, whose corners are then exact); a
  // launch per box, as a colour's boxes grown may overlap in a small box
  const bool whole_plane = ghost_fill_ == GhostFill::full;
  const Range3 plane = g.all();
  for (int c = 0; c < size(); ++c) {
    if (!near_wall_[c]) continue;
    const Field3 a = c_[c];
    for (int b = 0; b < (whole_plane ? 1 : wall_reads_[c].count); ++b) {
      const Range3& r = whole_plane ? plane : wall_reads_[c].box[b];
      par_for(
          "walls_colour", Range3{r.ib, r.ie, 0, ng, r.kb, r.ke}, KOKKOS_LAMBDA(int i, int m, int k) {
            a(i, ng - 1 - m, k) = a(i, ng + m, k);
            a(i, ng + ny + m, k) = a(i, ng + ny - 1 - m, k);
          });
    }
  }
}

// The x and z ghost slabs: x low and high over the whole y-z extent
// (corners included), z low and high over the interior x; disjoint
std::array<Range3, 4> ColourFields::ghost_slabs(const Grid& g) {
  const int ng = Grid::ng;
  const Range3 all = g.all();
  return {Range3{0, ng, all.jb, all.je, all.kb, all.ke},
          Range3{ng + g.nx, all.ie, all.jb, all.je, all.kb, all.ke},
          Range3{ng, ng + g.nx, all.jb, all.je, 0, ng},
          Range3{ng, ng + g.nx, all.jb, all.je, ng + g.nz, all.ke}};
}

// The periodic ghosts colour c's next stage reads. Its reads lie within its
// wall_reads_ boxes (storage indices) or their periodic images: a box at the
// high x end reads the high ghosts, copies of cells at the low end that its
// other box holds (a box ending at x = 0's seam and its image one period on
// are the same cells). So each box is shifted by -n, 0, +n periods in x and
// z, and each ghost slab (x low and high over the whole y-z extent, corners
// included; z low and high over the interior x) gets the bounding box of
// what the shifted boxes cover of it: four disjoint tasks at most. A cell
// filled beyond the reads gets its true value too.
void ColourFields::add_periodic_ghosts(const Grid& g, int c) const {
  const int nx = g.nx, nz = g.nz;
  const std::array<Range3, 4> slab = ghost_slabs(g);
  Range3 need[4];
  bool any[4] = {false, false, false, false};
  auto meet = [](const Range3& a, const Range3& b) {
    return Range3{std::max(a.ib, b.ib), std::min(a.ie, b.ie), std::max(a.jb, b.jb),
                  std::min(a.je, b.je), std::max(a.kb, b.kb), std::min(a.ke, b.ke)};
  };
  for (int b = 0; b < wall_reads_[c].count; ++b)
    for (int sx = -1; sx <= 1; ++sx)
      for (int sz = -1; sz <= 1; ++sz) {
        const Range3& e = wall_reads_[c].box[b];
        const Range3 shifted{e.ib + sx * nx, e.ie + sx * nx, e.jb, e.je, e.kb + sz * nz, e.ke + sz * nz};
        for (int s = 0; s < 4; ++s) {
          const Range3 m = meet(shifted, slab[s]);
          if (m.empty()) continue;
          need[s] = any[s] ? Range3{std::min(need[s].ib, m.ib), std::max(need[s].ie, m.ie),
                                    std::min(need[s].jb, m.jb), std::max(need[s].je, m.je),
                                    std::min(need[s].kb, m.kb), std::max(need[s].ke, m.ke)}
                           : m;
          any[s] = true;
        }
      }
  for (int s = 0; s < 4; ++s)
    if (any[s]) batch_.add(need[s], c, 0, c_[c]);
}

}  // namespace softflow
