// Everything a run writes into its output folder:
//   series.csv          one row of scalars every output.series_every steps
//   particles.csv       particle shapes (Taylor parameter, axes, Phi_e), same rows
//   profiles_series.csv instantaneous profiles across the gap every output.profiles_every steps
//   profiles.csv        their time averages with uncertainties (at the end)
//   fields_NNNNNNNN.h5  cell-centred u, v, w, p snapshots, and fields.xdmf
//                       listing them for ParaView
//   checkpoint.h5       the raw staggered state for restarts
//   summary.json        case, code version, final diagnostics, timings
// Every file is written under a temporary name and renamed when complete,
// except the *series.csv files, appended to one flushed row at a time.
#pragma once
#include <fstream>
#include <string>
#include <vector>

#include "csv_series.hpp"
#include "diagnostics.hpp"
#include "hdf5_io.hpp"
#include "particle_tracker.hpp"

namespace softflow {

class Output {
 public:
  Output(FlowSolver& s, bool restarted);
  void series_row(const FlowScalars& f, Real dt);
  void particles_row(const std::vector<ParticleShape>& shapes);
  void profile_sample(const FlowProfiles& p);
  void snapshot();
  // the tracked particles' centroids and reach go along, for a restart to
  // keep tracking them as the run would have
  void checkpoint(const std::vector<ParticleShape>& particles);
  void write_text(const std::string& name, const std::string& text);  // rank 0, tmp + rename
  // reads checkpoint `path` into the solver (time, step, fields); returns the
  // tracked particles it holds, centroid and reach (empty without particles)
  static std::vector<ParticleShape> restart(FlowSolver& s, const std::string& path);
  const std::string& dir() const { return dir_; }

 private:
  void write_xdmf();
  FlowSolver& s_;
  std::string dir_;
  FieldFile file_;
  std::vector<std::pair<long, Real>> snapshots_;  // (step, time)
  CsvSeries series_, particles_, profiles_;
};

// Checks the output folder can be created and written; throws InputError.
void check_output_dir(const std::string& dir);

}  // namespace softflow
