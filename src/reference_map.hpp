// The reference map of one particle (particles.solid_model =
// "reference_map"): xi, the undeformed position of the material in each
// cell, advected with the flow, d xi / dt + u . grad xi = 0. phi and B are
// read off it after every RK3 stage, in the method's order:
//   1. advance: xi's WENO5 advection and its RK3 update (advance_stage);
//   2. band: where a cell's centre maps outside the reference sphere, xi is
//      replaced by the affine least-squares continuation of the cells that
//      map inside (4 layers of cells, each fitted from the valid cells
//      within 3; farther out, a far value), so the map stays smooth across
//      the interface and the fluid's shear never stretches it; a first-layer
//      cell whose own value maps within a cell of the sphere keeps part of
//      it (the soft edge, soft_edge_weight), so that a cell leaving the
//      inside set changes gradually (refit_band);
//   3. phi: each cell's share of the reference sphere's image, xi linear
//      across the cell; the sphere's volume kept to round-off by moving the
//      sum's error into the interface cells as phi's bounded redistribution
//      does (phi_from_map);
//   4. B = F F^T, F = (grad xi)^-1, where phi > 0 (b_from_map).
// One lone sphere, so that xi is one smooth field; the dense cases would need
// one map per particle (the colour fields' boxes).
#pragma once
#include <functional>

#include "../kernels/flow_state.hpp"
#include "../kernels/reference_map.hpp"
#include "../kernels/solid_state.hpp"
#include "../kernels/solid_transport.hpp"
#include "grid.hpp"
#include "halo.hpp"
#include "poisson.hpp"

namespace softflow {

class ReferenceMap {
 public:
  ReferenceMap() = default;  // off
  // the sphere of radius r about c is the reference configuration;
  // correction_passes: correct_volume's calls a step (0: no correction; the
  // work box's margin counts them)
  ReferenceMap(const Grid& g, const Real c[3], Real r, int correction_passes);
  int correction_passes() const { return correction_passes_; }
  bool on() const { return xi_[0].data() != nullptr; }
  const Field3& xi(int m) const { return xi_[m]; }
  const Field3& inside() const { return inside_; }
  Real volume() const { return volume_; }

  // xi = x (the undeformed particle), then the band
  void seed(const Grid& g, Halo& halo, const FaceFluxes& scratch);
  // Before each step: the cells the map can touch in it (work()), the
  // global bounding box of the cells mapping inside grown by work_margin and
  // clipped to this rank's interior; every pass of the map but the halo runs
  // there only. whole: the interior (the reference the box is tested
  // against). Why the box: in a dilute case it is a few percent of the grid,
  // and the map's advection, band fits and masks over the whole box made its
  // step twice the phi/B model's (round 34).
  void begin_step(const Grid& g, MPI_Comm comm, bool whole);
  const Range3& work() const { return work_; }
  // the target of step 3: the solid volume (at the start and on restart)
  void set_volume(Real v) { volume_ = v; }
  // steps 1 and 2 (flux: the transport's face-flux scratch)
  void advance_stage(const Grid& g, const FlowState& flow, const FaceFluxes& flux, Real gdt, Real zdt,
                     Halo& halo);
  // step 2b (particles.map_volume_correction), after a step's last stage, in
  // particles.map_correction_passes passes: the map made volume-preserving
  // to first order by a potential displacement d = grad psi of its material,
  // L psi = 1 - 1 / det(grad xi) in the cells mapping inside (their sum sunk
  // evenly in the fluid), xi <- xi - (grad xi) d in every cell, then the
  // band refitted. An incompressible flow has no force that sees det(grad
  // xi) (an isotropic stress is a pressure), so nothing else removes the
  // map's volume error. Returns max |det B - 1| over the inside
  // cells before the correction (det B = det(grad xi)^-2)
  Real correct_volume(const Grid& g, PoissonSolver& poisson, Halo& halo, const FaceFluxes& scratch);
  // steps 3 and 4 into q (interior cells); returns the volume error step 3
  // moved, relative to the volume
  Real solid_from_map(const Grid& g, const SolidFields& q, const FaceFluxes& scratch,
                      const std::function<void(Real*, int)>& allreduce_sum) const;
  void fill_ghosts(const Grid& g, Halo& halo) const;
  // after a restart read xi and the inside marks: their ghosts
  void resume(const Grid& g, Halo& halo);

  // public only because nvcc's device lambdas cannot live in private members:
  // step 2 (after seed and every advance)
  void refit_band(const Grid& g, Halo& halo, const FaceFluxes& scratch);
  // the band fits' prior: the mean difference of xi between neighbouring
  // inside cells, per axis (grad xi in cell offsets)
  GradientPrior mean_gradient(const Grid& g, const std::function<void(Real*, int)>& allreduce_sum) const;

 private:
  Field3 xi_[3], now_[3], before_[3];
  Field3 inside_;          // 1 where a cell's centre maps inside the sphere (after the last band refit)
  GradientPrior prior_{};  // the last band refit's prior: solid_from_map's fits use the same
  Range3 work_{};          // this step's cells (begin_step); outside them xi holds the far value
  int correction_passes_ = 0;
  Real c_[3] = {0, 0, 0}, r_ = 1;
  Real volume_ = 0;
};

}  // namespace softflow
