// The conditions issue 12 sets for a physical solid phase, checked on every
// series row: det B before the unimodular projection within [0.97, 1.03] in
// the cells with phi > 0.5, less than 5% of the solid's elastic shear stress
// in cells with phi < 0.1 (solid that has left its particle), and the solid
// volume conserved to 1e-12 relative. A run warns once per condition the first
// time a row breaks it (SolidWatch); at its end summary.json's "solid_checks"
// gives each condition's bound, the extreme value over the whole series.csv
// (a restarted run's history included) and the first row that broke it.
// Why: the averages of a run whose solid stopped being physical are not the
// suspension's rheology, and the series columns alone leave that to be found
// after the fact (a dilute Ca = 2 particle at 4 points per radius sheds 10%
// of its elastic stress into phi < 0.1 cells: results/README.md).
#pragma once
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace softflow {

struct FlowScalars;

namespace solid_bounds {
constexpr double detb_low = 0.97, detb_high = 1.03;  // issue 12, det B before the projection, phi > 0.5
constexpr double elastic_share_lowphi = 0.05;        // issue 12, share of sum(phi G B_xy) in phi < 0.1 cells
constexpr double volume_drift = 1e-12;               // issue 12, |V - V0| / V0
}  // namespace solid_bounds

// Warnings while a run goes (rank 0): one line on `log` the first time a row
// breaks each condition. The volume's reference is the first row it sees.
class SolidWatch {
 public:
  void row(const FlowScalars& f, long step, double strain, std::ostream& log);

 private:
  bool warned_[3] = {false, false, false};
  double v0_ = 0;
};

// summary.json's "solid_checks" from series.csv's columns (read_columns)
nlohmann::json solid_checks(const std::map<std::string, std::vector<double>>& series);

}  // namespace softflow
