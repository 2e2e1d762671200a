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

namespace {
// the span: the finite samples from strain `from` on, with their strains
struct Span {
  std::vector<double> strain, x;
};
Span span_from(const std::vector<double>& strain, const std::vector<double>& x, double from) {
  Span s;
  for (size_t k = 0; k < x.size() && k < strain.size(); ++k)
    if (strain[k] >= from - 1e-12 && std::isfinite(x[k])) {
      s.strain.push_back(strain[k]);
      s.x.push_back(x[k]);
    }
  return s;
}
}  // namespace

Halves compare_halves(const std::vector<double>& strain, const std::vector<double>& x, double from) {
  Halves h;
  const Span span = span_from(strain, x, from);
  double last = from;
  for (double t : span.strain) last = std::max(last, t);
  h.split = 0.5 * (from + last);
  std::vector<double> a, b;
  for (size_t k = 0; k < span.x.size(); ++k) (span.strain[k] < h.split ? a : b).push_back(span.x[k]);
  h.first.samples = long(a.size()), h.second.samples = long(b.size());
  if (a.size() < 20 || b.size() < 20) {
    h.first.mean = h.second.mean = h.first.stderr_ = h.second.stderr_ = h.tolerance = NAN;
    return h;
  }
  const double tau = integrated_time(span.x);
  h.first = mean_with_tau(a, tau);
  h.second = mean_with_tau(b, tau);
  h.tolerance = std::max(2 * std::hypot(h.first.stderr_, h.second.stderr_), 0.01 * std::abs(h.second.mean));
  h.judged = true;
  h.agree = std::abs(h.second.mean - h.first.mean) <= h.tolerance;
  return h;
}

Trend fit_trend(const std::vector<double>& strain, const std::vector<double>& x, double from) {
  constexpr int batches = 10;
  Trend t;
  const Span span = span_from(strain, x, from);
  const size_t n = span.x.size();
  t.samples = long(n);
  t.slope = t.slope_stderr = t.mean = t.change = t.change_stderr = NAN;
  if (n == 0) return t;
  double sum = 0;
  for (double e : span.x) sum += e;
  t.mean = sum / double(n);
  if (n < 20 || t.mean == 0) return t;
  const size_t len = n / batches, skip = n - len * batches;
  double bx[batches], by[batches], mx = 0, my = 0;
  for (int b = 0; b < batches; ++b) {
    bx[b] = by[b] = 0;
    for (size_t k = skip + b * len; k < skip + (b + 1) * len; ++k)
      bx[b] += span.strain[k], by[b] += span.x[k];
    bx[b] /= double(len), by[b] /= double(len);
    mx += bx[b] / batches, my += by[b] / batches;
  }
  double sxx = 0, sxy = 0;
  for (int b = 0; b < batches; ++b) sxx += (bx[b] - mx) * (bx[b] - mx), sxy += (bx[b] - mx) * (by[b] - my);
  if (sxx == 0) return t;
  t.slope = sxy / sxx;
  double res = 0;
  for (int b = 0; b < batches; ++b) res += std::pow(by[b] - my - t.slope * (bx[b] - mx), 2);
  t.slope_stderr = std::sqrt(res / (batches - 2) / sxx);
  const double length = span.strain.back() - span.strain.front();
  t.change = t.slope * length / std::abs(t.mean);
  t.change_stderr = t.slope_stderr * length / std::abs(t.mean);
  t.judged = true;
  t.drifts = std::abs(t.change) > 2 * t.change_stderr && std::abs(t.change) > 0.01;
  return t;
}

}  // namespace softflow
