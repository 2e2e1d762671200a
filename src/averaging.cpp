#include "averaging.hpp"

#include <cmath>

namespace softflow {

size_t mser_start(const std::vector<double>& x) {
  const size_t n = x.size();
  if (n < 10) return 0;
  // suffix sums: mean and variance of x[d:] for every d in one sweep
  double s = 0, s2 = 0;
  std::vector<double> score(n, INFINITY);
  for (size_t k = n; k-- > 0;) {
    s += x[k], s2 += x[k] * x[k];
    const double m = double(n - k);
    const double var = std::max(0.0, s2 / m - (s / m) * (s / m));
    score[k] = var / m;
  }
  size_t best = 0;
  for (size_t d = 0; d <= n / 2; ++d)
    if (score[d] < score[best]) best = d;
  return best;
}

Average batch_mean(const std::vector<double>& x, size_t start, int batches) {
  std::vector<double> v;
  for (size_t k = start; k < x.size(); ++k)
    if (std::isfinite(x[k])) v.push_back(x[k]);
  Average a;
  a.samples = long(v.size());
  if (v.empty()) {
    a.mean = a.stderr_ = NAN;
    return a;
  }
  double sum = 0;
  for (double e : v) sum += e;
  a.mean = sum / double(v.size());
  if (v.size() < 20) {
    a.stderr_ = NAN;
    return a;
  }
  // batches of equal length, the few leftover samples at the start dropped
  const size_t len = v.size() / batches, skip = v.size() - len * batches;
  double bs = 0, bs2 = 0;
  for (int b = 0; b < batches; ++b) {
    double m = 0;
    for (size_t k = 0; k < len; ++k) m += v[skip + b * len + k];
    m /= double(len);
    bs += m, bs2 += m * m;
  }
  const double bm = bs / batches;
  const double var = std::max(0.0, (bs2 - batches * bm * bm) / (batches - 1));
  a.stderr_ = std::sqrt(var / batches);
  return a;
}

}  // namespace softflow
