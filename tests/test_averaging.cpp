// Time averages (src/averaging.hpp): the transient detection and the
// batch-means uncertainty on synthetic series with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "averaging.hpp"

using namespace softflow;

namespace {
// AR(1): x_k = m + rho (x_{k-1} - m) + e_k, e ~ N(0, s^2); the variance of the
// mean of n samples tends to s^2 / (1 - rho)^2 / n
std::vector<double> ar1(size_t n, double m, double rho, double s, unsigned seed) {
  std::mt19937 g(seed);
  std::normal_distribution<double> e(0, s);
  std::vector<double> x(n);
  double v = m;
  for (auto& xi : x) xi = v = m + rho * (v - m) + e(g);
  return x;
}
}  // namespace

TEST(Averaging, MserStartsAfterAnExponentialTransient) {
  // 1 + 5 exp(-k / 50) plus noise of 0.02: the transient is below the noise after ~280 samples
  auto x = ar1(3000, 1.0, 0.5, 0.02, 7);
  for (size_t k = 0; k < x.size(); ++k) x[k] += 5 * std::exp(-double(k) / 50);
  const size_t d = mser_start(x);
  EXPECT_GT(d, 150u);
  EXPECT_LT(d, 600u);
  // a stationary series keeps (nearly) everything
  EXPECT_LT(mser_start(ar1(3000, 1.0, 0.5, 0.02, 8)), 300u);
}

TEST(Averaging, BatchMeansMatchTheTrueStandardErrorOfCorrelatedData) {
  // over 200 independent AR(1) series (rho = 0.9, correlation time ~19
  // samples) the batch-means error estimates scatter around the true
  // standard error; the naive iid estimate would be 4.4x too small
  const size_t n = 4000;
  const double rho = 0.9, s = 1, truth = s / (1 - rho) / std::sqrt(double(n));
  double mean_est = 0, sq_err = 0;
  const int reps = 200;
  for (int r = 0; r < reps; ++r) {
    const auto x = ar1(n, 3.0, rho, s, 100 + r);
    const Average a = batch_mean(x, 0);
    EXPECT_EQ(a.samples, long(n));
    mean_est += a.stderr_ / reps;
    sq_err += (a.mean - 3.0) * (a.mean - 3.0) / reps;
  }
  // 10 batches: the estimate's own relative scatter is ~1/sqrt(18), so its
  // mean over 200 series lies within a few percent; allow 15% for the finite
  // batch length (batches of 400 samples against a correlation time of 19)
  EXPECT_NEAR(mean_est / truth, 1.0, 0.15);
  // and the actual scatter of the means agrees with the truth (200 samples: ~10%)
  EXPECT_NEAR(std::sqrt(sq_err) / truth, 1.0, 0.25);
}

TEST(Averaging, ShortSeriesGetNoUncertaintyAndNaNsAreSkipped) {
  std::vector<double> x = {1, 2, NAN, 3};
  const Average a = batch_mean(x, 0);
  EXPECT_EQ(a.samples, 3);
  EXPECT_DOUBLE_EQ(a.mean, 2.0);
  EXPECT_TRUE(std::isnan(a.stderr_));
  EXPECT_EQ(mser_start(x), 0u);
}
