#include "run_averages.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "averaging.hpp"

namespace softflow {

namespace {

using Columns = std::map<std::string, std::vector<double>>;

nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json to_json(const Average& a) {
  return {{"mean", num(a.mean)}, {"stderr", num(a.stderr_)}, {"samples", a.samples}};
}

nlohmann::json to_json(const Halves& h, const std::string& quantity) {
  return {{"quantity", quantity},
          {"first", to_json(h.first)},
          {"second", to_json(h.second)},
          {"tolerance", num(h.tolerance)},
          {"agree", h.judged ? nlohmann::json(h.agree) : nlohmann::json(nullptr)}};
}

nlohmann::json to_json(const Trend& t, const std::string& quantity) {
  return {
      {"quantity", quantity},    {"mean", num(t.mean)},
      {"slope", num(t.slope)},   {"slope_stderr", num(t.slope_stderr)},
      {"change", num(t.change)}, {"change_stderr", num(t.change_stderr)},
      {"samples", t.samples},    {"drifts", t.judged ? nlohmann::json(t.drifts) : nlohmann::json(nullptr)}};
}

std::string num_str(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream o;
  o << std::setprecision(10) << v;
  return o.str();
}

// first index whose strain reaches `from`
size_t first_at(const std::vector<double>& strain, double from) {
  size_t k = 0;
  while (k < strain.size() && strain[k] < from - 1e-12) ++k;
  return k;
}

// samples after the initial row (step 0: the initial state, not a sample of the flow)
std::vector<double> drop_initial(const Columns& c, const std::string& name) {
  const auto& v = c.at(name);
  const auto& step = c.at("step");
  std::vector<double> out;
  for (size_t k = 0; k < v.size(); ++k)
    if (step[k] > 0) out.push_back(v[k]);
  return out;
}

}  // namespace

nlohmann::json run_averages(const FlowSolver& s, Output& out, const Columns& series) {
  nlohmann::json j;
  if (!s.decomposition().is_root()) return j;
  const Config& c = s.config();
  const std::string dir = out.dir();
  if (!series.count("strain") || series.at("strain").size() < 2) return j;
  const Columns parts = s.solid() ? read_columns(dir + "/particles.csv") : Columns{};
  const bool has_parts = parts.count("taylor_mean") && parts.at("taylor_mean").size() > 1;

  const auto strain = drop_initial(series, "strain");
  double from = c.output.average_from_strain;
  std::string how = "set by output.average_from_strain";
  if (from < 0) {
    // MSER on mu_eff and, with particles, on the mean Taylor parameter: the later start
    const auto mu = drop_initial(series, "mu_eff");
    from = strain[mser_start(mu)];
    if (has_parts) {
      const auto ps = drop_initial(parts, "strain");
      from = std::max(from, ps[mser_start(drop_initial(parts, "taylor_mean"))]);
    }
    how = "detected: MSER (White 1997) on mu_eff" + std::string(has_parts ? " and taylor_mean" : "");
  }
  j["from_strain"] = from;
  j["to_strain"] = strain.back();
  j["start"] = how;
  j["uncertainty"] = "standard error of the mean from 10 non-overlapping batch means";

  const double gamma = c.shear_rate(), unit = gamma != 0 ? c.fluid.mu * gamma : 1.0;
  const size_t k0 = first_at(strain, from);
  auto avg = [&](const std::vector<double>& v) { return to_json(batch_mean(v, k0)); };
  nlohmann::json q;
  q["mu_eff"] = avg(drop_initial(series, "mu_eff"));
  std::vector<double> mb = drop_initial(series, "tau_bottom"), mt = drop_initial(series, "tau_top");
  for (auto& v : mb) v /= unit;
  for (auto& v : mt) v /= unit;
  q["mu_bottom"] = avg(mb);
  q["mu_top"] = avg(mt);
  q["n1"] = avg(drop_initial(series, "n1"));
  q["n2"] = avg(drop_initial(series, "n2"));
  q["kinetic_energy"] = avg(drop_initial(series, "kinetic_energy"));
  // the budget: gap averages and each term's share of their sum, sample by sample
  std::vector<std::vector<double>> terms;
  for (int b = 0; b < n_budget; ++b) terms.push_back(drop_initial(series, budget_name(b)));
  nlohmann::json budget, shares;
  for (int b = 0; b < n_budget; ++b) {
    std::vector<double> share(terms[b].size());
    for (size_t k = 0; k < share.size(); ++k) {
      double total = 0;
      for (int e = 0; e < n_budget; ++e) total += terms[e][k];
      share[k] = total != 0 ? terms[b][k] / total : NAN;
    }
    budget[budget_name(b)] = avg(terms[b]);
    shares[budget_name(b)] = avg(share);
  }
  q["budget"] = budget;
  q["budget_share"] = shares;
  if (s.solid()) {
    const double vbox = c.grid.lx * c.grid.ly * c.grid.lz;
    std::vector<double> phi = drop_initial(series, "solid_volume");
    for (auto& v : phi) v /= vbox;
    const Average pa = batch_mean(phi, k0);
    q["Phi"] = to_json(pa);
    q["detb_min"] = avg(drop_initial(series, "detb_min"));
    q["detb_max"] = avg(drop_initial(series, "detb_max"));
    // intrinsic viscosity [mu] = (mu - mu_f) / (mu_f Phi), meaningful for dilute cases
    Average mu = batch_mean(drop_initial(series, "mu_eff"), k0), im = mu;
    im.mean = (mu.mean - 1) / pa.mean, im.stderr_ = mu.stderr_ / pa.mean;
    q["intrinsic_viscosity"] = to_json(im);
  }
  if (has_parts) {
    const auto ps = drop_initial(parts, "strain");
    const size_t p0 = first_at(ps, from);
    auto pav = [&](const char* name) { return to_json(batch_mean(drop_initial(parts, name), p0)); };
    q["taylor"] = pav("taylor_mean");
    q["taylor_spread"] = pav("taylor_std");  // standard deviation over the particles
    q["phi_e"] = pav("phi_e");
    q["a_xy"] = pav("a_xy_mean");
    q["b_xy"] = pav("b_xy_mean");
    q["angle_deg"] = pav("angle_mean_deg");
  }
  j["quantities"] = q;

  // the span's two halves, as issue 12 tests a run's windows, and its linear
  // trend: mu ([mu] for a dilute run, whose 1% is the particles' own) and the
  // mean Taylor parameter
  nlohmann::json halves, trend;
  std::vector<double> mu = drop_initial(series, "mu_eff");
  std::string mu_name = "mu_eff";
  if (s.solid() && q["Phi"]["mean"].is_number() && q["Phi"]["mean"].get<double>() < 0.01) {
    const double phi = q["Phi"]["mean"].get<double>();
    for (auto& v : mu) v = (v - 1) / phi;
    mu_name = "intrinsic_viscosity";
  }
  const Halves hm = compare_halves(strain, mu, from);
  halves["split_strain"] = hm.split;
  halves["test"] =
      "the means of the two halves agree within 2 standard errors of their difference (each from the whole "
      "span's integrated autocorrelation time) or 1% of the second, whichever is larger";
  halves["mu"] = to_json(hm, mu_name);
  trend["test"] =
      "a least-squares line through the span's 10 batch means; "
      "change = slope (last - first strain) / |mean|, its standard error from the batch means' scatter "
      "about the line; it drifts where the change is beyond 2 standard errors and above 1%";
  trend["mu"] = to_json(fit_trend(strain, mu, from), mu_name);
  if (has_parts) {
    const auto ps = drop_initial(parts, "strain"), taylor = drop_initial(parts, "taylor_mean");
    halves["taylor"] = to_json(compare_halves(ps, taylor, from), "taylor");
    trend["taylor"] = to_json(fit_trend(ps, taylor, from), "taylor");
  }
  j["halves"] = halves;
  j["trend"] = trend;

  // averaged profiles, row by row over the samples after the start
  const Columns prof = read_columns(dir + "/profiles_series.csv");
  if (prof.count("row") && !prof.at("row").empty()) {
    const auto& row = prof.at("row");
    const auto& pst = prof.at("strain");
    const auto& step = prof.at("step");
    const int rows = int(*std::max_element(row.begin(), row.end())) + 1;
    std::vector<std::string> names = {"u_mean", "phi_mean"};
    for (int b = 0; b < n_budget; ++b) names.push_back(budget_name(b));
    std::ostringstream o;
    o << std::setprecision(8) << "# time averages from strain " << from
      << "; u over V_w, stresses over mu_f gamma; "
      << "rows 0..ny-1 cell centres (y_centre), budget on the faces below them (y_face; the last row the top "
         "wall)\n"
      << "row,y_centre,y_face";
    for (const auto& n : names) o << "," << n << "," << n << "_stderr";
    o << "\n";
    const double vw = c.walls.velocity != 0 ? c.walls.velocity : 1.0;
    long samples = 0;
    for (int r = 0; r < rows; ++r) {
      std::vector<size_t> idx;
      for (size_t k = 0; k < row.size(); ++k)
        if (int(row[k]) == r && step[k] > 0 && pst[k] >= from - 1e-12) idx.push_back(k);
      samples = long(idx.size());
      auto pick = [&](const std::string& n) {
        std::vector<double> v;
        for (size_t k : idx) v.push_back(prof.at(n)[k]);
        return v;
      };
      const auto yc = pick("y_centre"), yf = pick("y_face");
      o << r << "," << (yc.empty() ? std::string() : num_str(yc[0])) << ","
        << (yf.empty() ? std::string() : num_str(yf[0]));
      for (const auto& n : names) {
        auto v = pick(n);
        const double scale = n == "u_mean" ? 1 / vw : n == "phi_mean" ? 1.0 : 1 / unit;
        for (auto& e : v) e *= scale;
        const Average a = batch_mean(v, 0);
        o << "," << num_str(a.mean) << "," << num_str(a.stderr_);
      }
      o << "\n";
    }
    out.write_text("profiles.csv", o.str());
    j["profile_samples"] = samples;
  }
  return j;
}

std::string halves_line(const nlohmann::json& averages) {
  if (!averages.contains("halves")) return "";
  const auto& h = averages["halves"];
  std::ostringstream o;
  o << std::setprecision(5) << "averages from strain " << averages["from_strain"].get<double>()
    << ", halves split at " << h["split_strain"].get<double>() << ":";
  for (const char* name : {"mu", "taylor"}) {
    if (!h.contains(name)) continue;
    const auto& e = h[name];
    o << " " << e["quantity"].get<std::string>();
    if (e["agree"].is_null()) {
      o << " not judged (under 20 samples a half);";
      continue;
    }
    o << " " << e["first"]["mean"].get<double>() << " / " << e["second"]["mean"].get<double>()
      << " (tolerance " << e["tolerance"].get<double>() << ") "
      << (e["agree"].get<bool>() ? "agree;" : "DO NOT AGREE: not stationary;");
  }
  return o.str();
}

std::string trend_line(const nlohmann::json& averages) {
  if (!averages.contains("trend")) return "";
  const auto& t = averages["trend"];
  std::ostringstream o;
  o << std::fixed << std::setprecision(2) << "trend across the span (change over its mean):";
  for (const char* name : {"mu", "taylor"}) {
    if (!t.contains(name)) continue;
    const auto& e = t[name];
    o << " " << e["quantity"].get<std::string>();
    if (e["drifts"].is_null()) {
      o << " not judged (under 20 samples);";
      continue;
    }
    double change = 100 * e["change"].get<double>();
    if (std::abs(change) < 0.005) change = 0;  // printed as +0.00, not -0.00
    o << " " << std::showpos << change << std::noshowpos << " +- " << 100 * e["change_stderr"].get<double>()
      << "% " << (e["drifts"].get<bool>() ? "DRIFTS: not stationary;" : "steady;");
  }
  return o.str();
}

}  // namespace softflow
