// The driver: one case from start (or checkpoint) to its end time, with
// progress lines, the time series, snapshots, checkpoints and the summary.
#pragma once
#include <mpi.h>

#include <iosfwd>

#include "config.hpp"

namespace softflow {

struct RunResult {
  long steps = 0;  // steps taken by this invocation
  double wall_seconds = 0;
};

// cfg must be checked (load_config, resolve_rank_grid, check_output_dir).
// Progress goes to `log` on rank 0.
RunResult run_case(const Config& cfg, MPI_Comm comm, std::ostream& log);

}  // namespace softflow
