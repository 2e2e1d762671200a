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
//
// Stationarity: the averaging span in two halves by strain, tested as issue
// 12 tests a run (means within 2 standard errors of their difference or 1%
// of the later one, whichever is larger), with each half's error from the
// whole span's integrated autocorrelation time, as scripts/stationarity.py
// check does by default. So every average in summary.json says whether the
// span it covers is stationary by that test.
//
// Trend: a slow drift lengthens the span's correlation time and so widens the
// halves' tolerance with it (a 3% rise under 0.5% noise passes the halves
// about half the time). The trend does not: a least-squares line through the
// span's 10 batch means, its slope's error from their scatter about the line,
// as scripts/stationarity.py's trend table computes it.
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

// integrated autocorrelation time of x in samples, tau = 1 + 2 sum_k rho_k
// with Sokal's automatic window (the first lag M >= 5 tau(M)); at least 1
double integrated_time(const std::vector<double>& x);

// the two halves of the span of x (sampled at `strain`) from strain `from` on
struct Halves {
  double split = 0;       // the strain between them: (from + last) / 2
  Average first, second;  // stderr: sqrt(var tau / n), tau from the whole span
  double tolerance = 0;   // max(2 sqrt(se1^2 + se2^2), 0.01 |second|)
  bool judged = false;    // each half has 20 samples or more
  bool agree = false;     // judged and |second - first| <= tolerance
};
Halves compare_halves(const std::vector<double>& strain, const std::vector<double>& x, double from);

// the linear trend of x against strain over the span from strain `from` on:
// the line through the 10 batch means of strain and of x (equal runs of
// samples, the leftover first ones dropped, as batch_mean's), the slope's
// standard error from their scatter about it (8 degrees of freedom)
struct Trend {
  double slope = 0, slope_stderr = 0;    // per strain unit
  double mean = 0;                       // of the span's samples
  double change = 0, change_stderr = 0;  // slope (last - first strain) / |mean|: across the span
  long samples = 0;
  bool judged = false;  // 20 samples or more, a mean that is not 0
  // judged, |change| beyond 2 standard errors and above 1% (the halves' floor:
  // a real but smaller drift is below what the test resolves)
  bool drifts = false;
};
Trend fit_trend(const std::vector<double>& strain, const std::vector<double>& x, double from);

}  // namespace softflow
