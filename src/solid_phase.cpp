#include "solid_phase.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "../kernels/solid_debris.hpp"
#include "../kernels/solid_region.hpp"
#include "../kernels/solid_transport.hpp"

namespace softflow {

SolidPhase::SolidPhase(const Config& cfg, const Grid& g, Halo& halo)
    : cfg_(cfg),
      g_(g),
      halo_(halo),
      q_(g, "solid"),
      rhs_now_(g, "solid_rhs_now"),
      rhs_before_(g, "solid_rhs_before"),
      flux_(g, cfg.particles.phi_scheme == "mthinc"),
      force_now_(g, "elastic_now"),
      force_before_(g, "elastic_before") {
  auto f = [&](const char* name) { return Field3(std::string(name), g.sx(), g.sy(), g.sz()); };
  tau_ = {f("tau_xx"), f("tau_xy"), f("tau_xz"), f("tau_yy"), f("tau_yz"), f("tau_zz")};
  nu_ = {f("nu_centre"), f("nu_xy"), f("nu_xz"), f("nu_yz")};
  stress_.idx = 1 / g.dx;
  stress_.idy = 1 / g.dy;
  stress_.idz = 1 / g.dz;
  stress_.nu_f = cfg.nu();
  stress_.dnu = (cfg.solid_viscosity() - cfg.fluid.mu) / cfg.fluid.rho;
  stress_.g_rho = cfg.shear_modulus() / cfg.fluid.rho;
  phi_scheme_.thinc_beta = cfg.particles.phi_scheme != "weno5" ? cfg.particles.thinc_beta : 0;
  phi_scheme_.multi_d = cfg.particles.phi_scheme == "mthinc";
  if (const int n = colour_count(cfg); n > 0) {
    colours_ = ColourFields(g, n, cfg.particles.colour_cut);
    phi_scheme_.phi_from_colours = true;
    bound_colour_sum_ = cfg.particles.colour_sum_bound;
  }
  if (cfg.particles.solid_model == "reference_map") {
    // allocated here, not in seed(): a restart reads the map into it. The
    // sphere is the case's (centre, or drawn from its seed), as seed() places it
    const std::vector<Sphere> s = seed_spheres(cfg);
    const Real c[3] = {Real(s[0].x), Real(s[0].y), Real(s[0].z)};
    map_ = ReferenceMap(g, c, cfg.particles.radius,
                        cfg.particles.map_volume_correction ? cfg.particles.map_correction_passes : 0);
  }
  extend_b_ = cfg.particles.b_extension && !map_.on();
  extend_every_stage_ = cfg.particles.b_extension_stages == "all";
  b_solid_phi_ = cfg.particles.b_solid_phi;
  own_b_phi_ = std::min(b_solid_phi_, phi_solid);
  return_debris_ = cfg.particles.debris_return && extend_b_;
  // the colours would undo it: phi is their sum again after the next stage
  if (return_debris_ && colours_.size() > 0)
    throw InputError(
        "'particles.debris_return' works on one phi field: set 'particles.colour_fields = 0' "
        "(this case has " +
        std::to_string(colours_.size()) + " colour fields)");
  if (extend_b_) b_live_ = LiveCells(g);
  if (extend_b_ && b_solid_phi_ > own_b_phi_) core_logs_ = SolidFields(g, "solid_core_log");
  unimodular_b_ = cfg.particles.unimodular_b;
  // the det test needs det B = 1 at every stage's start: only with the projection
  b_check_.on = cfg.particles.b_fallback && !map_.on();
  b_check_.det_tol = unimodular_b_ ? cfg.particles.b_fallback_det : 0;
  b_check_.phi_min = extend_b_ ? own_b_phi_ : phi_fluid_cut;
  b_check_.flag = flux_.x;  // the face-flux scratch is free once the stage's fluxes are summed
}

// Elastic waves are advanced explicitly (B from the stage's starting
// velocity): RK3's imaginary-axis bound sqrt(3) over the largest eigenvalue of
// the staggered wave operator, 2 c sqrt(1/dx^2 + 1/dy^2 + 1/dz^2), with c the
// wave speed of the most stretched solid.
Real SolidPhase::elastic_dt(Real stretch) const {
  const Real c = std::sqrt(stress_.g_rho * stretch);
  return std::sqrt(3.0) / 2 /
         (c * std::sqrt(stress_.idx * stress_.idx + stress_.idy * stress_.idy + stress_.idz * stress_.idz));
}

Real SolidPhase::max_stretch() const {
  const SolidViews q(q_);
  Real m = 1;
  par_reduce(
      "solid_max_stretch", region_,
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) {
        const Real xx = q.b0(i, j, k), xy = Kokkos::fabs(q.b1(i, j, k)), xz = Kokkos::fabs(q.b2(i, j, k)),
                   yy = q.b3(i, j, k), yz = Kokkos::fabs(q.b4(i, j, k)), zz = q.b5(i, j, k);
        const Real l = Kokkos::fmax(xx + xy + xz, Kokkos::fmax(xy + yy + yz, xz + yz + zz));
        const Real v = fraction(q.phi(i, j, k)) * l;
        a = v > a ? v : a;
      },
      Kokkos::Max<Real>(m));
  return m > 1 ? m : Real(1);
}

namespace {
// d^T B^-1 d for a B with det 1 (B^-1 = adj B); d^T d when B = I, to the bit
struct EllipsoidNorm {
  Real a0, a1, a2, a3, a4, a5;
  explicit EllipsoidNorm(const Real* b)
      : a0(b[3] * b[5] - b[4] * b[4]),
        a1(b[2] * b[4] - b[1] * b[5]),
        a2(b[1] * b[4] - b[2] * b[3]),
        a3(b[0] * b[5] - b[2] * b[2]),
        a4(b[1] * b[2] - b[0] * b[4]),
        a5(b[0] * b[3] - b[1] * b[1]) {}
  KOKKOS_INLINE_FUNCTION Real operator()(Real x, Real y, Real z) const {
    return a0 * x * x + a3 * y * y + a5 * z * z + 2 * (a1 * x * y + a2 * x * z + a4 * y * z);
  }
};
}  // namespace

void SolidPhase::seed() {
  const Grid g = g_;
  const SolidViews q(q_);
  const ParticleConfig& p = cfg_.particles;
  if (p.shape == "layer") {
    const Real half = p.layer_thickness / 2;
    par_for(
        "seed_layer", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
          const Real lo = Kokkos::fmax(g.yc(j) - g.dy / 2, -half),
                     hi = Kokkos::fmin(g.yc(j) + g.dy / 2, half);
          q.phi(i, j, k) = Kokkos::fmax(Real(0), hi - lo) / g.dy;
        });
  } else {
    spheres_ = seed_spheres(cfg_);
    const int n = int(spheres_.size());
    Kokkos::View<Real* [3], MemSpace> c("seed_centres", n);
    auto ch = Kokkos::create_mirror_view(c);
    for (int m = 0; m < n; ++m) {
      ch(m, 0) = spheres_[m].x;
      ch(m, 1) = spheres_[m].y;
      ch(m, 2) = spheres_[m].z;
    }
    Kokkos::deep_copy(c, ch);
    const Real r = p.radius, lx = g.lx, lz = g.lz;
    const int ns = p.subsamples;
    // each particle is the ellipsoid |d|_A < r, |d|_A^2 = d^T A d with A =
    // B^-1 (the sphere when B = I). |.|_A is a norm with Lipschitz constant
    // sqrt(lambda_max(A)) = 1 / sqrt(lambda_min(B)) <= lambda_max(B) (det B
    // = 1: lambda_min >= 1 / lambda_max^2): beyond r + hd lambda_max(B) a cell
    // is outside, within r minus that inside, hd the half-diagonal of a cell
    const EllipsoidNorm norm2(p.initial_b);
    const Real lip = p.deformed_start() ? largest_stretch(p.initial_b) : Real(1);
    const Real hd = 0.5 * std::sqrt(g.dx * g.dx + g.dy * g.dy + g.dz * g.dz) * lip;
    // into phi, or with colours each colour's particles into its field
    const int ncol = colours_.size();
    for (int col = 0; col < std::max(1, ncol); ++col) {
      const Field3 out = ncol > 0 ? colours_.colour(col) : q.phi;
      par_for(
          "seed_spheres", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
            const Real x = g.xc(i), y = g.yc(j), z = g.zc(k);
            Real f = 0;
            for (int m = 0; m < n; ++m) {
              if (ncol > 0 && m % ncol != col) continue;
              Real dx = x - c(m, 0), dy = y - c(m, 1), dz = z - c(m, 2);
              dx -= lx * Kokkos::round(dx / lx);
              dz -= lz * Kokkos::round(dz / lz);
              const Real d = Kokkos::sqrt(norm2(dx, dy, dz));
              if (d >= r + hd) continue;
              if (d <= r - hd) {
                f += 1;
                continue;
              }
              int in = 0;
              for (int a = 0; a < ns; ++a)
                for (int b = 0; b < ns; ++b)
                  for (int e = 0; e < ns; ++e) {
                    const Real sx = dx + g.dx * ((a + Real(0.5)) / ns - Real(0.5));
                    const Real sy = dy + g.dy * ((b + Real(0.5)) / ns - Real(0.5));
                    const Real sz = dz + g.dz * ((e + Real(0.5)) / ns - Real(0.5));
                    in += norm2(sx, sy, sz) < r * r;
                  }
              f += Real(in) / (ns * ns * ns);
            }
            out(i, j, k) = Kokkos::fmin(Real(1), f);
          });
    }
    if (ncol > 0) colours_.sum_into(q.phi, g.interior());
  }
  // B = I in the fluid; a deformed start's B in every cell with solid
  const Real* b = p.initial_b;
  const Real s0 = b[0], s1 = b[1], s2 = b[2], s3 = b[3], s4 = b[4], s5 = b[5];
  par_for(
      "seed_b", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        const bool solid = q.phi(i, j, k) > 0;
        q.b0(i, j, k) = solid ? s0 : 1;
        q.b1(i, j, k) = solid ? s1 : 0;
        q.b2(i, j, k) = solid ? s2 : 0;
        q.b3(i, j, k) = solid ? s3 : 1;
        q.b4(i, j, k) = solid ? s4 : 0;
        q.b5(i, j, k) = solid ? s5 : 1;
      });
  fill_ghosts();
  if (map_.on()) {
    map_.seed(g_, halo_, flux_);
    map_.set_volume(solid_volume());
    solid_from_map();
  }
}

Real SolidPhase::solid_volume() const {
  const Field3 phi = q_.phi();
  Real v = 0;
  par_reduce(
      "solid_volume_sum", g_.interior(), KOKKOS_LAMBDA(int i, int j, int k, Real& s) { s += phi(i, j, k); },
      Kokkos::Sum<Real>(v));
  MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_DOUBLE, MPI_SUM, halo_.comm());
  return v;
}

void SolidPhase::solid_from_map() {
  const auto allreduce_sum = [this](Real* x, int n) {
    MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_SUM, halo_.comm());
  };
  const Real moved = map_.solid_from_map(g_, q_, flux_, allreduce_sum);
  b_stats_.map_volume_moved = std::max(b_stats_.map_volume_moved, std::abs(moved));
  fill_ghosts();
  constrain_b(false);
}

void SolidPhase::fill_ghosts() {
  halo_.exchange({q_.q[0], q_.q[1], q_.q[2], q_.q[3], q_.q[4], q_.q[5], q_.q[6]});
  apply_solid_walls(g_, q_);
  colours_.fill_ghosts(halo_, g_);
}

// after B's constraints, which leave phi (and its ghosts) as they are
void SolidPhase::fill_b_ghosts() {
  halo_.exchange({q_.q[1], q_.q[2], q_.q[3], q_.q[4], q_.q[5], q_.q[6]});
  apply_solid_walls<1>(g_, q_);
}

const StoredNu& SolidPhase::viscosity(const Range3& where) {
  if (where.size() <= 0) return nu_;
  const NuFromPhi from{stress_.nu_f, stress_.dnu, q_.phi()};
  const StoredNu n = nu_;
  // one cell around `where`, where the viscous stencils read (`where` is a part
  // of the interior, so an edge value at the top still has its +1 neighbours)
  par_for(
      "solid_viscosity", grown(where, 1, g_.all()), KOKKOS_LAMBDA(int i, int j, int k) {
        n.c(i, j, k) = from.centre(i, j, k);
        n.exy(i, j, k) = from.xy(i, j, k);
        n.exz(i, j, k) = from.xz(i, j, k);
        n.eyz(i, j, k) = from.yz(i, j, k);
      });
  return nu_;
}

void SolidPhase::elastic_force(const MomentumRhs& out, const Range3& where) {
  if (where.size() <= 0) return;
  const MixtureStress st = stress_;
  const TauFromB from{st, SolidViews(q_)};
  const StoredTau t = tau_;
  // the stress where the force's stencils read it: one cell around `where`
  const Range3 wide = grown(where, 1, g_.all());
  par_for(
      "solid_elastic_stress", wide, KOKKOS_LAMBDA(int i, int j, int k) {
        t.t0(i, j, k) = from(0, i, j, k);
        t.t1(i, j, k) = from(1, i, j, k);
        t.t2(i, j, k) = from(2, i, j, k);
        t.t3(i, j, k) = from(3, i, j, k);
        t.t4(i, j, k) = from(4, i, j, k);
        t.t5(i, j, k) = from(5, i, j, k);
      });
  auto fu = out.u, fv = out.v, fw = out.w;
  const int vtop = Grid::ng + g_.ny - 1;
  par_for(
      "solid_elastic_force", where, KOKKOS_LAMBDA(int i, int j, int k) {
        fu(i, j, k) = st.elastic_u(t, i, j, k);
        fw(i, j, k) = st.elastic_w(t, i, j, k);
        fv(i, j, k) = j < vtop ? st.elastic_v(t, i, j, k) : Real(0);
      });
}

void SolidPhase::init_force() {
  if (map_.on()) map_.resume(g_, halo_);  // a restart's map needs its ghosts
  begin_step();
  for (const MomentumRhs* f : {&force_now_, &force_before_}) {
    Kokkos::deep_copy(f->u, 0.0);
    Kokkos::deep_copy(f->v, 0.0);
    Kokkos::deep_copy(f->w, 0.0);
  }
  elastic_force(force_before_, force_region_);
}

void SolidPhase::begin_step() {
  const Range3 old_force = force_region_;
  if (!track_region_) {
    region_ = force_region_ = g_.interior();
  } else {
    const IndexBox support = phi_support(g_, q_.phi());
    region_ = grown_range(support, solid_region_margin, g_.interior());
    force_region_ = grown_range(support, solid_region_margin + 1, g_.interior());
  }
  colours_.begin_step(g_, region_);
  if (map_.on()) map_.begin_step(g_, halo_.comm(), !track_region_);
  // the force arrays must hold 0 wherever the force kernel no longer writes
  // (the force there is 0: phi's support lies inside the new region)
  zero_outside(force_now_, old_force, force_region_);
  zero_outside(force_before_, old_force, force_region_);
}

// f = 0 on the cells of old_region outside new_region
void SolidPhase::zero_outside(const MomentumRhs& f, const Range3& old_region, const Range3& n) {
  auto fu = f.u, fv = f.v, fw = f.w;
  par_for(
      "solid_force_clear", old_region, KOKKOS_LAMBDA(int i, int j, int k) {
        if (n.contains(i, j, k)) return;
        fu(i, j, k) = 0;
        fv(i, j, k) = 0;
        fw(i, j, k) = 0;
      });
}

void SolidPhase::advance_stage(const FlowState& flow, Real gdt, Real zdt, bool last_stage) {
  if (map_.on()) {
    map_.advance_stage(g_, flow, flux_, gdt, zdt, halo_);
    // once a step: a stage's drift is small, and each pass costs a Poisson
    // solve. A pass removes only part of an error in a cell next to the band
    // (its central differences read the band's refitted values), so a second
    // pass helps there (round 37, 4 ppr, Ca = 0.2, strain 0-7: det B before
    // the projection in [0.979, 1.029] with one pass, [0.985, 1.017] with two)
    if (last_stage)
      for (int pass = 0; pass < map_.correction_passes(); ++pass) {
        const Real found = map_.correct_volume(g_, *poisson_, halo_, flux_);
        if (pass == 0) b_stats_.map_det_corrected = std::max(b_stats_.map_det_corrected, found);
      }
    solid_from_map();
    elastic_force(force_now_, force_region_);
    return;
  }
  // the right-hand sides vanish beyond phi's current support + 3 cells (the
  // WENO stencil); a dilute case's support is much smaller than the region,
  // which has to hold a whole step's growth
  const Range3 active = track_region_ ? grown_range(phi_support(g_, q_.phi()), 3, region_) : region_;
  PhiScheme scheme = phi_scheme_;
  scheme.stage_dt = gdt + zdt;  // solid_rk3_update: q += gdt r_now + zdt r_before
  const bool live = extend_b_ && b_live_cells_;
  if (live && !active.empty())
    mark_near(
        q_.phi(), phi_b_live, 1,
        Range3{active.ib - 1, active.ie + 1, active.jb - 1, active.je + 1, active.kb - 1, active.ke + 1},
        flux_.x, flux_.y, b_live_.mask);  // the face-flux scratch is free before the transport
  solid_transport_rhs(g_, flow, q_, rhs_now_, flux_, region_, active, scheme, live ? b_live_ : LiveCells{});
  const auto allreduce_sum = [this](Real* x, int n) {
    MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_SUM, halo_.comm());
  };
  if (colours_.size() > 0) {
    // phi's right-hand side is 0: the colours move, and phi is their sum
    // before B's update reads it (its reset to I where phi vanishes)
    colours_.advance_stage(g_, flow, flux_, scheme, gdt, zdt, allreduce_sum);
    colours_.sum_into(q_.phi(), region_);
    if (bound_colour_sum_ && colours_.bound_sum(q_.phi(), allreduce_sum))
      colours_.sum_into(q_.phi(), region_);
  }
  solid_rk3_update(q_, rhs_now_, rhs_before_, gdt, zdt, region_, b_check_);
  if (b_check_.on) {
    const long troubled = count_troubled(b_check_, region_);
    if (troubled > 0) b_upwind_fallback(g_, flow, q_, rhs_now_, rhs_before_, b_check_, gdt, zdt, region_);
    b_stats_.fallback_cells += troubled;
  }
  if (colours_.size() == 0) phi_bounded_redistribution(q_.phi(), allreduce_sum, region_);
  std::swap(rhs_now_, rhs_before_);
  fill_ghosts();
  constrain_b(extend_every_stage_ || last_stage);
  elastic_force(force_now_, force_region_);
}

void SolidPhase::constrain_b(bool extend) {
  if (extend_b_ && extend) {
    // the transport's face-flux scratch is free between stages: the masks'
    // passes use its arrays. The largest phi within two cells says which
    // cells are near the core and which near phi >= 0.5 (phi does not
    // change in the bands, so both read the one field)
    block_max(q_.phi(), 2, region_, flux_.x, flux_.y, flux_.x);
    // the lost solid back to its particle first, so that the bands below
    // see the phi that stays (a cell the return lifts past own_b_phi_ must
    // not keep a band's B)
    if (return_debris_ && return_debris(flux_.x)) block_max(q_.phi(), 2, region_, flux_.x, flux_.y, flux_.x);
    if (b_solid_phi_ > own_b_phi_) {
      // the inner band first, from the core: the outer band then reads it.
      // The log of each core cell within two of the band, once (the third
      // scratch array holds the mask), then the band's mean of them
      const Range3 sources = grown(region_, 2, g_.all());
      mark_near_below(q_.phi(), b_solid_phi_, 2, sources, flux_.z, flux_.y, flux_.z);
      log_core_b(q_, sources, b_solid_phi_, flux_.z, core_logs_);
      extend_b_from_solid(q_, region_, flux_.x, ExtensionBand{own_b_phi_, b_solid_phi_, true, core_logs_});
      // the outer band reads inner band cells up to two cells into the
      // ghosts (a neighbour rank's, a periodic image's, a wall's mirror):
      // they must hold the new B there too, not the transport's (without
      // this the answer depended on the rank grid, 1e-4-1e-2 in 6 steps)
      fill_b_ghosts();
    }
    extend_b_from_solid(q_, region_, flux_.x, ExtensionBand{-1, own_b_phi_, false, {}});
  }
  Real st[4];
  if (unimodular_b_) {
    const UnimodularStats u = project_b_unimodular(q_, region_);
    st[0] = -u.det_min, st[1] = u.det_max, st[2] = u.removed_xy, st[3] = u.kept_xy;
  } else {
    const Kokkos::MinMaxScalar<Real> mm = det_b_range(q_, region_);
    st[0] = -mm.min_val, st[1] = mm.max_val, st[2] = 0, st[3] = 1;
  }
  MPI_Allreduce(MPI_IN_PLACE, st, 2, MPI_DOUBLE, MPI_MAX, halo_.comm());
  MPI_Allreduce(MPI_IN_PLACE, st + 2, 2, MPI_DOUBLE, MPI_SUM, halo_.comm());
  b_stats_.det_min = std::min(b_stats_.det_min, -st[0]);
  b_stats_.det_max = std::max(b_stats_.det_max, st[1]);
  const Real total = st[2] + st[3];
  if (total != 0) b_stats_.removed_sum += st[2] / total;
  ++b_stats_.stages;
  if (extend_b_ || unimodular_b_) fill_b_ghosts();
}

// Lost solid back to the particles' interface (kernels/solid_debris.hpp);
// near_max: block_max with reach 2. Returns whether any solid moved (then
// the block max is stale; the ghosts are filled here).
bool SolidPhase::return_debris(const Field3& near_max) {
  Real sums[3];
  debris_sums(q_.phi(), near_max, region_, sums);
  MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPI_DOUBLE, MPI_SUM, halo_.comm());
  if (sums[0] <= 0) return false;
  b_stats_.debris_returned += sums[2] > 0 ? sums[0] / sums[2] : 0;
  softflow::return_debris(q_, near_max, region_, sums);
  fill_ghosts();
  return true;
}

SolidPhase::BStats SolidPhase::take_b_stats() {
  BStats s = b_stats_;
  b_stats_ = BStats{};
  return s;
}

}  // namespace softflow
