// The particles' phase of the one-continuum model: phi, B, their RK3
// right-hand sides and the elastic force. Allocated only for cases with
// [particles]; FlowSolver calls it inside each RK3 stage.
#pragma once
#include <vector>

#include "../kernels/flow_state.hpp"
#include "../kernels/mixture_stress.hpp"
#include "../kernels/solid_extension.hpp"
#include "../kernels/solid_state.hpp"
#include "../kernels/solid_transport.hpp"
#include "colour_fields.hpp"
#include "config.hpp"
#include "halo.hpp"
#include "particle_seeding.hpp"
#include "reference_map.hpp"

namespace softflow {

class SolidPhase {
 public:
  SolidPhase(const Config& cfg, const Grid& g, Halo& halo);

  // phi from the seeded spheres (or the layer) by sub-cell sampling; B = I
  void seed();
  void fill_ghosts();
  void fill_b_ghosts();  // B's six fields only

  // Before each step: the region the solid can reach in it (phi's support
  // grown by solid_region_margin, kernels/solid_region.hpp); phi and B are
  // advanced there only, the elastic force one cell further.
  void begin_step();
  const Range3& region() const { return region_; }
  const Range3& force_region() const { return force_region_; }
  // off: the whole interior every step (the reference the region is tested
  // against)
  void set_region_tracking(bool on) { track_region_ = on; }
  // B's right-hand side only in live cells (the default with B's extension;
  // off: everywhere, for the test that both give the same answer)
  void set_b_live_cells(bool on) { b_live_cells_ = on; }

  // stage s, before the momentum update: advance phi and B from the velocity
  // of the previous stage, then B's constraints (constrain_b: B's extension
  // after every stage, or after a step's last one only, as
  // particles.b_extension_stages says); then compute the new elastic force
  void advance_stage(const FlowState& flow, Real gdt, Real zdt, bool last_stage);
  // the flow's Poisson solver, free between its projections (the reference
  // map's volume correction solves with it)
  void use_poisson(PoissonSolver& p) { poisson_ = &p; }
  // the elastic force of the current phi, B into force_before() (start of a
  // run, restart or a changed phi/B); also sets the region
  void init_force();
  // the stage's elastic force: (E_now + E_before) / 2, to be multiplied by
  // alpha dt
  const MomentumRhs& force_now() const { return force_now_; }
  const MomentumRhs& force_before() const { return force_before_; }
  void end_stage() { std::swap(force_now_, force_before_); }

  const SolidFields& fields() const { return q_; }
  // with particles.colour_fields: phi's colours (phi is their sum)
  const ColourFields& colours() const { return colours_; }
  // with particles.solid_model = "reference_map": the map phi and B are read from
  const ReferenceMap& reference_map() const { return map_; }
  ReferenceMap& reference_map() { return map_; }
  ColourFields& colours() { return colours_; }
  const MixtureStress& stress() const { return stress_; }
  // K = 1: the mixture's viscosity is the fluid's everywhere, so the
  // viscous excess div(2 mu(phi) D) / rho - nu_f L u is nu_f grad(div u), zero
  // to round-off (u is projected): the flow solver skips it and nu(phi)
  bool uniform_viscosity() const { return stress_.dnu == 0; }
  // nu(phi) of the current phi at the cell centres and edges the viscous
  // stencils of `where` (a part of the interior) read; returns the arrays
  const StoredNu& viscosity(const Range3& where);
  const std::vector<Sphere>& spheres() const { return spheres_; }
  // dt limit of the explicit elastic waves for a given stretch (below)
  Real elastic_dt(Real stretch) const;
  // max over this rank's cells of phi lambda_max(B) (Gershgorin bound), at
  // least 1: a neo-Hookean solid's wave speed is sqrt(G lambda_max(B) / rho)
  Real max_stretch() const;
  // sum of phi over the interior, all ranks
  Real solid_volume() const;

  // det B before the unimodular projection (phi > 0.5 cells; without the
  // projection, after each stage), the sum over stages of the share of
  // the solid's elastic shear stress each projection removed (signed: a
  // bias shows as a non-zero mean) and the cells whose B took the
  // first-order fallback, since the last call (then reset)
  struct BStats {
    Real det_min = 1e300, det_max = -1e300, removed_sum = 0;
    long stages = 0;
    long fallback_cells = 0;  // cell-stages of this rank whose B took the first-order fallback
    // the reference map's: the largest |det B - 1| its volume correction
    // found (before correcting), and the largest volume error, relative, its
    // phi moved into the interface cells (all ranks)
    Real map_det_corrected = 0, map_volume_moved = 0;
    Real debris_returned = 0;  // particles.debris_return: the solid volume returned, relative, summed
  };
  BStats take_b_stats();

  // public only because nvcc forbids extended (KOKKOS_LAMBDA) lambdas in
  // private or protected member functions
  void elastic_force(const MomentumRhs& out, const Range3& where);
  void zero_outside(const MomentumRhs& f, const Range3& old_region, const Range3& new_region);
  // B in the interface band from the solid side (`extend`: as the case asks),
  // then det B = 1 (as the case asks; kernels/solid_extension.hpp)
  void constrain_b(bool extend = true);
  // particles.debris_return: lost solid back to the interface (the .cpp says which)
  bool return_debris(const Field3& near_max);
  // reference map: phi and B from the map, then det B = 1 (as the case asks)
  void solid_from_map();

 private:
  const Config& cfg_;
  Grid g_;
  Halo& halo_;
  SolidFields q_, rhs_now_, rhs_before_;
  ColourFields colours_;  // empty: phi is transported itself
  PoissonSolver* poisson_ = nullptr;
  ReferenceMap map_;       // off: phi and B are transported themselves
  FaceFluxes flux_;        // the transport's face-flux scratch
  LiveCells b_live_;       // with B's extension: where B's right-hand side is needed (mark_near with reach 1)
  SolidFields core_logs_;  // with b_solid_phi > 1/2: the core's log B the inner band reads (log_core_b)
  MomentumRhs force_now_, force_before_;
  MixtureStress stress_;
  StoredTau tau_;  // the elastic stress at cell centres, the force kernel's input
  StoredNu nu_;    // the mixture viscosity at centres and edges
  std::vector<Sphere> spheres_;
  PhiScheme phi_scheme_;
  bool extend_b_, unimodular_b_;
  bool extend_every_stage_ = false;  // particles.b_extension_stages = "all" (else the step's last stage only)
  bool bound_colour_sum_ = true;     // particles.colour_sum_bound (ColourFields::bound_sum)
  Real b_solid_phi_;                 // B's own equation at or above, the extension's below
  Real own_b_phi_;                   // B's own equation at or above: min(b_solid_phi, 1/2)
  bool return_debris_ = false;       // particles.debris_return (SolidPhase::return_debris)
  BCheck b_check_;  // B's admissibility test and first-order fallback (kernels/solid_b_fallback.hpp)
  BStats b_stats_;
  bool track_region_ = true;
  bool b_live_cells_ = true;
  Range3 region_{}, force_region_{};
};

}  // namespace softflow
