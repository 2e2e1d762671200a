// The end-of-run averages: read back the run's series (rank 0), find where
// the averages start (src/averaging.hpp), and give the summary's "averages"
// object: every quantity with its mean, batch-means standard error and sample
// count; the averaged profiles go to profiles.csv. Reading the files rather
// than accumulating in memory makes a restarted run average over its whole
// history.
#pragma once
#include <nlohmann/json.hpp>

#include "output.hpp"

namespace softflow {

nlohmann::json run_averages(const FlowSolver& s, Output& out);

}  // namespace softflow
