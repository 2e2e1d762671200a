// Stops a run that goes bad before the bad state reaches a file: a time step
// that collapses far below its recent values (a blow-up in the making: det B
// < 0 in the solid, runaway velocities), or fields that are no longer finite.
// The driver (src/run.cpp) asks before each step and before each snapshot or
// checkpoint, so the last checkpoint written is always a good one.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "flow_solver.hpp"

namespace softflow {

// A run that went bad (not bad input): the message names the step, the
// strain and what failed. Every rank throws it together.
struct RunFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class StepGuard {
 public:
  // the running median spans the last `window` steps; a step below
  // `ratio` times it has collapsed
  static constexpr int window = 100;
  static constexpr int min_history = 10;  // no verdict before this many steps
  static constexpr double ratio = 1e-3;

  // Throws RunFailure when dt, set by `lim`, is not finite and positive, or
  // is below ratio x the median of the recent steps. The step cut short to
  // land on the end time is exempt (and not remembered).
  void check(long step, double strain, double dt, DtLimit lim);

 private:
  std::vector<double> recent_;  // ring buffer of the last `window` time steps
  std::vector<double> sorted_;  // the median's scratch, reserved once (no allocation a step)
  size_t next_ = 0;
};

// The number of non-finite values in the velocity, pressure and solid fields
// of all ranks (collective).
long non_finite_values(FlowSolver& s);

}  // namespace softflow
