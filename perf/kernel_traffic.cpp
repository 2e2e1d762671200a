#include "kernel_traffic.hpp"

#include <unordered_map>

namespace softflow::perf {

// Not in the table (nullopt): the halo's copies (halo_periodic_*, halo_pack_*,
// halo_unpack_*) and the wall ghosts (walls_velocity, walls_pressure,
// walls_solid), which scale with a surface; kernels of the set-up (init_*,
// seed_*), of the output (io_*, tracker_*) and of the diagnostics
// (diagnostics_*).
std::optional<Traffic> kernel_traffic(const std::string& label) {
  static const std::unordered_map<std::string, Traffic> table = {
      // kernels/momentum_rhs.hpp; the implicit stage's advection (nu = 0) reads
      // the same arrays
      {"momentum_rhs", {3, 3, "r: u,v,w; w: ru,rv,rw"}},
      // near the solid only (force region): adds to ru, rv, rw
      {"momentum_viscous_excess", {10, 3, "r: u,v,w,nu(4),ru,rv,rw; w: ru,rv,rw", Domain::solid_force}},
      // kernels/rk3_update.hpp: u, v, w read and written
      {"rk3_update", {9, 3, "r: u,v,w, N_now(3), N_before(3); w: u,v,w"}},
      {"rk3_update_cn", {15, 3, "r: u,v,w, N_now(3), N_before(3), F_now(3), F_before(3); w: u,v,w"}},
      // kernels/projection.hpp; the incremental projection (implicit) writes
      // and reads dp instead of p
      {"projection_divergence", {3, 1, "r: u,v,w; w: poisson rhs"}},
      {"projection_copy_pressure", {1, 1, "r: poisson solution; w: p (dp)"}},
      {"projection_correct", {4, 3, "r: p (dp),u,v,w; w: u,v,w"}},
      // kernels/implicit_viscous.hpp; the particles' terms near the solid only
      // (the whole box for K > 1)
      {"implicit_predictor", {10, 3, "r: u,v,w,p, N_now(3), N_before(3); w: helm_u,helm_v,helm_w"}},
      {"implicit_predictor_solid",
       {16, 3, "r: u,v,w,nu(4), F_now(3), F_before(3), helm(3); w: helm(3)", Domain::solid_force}},
      // K = 1 (uniform mixture viscosity): the force alone
      {"implicit_predictor_force", {9, 3, "r: F_now(3), F_before(3), helm(3); w: helm(3)", Domain::solid_force}},
      {"implicit_copy_velocity", {3, 3, "r: helm_u,helm_v,helm_w; w: u,v,w"}},
      {"implicit_pressure_update", {2, 1, "r: p,dp; w: p"}},
      // kernels/timestep_limits.hpp (reduction)
      {"timestep_advective_rate", {3, 0, "r: u,v,w"}},
      // kernels/solid_transport.hpp, per call (flux and divergence run once per
      // field, 7 per stage);
      // the source counts the solid path (a cell whose whole stencil is fluid
      // reads only phi and
      // writes zeros) (all over the solid region of kernels/solid_region.hpp)
      {"solid_transport_flux", {4, 3, "r: u,v,w, one field; w: its x, y, z face fluxes", Domain::solid}},
      // phi's THINC face fluxes (particles.phi_scheme = "thinc"): the same arrays
      {"solid_transport_flux_thinc", {4, 3, "r: u,v,w, phi; w: its x, y, z face fluxes", Domain::solid}},
      {"solid_transport_divergence", {3, 1, "r: the three face fluxes; w: the field's rhs", Domain::solid}},
      {"solid_transport_source", {16, 6, "r: u,v,w,phi,B(6),rhs B(6); w: rhs B(6)", Domain::solid}},
      {"solid_rk3_update",
       {21, 8, "r: phi,B(6), rhs_now(7), rhs_before(7); w: phi,B(6), fallback flag", Domain::solid}},
      // kernels/solid_b_fallback.hpp: the troubled-cell count runs every
      // stage; the fallback itself only where a cell is troubled (rare: its
      // per-cell traffic counts the troubled cell's flag only)
      {"solid_b_troubled_count", {1, 0, "r: fallback flag", Domain::solid}},
      {"solid_b_fallback", {1, 0, "r: fallback flag (+ B, rhs of the few troubled cells)", Domain::solid}},
      {"solid_b_fallback_swap",
       {1, 0, "r: fallback flag (+ B, rhs of the few troubled cells)", Domain::solid}},
      {"solid_phi_excess", {1, 0, "r: phi", Domain::solid}},
      {"solid_phi_interface_weight", {1, 0, "r: phi", Domain::solid}},
      {"solid_phi_redistribute", {1, 1, "r: phi; w: phi", Domain::solid}},
      // kernels/solid_extension.hpp: B in the interface band from the solid
      // side (reads a 5x5x5 block of phi and B, from cache: counted once),
      // det B's range, the projection and its shear sum
      {"solid_near_x", {1, 1, "r: phi; w: mask pass", Domain::solid}},
      {"solid_near_y", {1, 1, "r: mask pass; w: mask pass", Domain::solid}},
      {"solid_near_z", {1, 1, "r: mask pass; w: near-solid mask", Domain::solid}},
      {"solid_b_extension", {8, 6, "r: phi,mask,B(6); w: B(6) of band cells", Domain::solid}},
      {"solid_b_det_range", {7, 0, "r: phi,B(6)", Domain::solid}},
      {"solid_b_unimodular", {7, 6, "r: phi,B(6); w: B(6)", Domain::solid}},
      {"solid_b_shear_sum", {2, 0, "r: phi,Bxy", Domain::solid}},
      // src/solid_phase.cpp: the elastic force uses all six components of B
      {"solid_elastic_stress", {7, 6, "r: phi,B(6); w: tau(6)", Domain::solid_force}},
      {"solid_elastic_force", {6, 3, "r: tau(6); w: Fu,Fv,Fw", Domain::solid_force}},
      {"solid_viscosity", {1, 4, "r: phi; w: nu at centres and xy, xz, yz edges", Domain::solid_force}},
      {"solid_max_stretch", {7, 0, "r: phi,B(6)", Domain::solid}},
      // kernels/solid_region.hpp: phi over the whole storage, once per step
      {"solid_support_box", {1, 0, "r: phi", Domain::box}},
      // src/poisson.cpp, one Thomas sweep per line: the forward pass reads y
      // and writes y and the
      // scratch cp; the back substitution reads cp and y again and rewrites y
      // (lines of ny Reals per
      // thread do not stay in cache between the passes); the eigenvalue arrays
      // are negligible
      {"poisson_tridiagonal", {3, 3, "r: y, then cp,y; w: y,cp, then y (two passes)"}},
      // src/transpose.cpp: the whole pencil array (nxl ny nzl Reals) per call for pack (which
      // copies this rank's own block straight to its place); unpack moves (p - 1) / p of it,
      // counted here as the whole (an upper bound). With one rank in the group only the pack
      // label runs, as a direct permutation src -> dst
      {"transpose_pack_y_to_x", {1, 1, "r: y pencil; w: send buffer (x pencil)"}},
      {"transpose_unpack_y_to_x", {1, 1, "r: recv buffer; w: x pencil"}},
      {"transpose_pack_x_to_y", {1, 1, "r: x pencil; w: send buffer (y pencil)"}},
      {"transpose_unpack_x_to_y", {1, 1, "r: recv buffer; w: y pencil"}},
      {"transpose_pack_y_to_z", {1, 1, "r: y pencil; w: send buffer (z pencil)"}},
      {"transpose_unpack_y_to_z", {1, 1, "r: recv buffer; w: z pencil"}},
      {"transpose_pack_z_to_y", {1, 1, "r: z pencil; w: send buffer (y pencil)"}},
      {"transpose_unpack_z_to_y", {1, 1, "r: recv buffer; w: y pencil"}},
      // src/fft_cufft.cpp (CUDA builds): the complex work array holds n/2 + 1
      // complex per line of n
      // Reals, ~1 Real per cell
      {"fft_pack_halfcomplex", {1, 1, "r: fft work (complex); w: pencil"}},
      {"fft_unpack_halfcomplex", {1, 1, "r: pencil; w: fft work (complex)"}},
  };
  const auto it = table.find(label);
  if (it == table.end()) return std::nullopt;
  return it->second;
}

}  // namespace softflow::perf
