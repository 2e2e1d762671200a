#include "run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "csv_series.hpp"
#include "output.hpp"
#include "particle_seeding.hpp"
#include "run_averages.hpp"
#include "run_guard.hpp"
#include "solid_checks.hpp"
#include "version.hpp"

namespace softflow {

namespace {

std::string hms(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--:--";
  long t = long(s + 0.5);
  char b[32];
  std::snprintf(b, sizeof b, "%02ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  return b;
}

// measured: the end-of-run objects read back from the series ("averages",
// "solid_checks"), copied into the summary as they are
void write_summary(const FlowSolver& s, const FlowScalars& f, const RunResult& r, const std::string& dir,
                   const nlohmann::json& measured, size_t particle_count) {
  if (!s.decomposition().is_root()) return;
  const Config& c = s.config();
  nlohmann::json j;
  j["code"] = {{"name", "softflow"}, {"version", version()}, {"kokkos_execution_space", ExecSpace::name()}};
  j["case"] = {{"name", c.case_name},
               {"resolved_input", c.source_text},
               {"grid", {c.grid.nx, c.grid.ny, c.grid.nz}},
               {"box", {c.grid.lx, c.grid.ly, c.grid.lz}},
               {"rho", c.fluid.rho},
               {"mu_f", c.fluid.mu},
               {"wall_velocity", c.walls.velocity},
               {"shear_rate", c.shear_rate()},
               {"reynolds_h", c.fluid.rho * c.walls.velocity * c.h() / c.fluid.mu}};
  j["parallel"] = {{"ranks", s.decomposition().size},
                   {"px", c.parallel.px},
                   {"pz", c.parallel.pz},
                   {"threads_per_rank", ExecSpace().concurrency()}};
  j["final"] = {{"step", s.step},
                {"time", s.time},
                {"strain", s.time * c.shear_rate()},
                {"kinetic_energy", f.kinetic_energy},
                {"max_div", f.max_div},
                {"tau_bottom", f.tau_bottom},
                {"tau_top", f.tau_top},
                {"mu_eff", f.mu_eff},
                {"n1", f.n1},
                {"n2", f.n2}};
  for (const auto& [key, value] : measured.items()) j[key] = value;
  if (s.solid()) {
    j["case"]["particles"] = {
        {"count", particle_count},
        {"colour_fields", s.solid()->colours().size()},
        {"volume_fraction", f.solid_volume / (c.grid.lx * c.grid.ly * c.grid.lz)},
        {"radius", c.particles.radius},
        {"capillary",
         c.particles.capillary > 0 ? c.particles.capillary : c.fluid.mu * c.shear_rate() / c.shear_modulus()},
        {"shear_modulus", c.shear_modulus()},
        {"viscosity_ratio", c.particles.viscosity_ratio}};
    j["final"]["solid_volume"] = f.solid_volume;
    j["final"]["phi_range"] = {f.phi_min, f.phi_max};
    j["final"]["detb_range"] = {f.detb_min, f.detb_max};
  }
  const double cs = double(s.grid().cells_global()) * r.steps / std::max(r.wall_seconds, 1e-30);
  j["performance"] = {{"steps", r.steps}, {"wall_seconds", r.wall_seconds}, {"cell_steps_per_second", cs}};
  const std::string path = dir + "/summary.json";
  {
    std::ofstream o(path + ".tmp");
    o << j.dump(2) << "\n";
  }
  std::rename((path + ".tmp").c_str(), path.c_str());
}

}  // namespace

RunResult run_case(const Config& cfg, MPI_Comm comm, std::ostream& log, const AfterStep& after_step) {
  FlowSolver solver(cfg, comm);
  const bool root = solver.decomposition().is_root();
  const bool restarted = !cfg.restart.empty();
  std::vector<ParticleShape> tracked;
  if (restarted) {
    tracked = Output::restart(solver, cfg.restart);
  } else {
    solver.initialize();
  }
  Output out(solver, restarted);
  Diagnostics diag(solver);
  // particle identity for the shape diagnostics: seeded spheres, or the
  // particles the checkpoint tracked
  std::unique_ptr<ParticleTracker> tracker;
  if (solver.solid())
    tracker = std::make_unique<ParticleTracker>(
        solver,
        restarted ? tracked : ParticleTracker::from_spheres(solver.solid()->spheres(), cfg.particles));
  const std::vector<ParticleShape> no_particles;
  auto particles = [&]() -> const std::vector<ParticleShape>& {
    return tracker ? tracker->shapes() : no_particles;
  };
  SolidWatch watch;
  auto series_rows = [&](const FlowScalars& f, Real dt) {
    out.series_row(f, dt);
    if (root && solver.solid()) watch.row(f, solver.step, solver.time * cfg.shear_rate(), log);
    if (tracker) {
      tracker->update();
      out.particles_row(tracker->shapes());
    }
  };
  const OutputConfig& oc = cfg.output;
  const Real t_end = cfg.end_time_resolved();
  const Real gamma = cfg.shear_rate();
  // snapshots every fields_every strain units (or time units when gamma = 0)
  const Real snap_dt = oc.fields_every > 0 ? oc.fields_every / (gamma != 0 ? gamma : 1) : 0;
  Real next_snap = snap_dt > 0 ? (std::floor(solver.time / snap_dt + 1e-9) + 1) * snap_dt : 1e300;

  if (root) {
    const Grid& g = solver.grid();
    log << "softflow " << version() << ": case '" << cfg.case_name << "', grid " << g.nx << " x " << g.ny
        << " x " << g.nz << ", " << solver.decomposition().size << " rank(s) (" << cfg.parallel.px << " x "
        << cfg.parallel.pz << "), " << ExecSpace::name() << " with " << ExecSpace().concurrency()
        << " thread(s) per rank\n"
        << (restarted ? "restarted from " + cfg.restart + " at step " + std::to_string(solver.step)
                      : std::string("initial state: ") + cfg.initial.type)
        << ", end time " << t_end << " (strain " << t_end * gamma << ")\n";
    if (solver.solid() && cfg.particles.shape == "spheres") {
      // how phi is carried, and the colours' memory (three full-grid arrays each)
      const int n = solver.solid()->colours().size();
      log << "particles: " << sphere_count(cfg) << " sphere(s), "
          << (n > 0 ? std::to_string(n) + " colour field(s), " +
                          std::to_string(int(std::lround(24e-6 * double(g.sx()) * g.sy() * g.sz() * n))) +
                          " MB a rank"
                    : std::string("one phi field"))
          << "\n";
    }
  }
  if (!restarted) {
    series_rows(diag.scalars(), 0);
    if (oc.profiles_every) out.profile_sample(diag.profiles());
    out.snapshot();
  }

  RunResult res;
  using clock = std::chrono::steady_clock;
  Kokkos::fence("run_start");  // start-up's kernels (a restart's force) are not the run's
  const auto t0 = clock::now();
  auto last = t0;
  long last_step = solver.step;
  Real dt = 0;
  DtLimit lim = DtLimit::end_time;
  // the last good checkpoint, named when the run goes bad
  std::string last_checkpoint = restarted ? cfg.restart + " (step " + std::to_string(solver.step) + ")" : "";
  auto fail = [&](const std::string& what) {
    throw RunFailure(what + "; " +
                     (last_checkpoint.empty()
                          ? std::string("no checkpoint was written")
                          : "the last good checkpoint, " + last_checkpoint + ", is kept"));
  };
  // nothing is written from a state with a non-finite value in it
  auto check_finite = [&]() {
    if (const long bad = non_finite_values(solver)) {
      std::ostringstream m;
      m.precision(4);
      m << "the solution is no longer finite at step " << solver.step << " (strain " << solver.time * gamma
        << ", last dt " << dt << " from the " << to_string(lim) << " limit): " << bad << " non-finite values";
      fail(m.str());
    }
  };
  auto checkpoint = [&]() {
    check_finite();
    out.checkpoint(particles());
    last_checkpoint = oc.dir + "/checkpoint.h5 (step " + std::to_string(solver.step) + ")";
  };
  // wall-time checkpoints: rank 0's clock decides for all ranks
  const double checkpoint_seconds = oc.checkpoint_minutes * 60;
  auto last_checkpoint_time = t0;
  auto wall_checkpoint_due = [&]() {
    if (checkpoint_seconds <= 0) return false;
    int due =
        std::chrono::duration<double>(clock::now() - last_checkpoint_time).count() >= checkpoint_seconds;
    MPI_Bcast(&due, 1, MPI_INT, 0, solver.decomposition().comm);
    return due != 0;
  };
  StepGuard guard;
  while (solver.time < t_end * (1 - 1e-14) && (cfg.time.max_steps == 0 || res.steps < cfg.time.max_steps)) {
    dt = solver.stable_dt(&lim);
    if (solver.time + dt > t_end) {
      dt = t_end - solver.time;
      lim = DtLimit::end_time;
    }
    try {
      guard.check(solver.step + 1, solver.time * gamma, dt, lim);
    } catch (const RunFailure& e) {
      fail(e.what());
    }
    solver.advance(dt);
    ++res.steps;
    if (after_step) after_step(solver);
    FlowProfiles profiles;  // this step's, if its series row computed them
    bool have_profiles = false;
    if (!std::isfinite(solver.time) || (oc.series_every && solver.step % oc.series_every == 0)) {
      FlowScalars f = diag.scalars(&profiles);
      have_profiles = true;
      if (!std::isfinite(f.kinetic_energy)) check_finite();
      series_rows(f, dt);
    }
    if (solver.time >= next_snap * (1 - 1e-12)) {
      check_finite();
      out.snapshot();
      next_snap += snap_dt;
    }
    if (oc.profiles_every && solver.step % oc.profiles_every == 0)
      out.profile_sample(have_profiles ? profiles : diag.profiles());
    if (oc.checkpoint_every && solver.step % oc.checkpoint_every == 0) {
      checkpoint();
      last_checkpoint_time = clock::now();
    } else if (wall_checkpoint_due()) {
      checkpoint();
      last_checkpoint_time = clock::now();
      if (root)
        log << "checkpoint at step " << solver.step << " (every " << oc.checkpoint_minutes
            << " min of wall time)" << std::endl;
    }
    if (root && oc.progress_every && solver.step % oc.progress_every == 0) {
      Kokkos::fence("progress");
      const auto now = clock::now();
      const double per = std::chrono::duration<double>(now - last).count() / (solver.step - last_step);
      const double eta = per * (t_end - solver.time) / dt;
      log << "step " << std::setw(8) << solver.step << "  t " << std::setw(10) << std::setprecision(5)
          << solver.time << "  strain " << std::setw(8) << solver.time * gamma << "  dt "
          << std::setprecision(3) << dt << " (" << to_string(lim) << ")  " << std::setprecision(3)
          << per * 1e3 << " ms/step  ETA " << hms(eta) << std::endl;
      last = now;
      last_step = solver.step;
    }
  }
  Kokkos::fence("run_end");
  res.wall_seconds = std::chrono::duration<double>(clock::now() - t0).count();
  FlowScalars f = diag.scalars();
  // the end state as a last sample, unless the run only paused (max_steps):
  // its continuation must write the same rows as an uninterrupted run
  const bool finished = solver.time >= t_end * (1 - 1e-14);
  if (finished && res.steps > 0 && (!oc.series_every || solver.step % oc.series_every)) series_rows(f, dt);
  if (finished && res.steps > 0 && oc.profiles_every && solver.step % oc.profiles_every)
    out.profile_sample(diag.profiles());
  check_finite();
  out.snapshot();
  checkpoint();
  nlohmann::json measured;
  const auto series =
      root ? read_columns(oc.dir + "/series.csv") : std::map<std::string, std::vector<double>>{};
  measured["averages"] = run_averages(solver, out, series);
  if (root && solver.solid()) measured["solid_checks"] = solid_checks(series);
  write_summary(solver, f, res, oc.dir, measured, particles().size());
  if (root) {
    const std::string halves = halves_line(measured["averages"]);
    if (!halves.empty()) log << halves << "\n";
    const std::string trend = trend_line(measured["averages"]);
    if (!trend.empty()) log << trend << "\n";
    log << "done: " << res.steps << " steps in " << std::setprecision(4) << res.wall_seconds
        << " s, t = " << solver.time << ", mu_eff = " << std::setprecision(10) << f.mu_eff << ", output in "
        << oc.dir << "/\n";
  }
  return res;
}

}  // namespace softflow
