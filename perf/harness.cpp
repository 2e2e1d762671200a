// softflow-perf: the performance harness. For one case (single-phase, one
// particle, a dense suspension: any case file with --set overrides) it
//   1. measures the memory bandwidth (STREAM copy/triad as Kokkos kernels);
//   2. runs warm-up steps;
//   3. times the whole step (stable_dt + advance) over repetitions, fenced,
//      with no tool attached: cell-steps per second;
//   4. times every labelled kernel and region (perf/kernel_timer.hpp) over
//      repetitions, with a bandwidth measurement before each repetition so
//      every kernel also gets a machine-normalised time from the same moment;
//   5. writes JSON (min/median/max over repetitions; machine, backend, build
//      type, grid, ranks, commit) for perf/compare.py and perf/report.py.
// Times are the slowest rank's (MPI_MAX per repetition).
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config.hpp"
#include "flow_solver.hpp"
#include "kernel_timer.hpp"
#include "kernel_traffic.hpp"
#include "stream.hpp"
#include "version.hpp"

#ifndef SOFTFLOW_BUILD_TYPE
#define SOFTFLOW_BUILD_TYPE "unknown"
#endif

namespace {

using namespace softflow;
using namespace softflow::perf;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

const char* usage =
    "usage: softflow-perf CASE.toml [--set table.key=value]... [options]\n"
    "  --warmup N         untimed steps first (default 3)\n"
    "  --steps N          steps per repetition (default 5)\n"
    "  --reps N           repetitions (default 5)\n"
    "  --stream-mb M      MiB per STREAM array (default 256; use >= 4x the last-level cache)\n"
    "  --machine-class S  name of the machine class for the baselines (default: backend-Ncores)\n"
    "  --json FILE        write the results there (default: print to stdout)\n";

struct Options {
  std::string case_file, json_file, machine_class;
  std::vector<std::string> overrides;
  int warmup = 3, steps = 5, reps = 5;
  double stream_mb = 256;
};

struct MinMedMax {
  double min = 0, median = 0, max = 0;
};

MinMedMax stats(std::vector<double> v) {
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  const double med = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  return {v.front(), med, v.back()};
}

json to_json(const MinMedMax& s) { return {{"min", s.min}, {"median", s.median}, {"max", s.max}}; }

double max_over_ranks(double x, MPI_Comm comm) {
  MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE, MPI_MAX, comm);
  return x;
}
double sum_over_ranks(double x, MPI_Comm comm) {
  MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE, MPI_SUM, comm);
  return x;
}

// the steps a run takes: the stable time step, then the RK3 step
void take_steps(FlowSolver& s, int n) {
  for (int i = 0; i < n; ++i) s.advance(s.stable_dt());
}

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

std::string host_name() {
  char buf[256] = {};
  gethostname(buf, sizeof buf - 1);
  return buf;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int a = 1; a < argc; ++a) {
    const std::string s = argv[a];
    auto value = [&]() -> std::string {
      if (a + 1 >= argc) throw InputError("option " + s + " needs a value");
      return argv[++a];
    };
    if (s == "-h" || s == "--help") {
      std::cout << usage;
      std::exit(0);
    } else if (s == "--set") {
      o.overrides.push_back(value());
    } else if (s == "--warmup") {
      o.warmup = std::stoi(value());
    } else if (s == "--steps") {
      o.steps = std::stoi(value());
    } else if (s == "--reps") {
      o.reps = std::stoi(value());
    } else if (s == "--stream-mb") {
      o.stream_mb = std::stod(value());
    } else if (s == "--machine-class") {
      o.machine_class = value();
    } else if (s == "--json") {
      o.json_file = value();
    } else if (s.rfind("-", 0) == 0) {
      throw InputError("unknown option '" + s + "'\n" + usage);
    } else if (o.case_file.empty()) {
      o.case_file = s;
    } else {
      throw InputError("more than one case file given");
    }
  }
  if (o.case_file.empty()) throw InputError(std::string("no case file given\n") + usage);
  if (o.steps < 1 || o.reps < 1 || o.warmup < 0)
    throw InputError("--steps and --reps must be >= 1, --warmup >= 0");
  return o;
}

// Per-repetition kernel (or region) seconds per step, the slowest rank's.
using Samples = std::map<std::string, std::vector<double>>;

void add_samples(Samples& out, const std::map<std::string, TimedEntry>& in, int steps, MPI_Comm comm) {
  // every rank runs the same kernels (same code path), so the maps' keys agree
  for (const auto& [label, e] : in) out[label].push_back(max_over_ranks(e.seconds / steps, comm));
}

json run(const Options& o, MPI_Comm comm) {
  int nranks = 1;
  MPI_Comm_size(comm, &nranks);
  Config cfg = load_config(o.case_file, o.overrides);
  resolve_rank_grid(cfg, nranks);
  FlowSolver solver(cfg, comm);
  solver.initialize();
  const Grid& g = solver.grid();
  const double cells = double(g.nxl) * g.ny * g.nzl;  // this rank's
  const double cells_global = double(g.cells_global());

  StreamBench stream(size_t(o.stream_mb * 1024 * 1024));
  stream.measure(2);  // first touch
  take_steps(solver, o.warmup);

  // Each repetition: the bandwidth (all ranks streaming at once: they share
  // the memory), the whole step with no tool attached, then the kernels and
  // regions with the timer attached. Interleaving them puts the three
  // measurements of a repetition close in time on a machine whose speed drifts.
  std::vector<double> step_s, step_norm;
  Samples kernel_s, region_s;
  std::map<std::string, double> calls_per_step;
  std::vector<double> copy_bw, triad_bw, unit_s;
  long copies = 0;
  double copy_bytes = 0, halo_bytes = 0, transpose_bytes = 0;
  for (int r = 0; r < o.reps; ++r) {
    MPI_Barrier(comm);
    const Bandwidth bw = stream.measure(5);
    copy_bw.push_back(bw.copy);
    triad_bw.push_back(bw.triad);
    // time to stream one Real per cell at this repetition's triad bandwidth:
    // the unit of the machine-normalised times
    unit_s.push_back(max_over_ranks(cells * sizeof(Real) / bw.triad, comm));

    Kokkos::fence("perf_step_before");
    MPI_Barrier(comm);
    const auto t0 = Clock::now();
    take_steps(solver, o.steps);
    Kokkos::fence("perf_step_after");
    step_s.push_back(
        max_over_ranks(std::chrono::duration<double>(Clock::now() - t0).count() / o.steps, comm));
    step_norm.push_back(step_s.back() / unit_s.back());

    const size_t h0 = solver.halo().bytes_sent(), tr0 = solver.poisson().transposer().bytes_sent();
    MPI_Barrier(comm);
    TimerReport rep;
    {
      KernelTimer timer;
      take_steps(solver, o.steps);
      rep = timer.report();
    }
    add_samples(kernel_s, rep.kernels, o.steps, comm);
    for (const auto& [label, e] : rep.kernels) calls_per_step[label] = double(e.calls) / o.steps;
    add_samples(region_s, rep.regions, o.steps, comm);
    copies += rep.cross_space_copies;
    copy_bytes += double(rep.cross_space_bytes);
    halo_bytes += double(solver.halo().bytes_sent() - h0);
    transpose_bytes += double(solver.poisson().transposer().bytes_sent() - tr0);
  }
  const double steps_total = double(o.reps) * o.steps;
  // the solid's region at the end (it changes little over a few steps)
  const SolidPhase* solid = solver.solid();
  const double solid_share = solid ? double(solid->region().size()) / cells : 0.0;
  const double force_share = solid ? double(solid->force_region().size()) / cells : 0.0;
  const MinMedMax step = stats(step_s);

  json j;
  j["harness_version"] = 1;
  j["commit"] = version();
  j["build_type"] = SOFTFLOW_BUILD_TYPE;
  j["backend"] = ExecSpace::name();
  j["kokkos_version"] = std::to_string(KOKKOS_VERSION);
  j["concurrency"] = ExecSpace().concurrency();
  j["machine"] = {{"host", host_name()}, {"cpu", cpu_model()}};
  j["machine_class"] = o.machine_class.empty()
                           ? std::string(ExecSpace::name()) + "-" + std::to_string(ExecSpace().concurrency())
                           : o.machine_class;
  j["case"] = cfg.case_name;
  j["overrides"] = o.overrides;
  j["physics"] = {{"particles", cfg.particles.enabled},
                  {"volume_fraction", cfg.particles.enabled ? cfg.particles.volume_fraction : 0.0},
                  {"viscous", cfg.time.viscous}};
  j["grid"] = {g.nx, g.ny, g.nz};
  j["solid_region_share_of_box"] = solid_share;
  if (solid) {
    const Range3 r = solid->region();
    j["solid_region"] = {r.ib, r.ie, r.jb, r.je, r.kb, r.ke};  // storage indices, rank 0
  }
  j["ranks"] = nranks;
  j["rank_grid"] = {solver.decomposition().px, solver.decomposition().pz};
  j["warmup"] = o.warmup;
  j["steps"] = o.steps;
  j["reps"] = o.reps;
  j["stream"] = {{"mib_per_array", o.stream_mb},
                 {"copy_bytes_per_second_per_rank", to_json(stats(copy_bw))},
                 {"triad_bytes_per_second_per_rank", to_json(stats(triad_bw))},
                 {"triad_bytes_per_second_all_ranks", sum_over_ranks(stats(triad_bw).median, comm)}};
  j["step"] = {{"seconds", to_json(step)},
               {"cell_steps_per_second",
                {{"min", cells_global / step.max},
                 {"median", cells_global / step.median},
                 {"max", cells_global / step.min}}},
               // the step time in units of streaming one Real per cell, per
               // repetition (the gate compares the minimum: the least disturbed)
               {"normalized", to_json(stats(step_norm))}};
  const double triad = stats(triad_bw).median;
  double kernels_sum = 0;
  json kj = json::object();
  for (const auto& [label, v] : kernel_s) {
    const MinMedMax s = stats(v);
    kernels_sum += s.median;
    std::vector<double> norm(v.size());
    for (size_t r = 0; r < v.size(); ++r) norm[r] = v[r] / unit_s[r];
    json e = {{"seconds_per_step", to_json(s)},
              {"share_of_step", s.median / step.median},
              {"cell_updates_per_second", s.median > 0 ? cells * calls_per_step[label] / s.median : 0.0},
              {"normalized", to_json(stats(norm))}};
    const double calls = calls_per_step[label];
    e["calls_per_step"] = calls;
    if (auto t = kernel_traffic(label)) {
      // the table counts one call over its domain; per interior cell that is
      // scaled by the domain's share; bandwidth against this rank's triad
      const double share = t->domain == Domain::box     ? 1.0
                           : t->domain == Domain::solid ? solid_share
                                                        : force_share;
      const double bytes = (t->reads + t->writes) * sizeof(Real) * calls * share;
      e["traffic"] = {{"reals_read_per_call", t->reads},
                      {"reals_written_per_call", t->writes},
                      {"arrays", t->what},
                      {"bytes_per_cell_per_step", bytes}};
      e["bandwidth_bytes_per_second"] = bytes * cells / s.median;
      e["bandwidth_fraction_of_triad"] = bytes * cells / s.median / triad;
    }
    kj[label] = e;
  }
  j["kernels"] = kj;
  j["kernels_sum_share_of_step"] = kernels_sum / step.median;
  json rj = json::object();
  for (const auto& [label, v] : region_s) {
    const MinMedMax s = stats(v);
    rj[label] = {{"seconds_per_step", to_json(s)}, {"share_of_step", s.median / step.median}};
  }
  j["regions"] = rj;
  j["communication"] = {
      {"halo_bytes_per_step_rank0", halo_bytes / steps_total},
      {"transpose_bytes_per_step_rank0", transpose_bytes / steps_total},
      {"halo_bytes_per_step_all_ranks", sum_over_ranks(halo_bytes, comm) / steps_total},
      {"transpose_bytes_per_step_all_ranks", sum_over_ranks(transpose_bytes, comm) / steps_total}};
  j["cross_space_copies_per_step"] = copies / steps_total;
  j["cross_space_bytes_per_step"] = copy_bytes / steps_total;
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  Kokkos::initialize(argc, argv);
  int rc = 0;
  try {
    const Options o = parse(argc, argv);
    const json j = run(o, MPI_COMM_WORLD);
    if (rank == 0) {
      if (o.json_file.empty()) {
        std::cout << j.dump(2) << "\n";
      } else {
        {
          std::ofstream f(o.json_file + ".tmp");
          f << j.dump(2) << "\n";
          if (!f) throw std::runtime_error("cannot write " + o.json_file);
        }
        std::rename((o.json_file + ".tmp").c_str(), o.json_file.c_str());
        std::cout << "softflow-perf: wrote " << o.json_file << "\n";
      }
    }
  } catch (const InputError& e) {
    if (rank == 0) std::cerr << "softflow-perf: error: " << e.what() << std::endl;
    rc = 2;
  }
  Kokkos::finalize();
  MPI_Finalize();
  return rc;
}
