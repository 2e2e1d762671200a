#include "averaging.hpp"

#include <algorithm>
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

double integrated_time(const std::vector<double>& x) {
  const size_t n = x.size();
  if (n < 2) return 1;
  double m = 0;
  for (double e : x) m += e;
  m /= double(n);
  double c0 = 0;
  for (double e : x) c0 += (e - m) * (e - m);
  c0 /= double(n);
  if (c0 == 0) return 1;
  double tau = 1;
  for (size_t k = 1; k < n; ++k) {
    double ck = 0;
    for (size_t i = 0; i + k < n; ++i) ck += (x[i] - m) * (x[i + k] - m);
    tau += 2 * ck / double(n) / c0;
    if (double(k) >= 5 * tau) break;
  }
  return std::max(tau, 1.0);
}

namespace {
// mean and sqrt(var tau / n) (var with n - 1)
Average mean_with_tau(const std::vector<double>& v, double tau) {
  Average a;
  a.samples = long(v.size());
  double s = 0;
  for (double e : v) s += e;
  a.mean = s / double(v.size());
  double q = 0;
  for (double e : v) q += (e - a.mean) * (e - a.mean);
  a.stderr_ = std::sqrt(q / double(v.size() - 1) * tau / double(v.size()));
  return a;
}
}  // namespace

Halves compare_halves(const std::vector<double>& strain, const std::vector<double>& x, double from) {
  Halves h;
  std::vector<size_t> kept;  // the span's samples: from `from` on, finite
  double last = from;
  for (size_t k = 0; k < x.size() && k < strain.size(); ++k)
    if (strain[k] >= from - 1e-12 && std::isfinite(x[k])) {
      kept.push_back(k);
      last = std::max(last, strain[k]);
    }
  h.split = 0.5 * (from + last);
  std::vector<double> span, a, b;
  for (size_t k : kept) {
    span.push_back(x[k]);
    (strain[k] < h.split ? a : b).push_back(x[k]);
  }
  h.first.samples = long(a.size()), h.second.samples = long(b.size());
  if (a.size() < 20 || b.size() < 20) {
    h.first.mean = h.second.mean = h.first.stderr_ = h.second.stderr_ = h.tolerance = NAN;
    return h;
  }
  const double tau = integrated_time(span);
  h.first = mean_with_tau(a, tau);
  h.second = mean_with_tau(b, tau);
  h.tolerance = std::max(2 * std::hypot(h.first.stderr_, h.second.stderr_), 0.01 * std::abs(h.second.mean));
  h.judged = true;
  h.agree = std::abs(h.second.mean - h.first.mean) <= h.tolerance;
  return h;
}

}  // namespace softflow
