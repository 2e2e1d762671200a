// Everything a run writes into its output folder:
//   series.csv          one row of scalars every output.series_every steps
//   profiles.csv        mean velocity and shear stress across the gap (at the end)
//   fields_NNNNNNNN.h5  cell-centred u, v, w, p snapshots, and fields.xdmf
//                       listing them for ParaView
//   checkpoint.h5       the raw staggered state for restarts
//   summary.json        case, code version, final diagnostics, timings
// Every file is written under a temporary name and renamed when complete,
// except series.csv, which is appended to one flushed row at a time.
#pragma once
#include <fstream>
#include <string>
#include <vector>

#include "diagnostics.hpp"
#include "hdf5_io.hpp"

namespace softflow {

class Output {
 public:
  Output(FlowSolver& s, bool restarted);
  void series_row(const FlowScalars& f, Real dt);
  void snapshot();
  void checkpoint();
  void profiles(const FlowProfiles& p);
  // reads checkpoint `path` into the solver (time, step, fields)
  static void restart(FlowSolver& s, const std::string& path);
  const std::string& dir() const { return dir_; }

 private:
  void write_xdmf();
  void write_text(const std::string& name, const std::string& text);  // rank 0, tmp + rename
  FlowSolver& s_;
  std::string dir_;
  FieldFile file_;
  std::vector<std::pair<long, Real>> snapshots_;  // (step, time)
  std::ofstream series_file_;                       // series.csv, appended (rank 0)
};

// Checks the output folder can be created and written; throws InputError.
void check_output_dir(const std::string& dir);

}  // namespace softflow
