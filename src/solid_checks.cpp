#include "solid_checks.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "diagnostics.hpp"

namespace softflow {

namespace {
const char* const detb_hint =
    "the solid's stretch is drifting from volume-preserving (README, Known limits; results/README.md, "
    "issue 12)";
const char* const share_hint =
    "solid is leaving its particle, and the grid or the phi scheme does not hold it (a dilute Ca = 2 "
    "particle needs 6 points per radius: README, Issue 12 status)";
const char* const volume_hint = "the solid volume is not conserved";

double volume_drift(double v, double v0) { return v0 != 0 ? std::abs(v - v0) / std::abs(v0) : 0; }

// the three conditions, one row at a time (the watch and the series read the same)
bool detb_outside(double lo, double hi) {
  return lo < solid_bounds::detb_low || hi > solid_bounds::detb_high;
}
bool share_above(double share) { return share > solid_bounds::elastic_share_lowphi; }
bool volume_moved(double v, double v0) { return volume_drift(v, v0) > solid_bounds::volume_drift; }

std::string num(double x) {
  std::ostringstream o;
  o.precision(4);
  o << x;
  return o.str();
}
}  // namespace

void SolidWatch::row(const FlowScalars& f, long step, double strain, std::ostream& log) {
  if (v0_ == 0) v0_ = f.solid_volume;
  auto warn = [&](int which, const std::string& what, const char* hint) {
    if (warned_[which]) return;
    warned_[which] = true;
    log << "warning: at step " << step << " (strain " << strain << ") " << what << ": " << hint
        << " (reported once; summary.json's solid_checks has the whole run)" << std::endl;
  };
  // each message is built only the first time (rows come every few steps)
  if (!warned_[0] && detb_outside(f.detb_raw_min, f.detb_raw_max))
    warn(0,
         "det B (before any projection) spans [" + num(f.detb_raw_min) + ", " + num(f.detb_raw_max) +
             "] in phi > 0.5 cells, outside [" + num(solid_bounds::detb_low) + ", " +
             num(solid_bounds::detb_high) + "]",
         detb_hint);
  if (!warned_[1] && share_above(f.elastic_share_lowphi))
    warn(1,
         "cells with phi < 0.1 carry " + num(100 * f.elastic_share_lowphi) +
             "% of the elastic shear stress (bound " + num(100 * solid_bounds::elastic_share_lowphi) + "%)",
         share_hint);
  if (!warned_[2] && volume_moved(f.solid_volume, v0_))
    warn(2,
         "the solid volume moved by " + num(volume_drift(f.solid_volume, v0_)) + " relative (bound " +
             num(solid_bounds::volume_drift) + ")",
         volume_hint);
}

nlohmann::json solid_checks(const std::map<std::string, std::vector<double>>& series) {
  nlohmann::json j;
  auto column = [&](const char* name) -> const std::vector<double>& {
    static const std::vector<double> none;
    const auto it = series.find(name);
    return it == series.end() ? none : it->second;
  };
  const auto& step = column("step");
  const auto& strain = column("strain");
  const auto& lo = column("detb_raw_min");
  const auto& hi = column("detb_raw_max");
  const auto& share = column("elastic_share_lowphi");
  const auto& vol = column("solid_volume");
  const size_t n = std::min({step.size(), strain.size(), lo.size(), hi.size(), share.size(), vol.size()});
  if (n == 0) return j;
  // one condition: its extreme value and the first row that broke it
  auto check = [&](auto&& broken) {
    nlohmann::json c;
    c["pass"] = true;
    c["first_fail"] = nullptr;
    for (size_t k = 0; k < n; ++k)
      if (broken(k)) {
        c["pass"] = false;
        c["first_fail"] = {{"step", long(step[k])}, {"strain", strain[k]}};
        break;
      }
    return c;
  };
  nlohmann::json d = check([&](size_t k) { return detb_outside(lo[k], hi[k]); });
  d["bound"] = {solid_bounds::detb_low, solid_bounds::detb_high};
  d["range"] = {*std::min_element(lo.begin(), lo.begin() + n), *std::max_element(hi.begin(), hi.begin() + n)};
  j["detb_raw_phi_above_half"] = d;
  nlohmann::json s = check([&](size_t k) { return share_above(share[k]); });
  s["bound"] = solid_bounds::elastic_share_lowphi;
  s["max"] = *std::max_element(share.begin(), share.begin() + n);
  j["elastic_share_lowphi"] = s;
  nlohmann::json v = check([&](size_t k) { return volume_moved(vol[k], vol[0]); });
  v["bound"] = solid_bounds::volume_drift;
  double worst = 0;
  for (size_t k = 0; k < n; ++k) worst = std::max(worst, volume_drift(vol[k], vol[0]));
  v["max"] = worst;
  j["solid_volume_drift"] = v;
  return j;
}

}  // namespace softflow
