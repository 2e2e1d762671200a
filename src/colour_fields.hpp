// Multiple markers: phi as the sum of colour fields, particle m's volume in
// colour m % n, each colour transported on its own by the phi scheme.
//
// Why: one phi cannot hold two interfaces in a cell. When two particles come
// within a cell of each other, the single field's reconstruction (MTHINC's
// plane, or WENO5's stencil) sees one body and the film between them fills:
// numerical coalescence, which at 4-5 points per radius fuses the stiff dense
// case's particles (results/README.md). With its own field, each particle
// keeps its own interface however close another comes: the multiple-marker
// remedy of VOF methods (Coyajee & Boersma, J. Comput. Phys. 228, 2009).
// Each colour is conserved to round-off and kept in [0, 1] like phi. Their
// sum is kept at most 1 too (bound_sum): each colour's transport is bounded
// on its own, so where two particles meet closer than a cell both colours
// fill the cell between them (at 4 points per radius the overlap hid 11% of
// the solid of Phi = 0.33, Ca = 2 by strain 100, phi reaching 3.4;
// results/README.md, round 28). Where it is off, fraction(phi) clamps the
// sum wherever phi is read as a fraction, and the overlap's volume is lost
// to the mixture.
//
// phi, B, the stress and the diagnostics read phi = sum of the colours,
// formed after every stage. A colour shared by several particles (n below
// their number) fuses them as phi would if they meet.
#pragma once
#include <array>
#include <functional>
#include <vector>

#include "../kernels/flow_state.hpp"
#include "../kernels/solid_transport.hpp"
#include "box_batch.hpp"
#include "colour_boxes.hpp"
#include "halo.hpp"

namespace softflow {

class ColourFields {
 public:
  ColourFields() = default;
  // cut: values below it are set to 0 after every stage (particles.colour_cut)
  ColourFields(const Grid& g, int n, Real cut = phi_zero_cut);
  int size() const { return int(c_.size()); }
  const Field3& colour(int c) const { return c_[c]; }
  // where colour c can be during this step (src/colour_boxes.hpp)
  const ColourBoxes& step_boxes(int c) const { return step_[c]; }
  // where the last stage updated colour c (it is 0 outside them)
  const ColourBoxes& update_boxes(int c) const { return update_[c]; }

  // before each step: the boxes each colour can reach in it (within
  // `region`, the solid's: kernels/solid_region.hpp)
  void begin_step(const Grid& g, const Range3& region);
  // one RK3 stage of every colour: -div(u c) by the phi scheme on the
  // colour's support grown by the scheme's reach, c += gdt r_now +
  // zdt r_before, then the bounded redistribution
  // (kernels/solid_transport.hpp), on boxes about its support (the .cpp
  // says which); also which colours come near enough to an edge of some
  // rank's interior to need their ghosts filled (the sums' collective).
  // `flux` is the transport's scratch, free on entry.
  void advance_stage(const Grid& g, const FlowState& flow, const FaceFluxes& flux, const PhiScheme& scheme,
                     Real gdt, Real zdt, const std::function<void(Real*, int)>& allreduce_sum);
  // phi = sum of the colours on `where` (each colour added on its last
  // update boxes, outside which it is 0)
  void sum_into(const Field3& phi, const Range3& where) const;
  // keeps the sum a volume fraction, at most 1, with every colour's volume
  // conserved (particles.colour_sum_bound; the .cpp says how and why); phi
  // holds the sum on entry. Returns whether any colour changed (then phi
  // must be summed again). One collective, on every rank.
  bool bound_sum(const Field3& phi, const std::function<void(Real*, int)>& allreduce_sum);
  // halo and wall ghosts (even reflection, as phi's) of the colours that
  // need them in the next stage; the others' are not read (advance_stage)
  void fill_ghosts(Halo& halo, const Grid& g) const;
  // How fill_ghosts fills the periodic ghosts on a rank that holds x and z
  // whole: only where the next stage reads them (the default), every one
  // (the halo's periodic copy, then the wall ghosts over the whole plane,
  // corners included: the reference the tests compare with), or
  // where read after setting every other one to NaN (a test that nothing
  // else is read)
  enum class GhostFill { reads, full, reads_poisoned };
  void set_ghost_fill(GhostFill f) { ghost_fill_ = f; }
  // flags of the x, y and z indices where each colour c is nonzero within
  // its scan_[c], brought to the host in one copy (public only because
  // nvcc rejects a device lambda in a private member function)
  void scan_all(const Grid& g);

 private:
  // colour c's boxes from those flags, grown by m, within `within`
  ColourBoxes cover(const Grid& g, int c, int m, const Range3& within) const;
  // the last par_reduce2_boxes' sums added per colour into sums_[0, 2n)
  void per_colour_sums(int n);
  // each task's scalar: its colour's e / W from sums_, clipped to [-1, 1]
  // (`signed_a`) or [0, 1]
  void set_coefficients(int n, bool signed_a);
  // colour c's periodic ghost slabs that its next stage reads, into batch_
  void add_periodic_ghosts(const Grid& g, int c) const;
  static std::array<Range3, 4> ghost_slabs(const Grid& g);

  std::vector<Field3> c_, now_, before_;
  std::vector<ColourBoxes> step_;    // where each colour can be during this step
  std::vector<ColourBoxes> update_;  // where the last stage updated it (holds its support)
  std::vector<ColourBoxes> active_;  // where the last stage's right-hand side was computed
  std::vector<ColourBoxes> scan_;    // where scan_all looks for it
  Real cut_ = phi_zero_cut;
  std::size_t stride_ = 0;  // one colour's flags: sx + sy + sz
  Kokkos::View<int*, MemSpace> occ_;
  Kokkos::View<int*, MemSpace>::host_mirror_type occ_host_;
  std::vector<int> occ_last_;            // the flags of the last stage's scan (host)
  std::vector<int> occ_both_;            // scratch: one colour's flags or'd with the last stage's
  std::vector<int> near_halo_;           // 1: its halo (x, z) ghosts are filled after the stage
  std::vector<int> near_wall_;           // 1: its wall (y) ghosts are, over wall_reads_
  std::vector<ColourBoxes> wall_reads_;  // the boxes it can read in the next stage
  std::vector<Real> sums_;               // each colour's redistribution sums {e, W}, then its two near flags
  std::vector<Real> coef_;               // scratch: each colour's coefficient
  mutable std::vector<Field3> ghost_list_;
  GhostFill ghost_fill_ = GhostFill::reads;
  mutable BoxBatch batch_;  // one pass's boxes of every colour (src/box_batch.hpp)
  BoxBatch batch_before_;   // the RK3 update's second half
};

}  // namespace softflow
