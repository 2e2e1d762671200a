#include "colour_fields.hpp"

#include "../kernels/solid_region.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace softflow {

ColourFields::ColourFields(const Grid& g, int n) {
  for (int c = 0; c < n; ++c) {
    const std::string s = std::to_string(c);
    c_.emplace_back("colour_" + s, g.sx(), g.sy(), g.sz());
    now_.emplace_back("colour_rhs_now_" + s, g.sx(), g.sy(), g.sz());
    before_.emplace_back("colour_rhs_before_" + s, g.sx(), g.sy(), g.sz());
  }
  step_box_.assign(n, g.interior());
}

void ColourFields::begin_step(const Grid& g, const Range3& region) {
  for (int c = 0; c < size(); ++c)
    step_box_[c] = grown_range(phi_support(g, c_[c]), solid_region_margin, region);
}

// Each colour holds one particle (or a few), so its work is confined to its
// own ranges instead of the whole solid region: the right-hand side to the
// colour's support grown by 3 cells (as phi's `active`; a tenth of a dense
// box at 4 points per radius), the update and the redistribution to the
// step's box (its support at the step's start grown by the solid region's
// margin, which holds every stage's range). Both are functions of the
// state alone, so a restarted run repeats the sums bit for bit. The right-
// hand side is cleared over the rest of the step's box; the stage-0 update
// reads the last step's r_before times zeta_0 = 0 (RK3), which adds nothing.
void ColourFields::advance_stage(const Grid& g, const FlowState& flow, const FaceFluxes& flux,
                                 const PhiScheme& scheme, Real gdt, Real zdt,
                                 const std::function<void(Real*, int)>& allreduce_sum) {
  for (int c = 0; c < size(); ++c) {
    const Field3 q = c_[c], r = now_[c], rb = before_[c];
    const Range3 step = step_box_[c], box = grown_range(phi_support(g, q), 3, step);
    par_for(
        "colour_rhs_clear", step, KOKKOS_LAMBDA(int i, int j, int k) {
          if (!box.contains(i, j, k)) r(i, j, k) = 0;
        });
    if (!box.empty()) phi_transport_rhs(g, flow, q, r, flux, box, scheme);
    par_for(
        "colour_rk3_update", step,
        KOKKOS_LAMBDA(int i, int j, int k) { q(i, j, k) += gdt * r(i, j, k) + zdt * rb(i, j, k); });
    phi_bounded_redistribution(q, allreduce_sum, step);  // collective: every rank, empty range or not
    std::swap(now_[c], before_[c]);
  }
}

void ColourFields::sum_into(const Field3& phi, const Range3& where) const {
  for (int c = 0; c < size(); ++c) {
    const Field3 q = c_[c];
    const bool first = c == 0;
    par_for(
        "colour_sum", where, KOKKOS_LAMBDA(int i, int j, int k) {
          phi(i, j, k) = first ? q(i, j, k) : phi(i, j, k) + q(i, j, k);
        });
  }
}

void ColourFields::fill_ghosts(Halo& halo, const Grid& g) const {
  for (int c = 0; c < size(); c += Halo::max_fields) {
    halo.exchange(c_.data() + c, std::min(size() - c, Halo::max_fields));
  }
  const int ng = Grid::ng, ny = g.ny;
  for (const Field3& a : c_)
    par_for(
        "walls_colour", Range3{0, g.sx(), 0, ng, 0, g.sz()}, KOKKOS_LAMBDA(int i, int m, int k) {
          a(i, ng - 1 - m, k) = a(i, ng + m, k);
          a(i, ng + ny + m, k) = a(i, ng + ny - 1 - m, k);
        });
}

}  // namespace softflow
