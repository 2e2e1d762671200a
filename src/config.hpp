// The case description: every input key, grouped by the table it lives in.
// Read from a TOML file, overridden from the command line, and checked before
// anything is written. docs/case-file.md documents every key.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "real.hpp"  // not types.hpp: config.cpp must compile without Kokkos

namespace softflow {

// Bad input: the message names the key or file and what is wrong with it.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct GridConfig {
  int nx = 0, ny = 0, nz = 0;   // cells
  Real lx = 0, ly = 0, lz = 0;  // box; walls at y = -ly/2 and +ly/2
};

struct FluidConfig {
  Real rho = 1;  // density
  Real mu = 0;   // dynamic viscosity mu_f
};

struct WallConfig {
  Real velocity = 0;  // V_w: the top wall moves at +V_w, the bottom at -V_w (x direction)
  Real omega = 0;     // if > 0 the walls oscillate: +-V_w cos(omega t)
};

// The solid phase. Absent ([particles] not given): no phi, no B, no cost.
struct ParticleConfig {
  bool enabled = false;
  std::string shape = "spheres";         // "spheres", or "layer": a solid slab |y| < thickness / 2
  Real radius = 1;                       // sphere radius r
  Real volume_fraction = -1;             // Phi of the box, or
  int count = -1;                        // the number of spheres (exactly one of the two)
  std::string placement = "stratified";  // "stratified" (random, even across y), "random", or "centre"
  Real min_gap = 0.1;                    // smallest surface-to-surface gap at seeding, also to the walls
  Real min_gap_cells = 1;                // and at least this many cell diagonals (src/particle_seeding.cpp)
  unsigned long seed = 1;                // random placement seed
  int subsamples = 8;                    // sub-cell samples per direction for phi at interfaces
  Real layer_thickness = 0;              // shape = "layer"
  Real capillary = -1;                   // Ca = mu_f gamma / G, or
  Real shear_modulus = -1;               // G (exactly one of the two)
  Real viscosity_ratio = 1;              // K = mu_s / mu_f
  // the solid phase's numerics (kernels/mthinc.hpp, kernels/solid_extension.hpp)
  // "phi_b": phi and B transported (the default); "reference_map": one lone
  // sphere's phi and B from its reference map xi (src/reference_map.hpp)
  std::string solid_model = "phi_b";
  bool map_volume_correction = false;  // "reference_map": the map made volume-preserving once a step
  int map_correction_passes = 2;       // the correction's passes a step (each one Poisson solve)
  std::string phi_scheme = "mthinc";   // phi's faces: "mthinc", "thinc" (sharp) or "weno5" (the reference's)
  Real thinc_beta = 3.5;               // (M)THINC steepness: the interface spans about 2 / beta cells
  bool b_extension = true;  // B in 0 < phi < b_solid_phi cells from the solid side (else its own equation)
  // at or above: B by its own equation; below: from the core (>= 0.5: the inner
  // band, 0.5 <= phi < b_solid_phi) or from the solid (phi >= min(b_solid_phi, 0.5))
  Real b_solid_phi = 0.9;
  // solid that has left its particle (cells with no phi >= 1/2 within two)
  // goes back to the particles' interface cells once a step (SolidPhase::return_debris)
  bool debris_return = false;
  std::string b_extension_stages = "last";  // B's extension after a step's last stage, or "all"
  bool unimodular_b = true;                 // B <- B / det(B)^(1/3) after each stage
  bool b_fallback = true;                   // first-order B update where the stage's is not admissible
  Real b_fallback_det = 0.02;  // admissible: positive definite and |det B - 1| <= this (0: no det test)
  // every sphere starts homogeneously deformed: B = this (xx, xy, xz, yy, yz,
  // zz; scaled to det B = 1 on input) inside, the shape x^T B^-1 x < r^2
  // about its centre (a deformed sphere of the same volume). Identity: spheres
  Real initial_b[6] = {1, 0, 0, 1, 0, 1};
  // phi as the sum of this many colour fields, particle m in colour m % n,
  // each transported on its own (src/colour_fields.hpp); 0: one phi field;
  // auto_colours ("auto", the default): one per sphere where there are two
  // or more (colour_count, src/particle_seeding.hpp)
  static constexpr int auto_colours = -1;
  int colour_fields = auto_colours;
  // a colour's values below this are set to 0 (their volume goes back to its
  // interface, as phi's below 1e-10): the tails set the boxes it is worked
  // on. 1e-4: the 67-colour dense step 1.22x the issue-time step instead of
  // 1.56x, and the dense cases it was run on pass (results/README.md, round 23)
  Real colour_cut = 1e-4;
  // the colours' sum kept at most 1, each colour's volume conserved
  // (ColourFields::bound_sum): where particles meet closer than a cell their
  // colours otherwise overlap and the mixture loses the overlap's solid
  bool colour_sum_bound = true;
  bool deformed_start() const {
    return initial_b[0] != 1 || initial_b[1] != 0 || initial_b[2] != 0 || initial_b[3] != 1 ||
           initial_b[4] != 0 || initial_b[5] != 1;
  }
};

struct TimeConfig {
  Real end_strain = -1;  // run until gamma * t reaches this (gamma = V_w / h), or
  Real end_time = -1;    // until t reaches this; exactly one of the two is given
  Real cfl = 0.9;        // safety factor on the advective and viscous limits
  Real dt_max = 1e30;    // upper bound on the time step
  long max_steps = 0;    // stop after this many steps (0: no limit)
  // "explicit": viscosity in the RK3 right-hand side (viscous time-step limit);
  // "implicit": Crank-Nicolson across each stage with a constant-coefficient
  // Helmholtz solve (no viscous limit; see kernels/implicit_viscous.hpp)
  std::string viscous = "explicit";
  bool implicit_viscous() const { return viscous == "implicit"; }
};

struct InitialConfig {
  // "rest": fluid at rest; "couette": the steady linear profile;
  // "manufactured": the manufactured solution (with its forcing) used in tests.
  std::string type = "rest";
  Real amplitude = 0.1;  // manufactured solution amplitude
  Real omega = 1.0;      // manufactured solution angular frequency
};

struct OutputConfig {
  std::string dir = "output";
  long progress_every = 100;      // steps between progress lines (0: none)
  long series_every = 10;         // steps between time-series rows (0: none)
  Real fields_every = 0;          // strain units between field snapshots (0: only at the end)
  long checkpoint_every = 0;      // steps between checkpoints (0: only at the end)
  Real checkpoint_minutes = 30;   // also a checkpoint after this much wall time (0: no)
  long profiles_every = 100;      // steps between profile samples in profiles_series.csv (0: none)
  Real average_from_strain = -1;  // start of the time averages (< 0: detected, see src/averaging.hpp)
};

struct ParallelConfig {
  int px = 0, pz = 0;  // MPI rank grid in x and z (0: chosen automatically)
};

struct Config {
  GridConfig grid;
  FluidConfig fluid;
  WallConfig walls;
  TimeConfig time;
  InitialConfig initial;
  OutputConfig output;
  ParallelConfig parallel;
  ParticleConfig particles;
  std::string restart;      // checkpoint to start from ("" = none)
  std::string case_name;    // file stem of the case file
  std::string source_text;  // the resolved case, as TOML, for the run summary

  Real h() const { return grid.ly / 2; }
  Real shear_rate() const { return walls.velocity / h(); }  // gamma = V_w / h
  Real nu() const { return fluid.mu / fluid.rho; }
  // the solid's shear modulus G (from Ca or given) and viscosity mu_s = K mu_f
  Real shear_modulus() const {
    return particles.shear_modulus > 0 ? particles.shear_modulus
                                       : fluid.mu * shear_rate() / particles.capillary;
  }
  Real solid_viscosity() const { return particles.viscosity_ratio * fluid.mu; }
  Real end_time_resolved() const;
};

// Reads the case file, applies "table.key=value" overrides, checks every
// key and value. Throws InputError naming the problem.
Config load_config(const std::string& path, const std::vector<std::string>& overrides);

// Same, from TOML text (tests use it).
Config parse_config(const std::string& toml_text, const std::string& name,
                    const std::vector<std::string>& overrides);

// Checks that need the rank count: chooses px, pz when 0, checks the grid
// divides among them.
void resolve_rank_grid(Config& cfg, int nranks);

}  // namespace softflow
