// The end-of-run averages: from the run's series read back (rank 0), find where
// the averages start (src/averaging.hpp), and give the summary's "averages"
// object: every quantity with its mean, batch-means standard error and sample
// count; the averaged profiles go to profiles.csv. Reading the files rather
// than accumulating in memory makes a restarted run average over its whole
// history.
#pragma once
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "output.hpp"

namespace softflow {

// series: series.csv's columns, read once by the caller (rank 0)
nlohmann::json run_averages(const FlowSolver& s, Output& out,
                            const std::map<std::string, std::vector<double>>& series);

// one log line from run_averages' "halves": each half's mean, the tolerance
// and whether they agree; empty without them
std::string halves_line(const nlohmann::json& averages);

// one log line from run_averages' "trend": each quantity's change across the
// span, its standard error and whether it drifts; empty without it
std::string trend_line(const nlohmann::json& averages);

}  // namespace softflow
