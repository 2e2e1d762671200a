// Time averages with statistical uncertainties.
//
// Transient: the Marginal Standard Error Rule (MSER, White 1997) picks the
// truncation d that minimises the squared standard error of the mean of the
// remaining samples, var(x[d:]) / (n - d), searched over d <= n / 2; it is
// applied to the effective viscosity and, with particles, to the mean Taylor
// parameter, and the later of the two starts every average. A case can set
// the start instead (output.average_from_strain).
//
// Uncertainty: non-overlapping batch means, 10 batches of equal length:
// stderr = std(batch means) / sqrt(10). Batches longer than the correlation
// time make the batch means independent; with fewer than 20 samples no
// uncertainty is given (NaN).
#pragma once
#include <cstddef>
#include <vector>

namespace softflow {

struct Average {
  double mean = 0;
  double stderr_ = 0;  // standard error of the mean (NaN if not estimable)
  long samples = 0;
};

// index of the first sample kept by MSER (0 for a series too short to judge)
size_t mser_start(const std::vector<double>& x);

// mean and batch-means standard error of x[start:], NaN entries skipped
Average batch_mean(const std::vector<double>& x, size_t start, int batches = 10);

}  // namespace softflow
