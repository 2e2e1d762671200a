// The driver: one case from start (or checkpoint) to its end time, with
// progress lines, the time series, snapshots, checkpoints and the summary.
#pragma once
#include <mpi.h>

#include <functional>
#include <iosfwd>

#include "config.hpp"

namespace softflow {

class FlowSolver;

struct RunResult {
  long steps = 0;  // steps taken by this invocation
  double wall_seconds = 0;
};

// Called after every step, before any check or output of it (tests use it
// to make a run go bad).
using AfterStep = std::function<void(FlowSolver&)>;

// cfg must be checked (load_config, resolve_rank_grid, check_output_dir).
// Progress goes to `log` on rank 0. A run that goes bad (its time step
// collapses, or its fields stop being finite) throws RunFailure
// (src/run_guard.hpp) on every rank, having written nothing of the bad state.
RunResult run_case(const Config& cfg, MPI_Comm comm, std::ostream& log, const AfterStep& after_step = {});

}  // namespace softflow
