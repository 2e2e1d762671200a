#include "run_guard.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace softflow {

void StepGuard::check(long step, double strain, double dt, DtLimit lim) {
  // the messages are built only when a check fails: check runs every step
  if (!std::isfinite(dt) || !(dt > 0)) {
    std::ostringstream m;
    m.precision(4);
    m << "the time step is " << dt << " at step " << step << " (strain " << strain << ", " << to_string(lim)
      << " limit): the solution is no longer finite";
    throw RunFailure(m.str());
  }
  if (lim == DtLimit::end_time) return;
  if (recent_.empty()) {
    recent_.reserve(window);
    sorted_.reserve(window);
  }
  if (int(recent_.size()) >= min_history) {
    sorted_.assign(recent_.begin(), recent_.end());
    std::nth_element(sorted_.begin(), sorted_.begin() + sorted_.size() / 2, sorted_.end());
    const double median = sorted_[sorted_.size() / 2];
    if (dt < ratio * median) {
      std::ostringstream m;
      m.precision(4);
      m << "the time step collapsed at step " << step << " (strain " << strain << "): dt = " << dt
        << " from the " << to_string(lim) << " limit, below " << ratio << " x the median " << median
        << " of the last " << recent_.size() << " steps";
      throw RunFailure(m.str());
    }
  }
  if (int(recent_.size()) < window)
    recent_.push_back(dt);
  else
    recent_[next_] = dt;
  next_ = (next_ + 1) % window;
}

long non_finite_values(FlowSolver& s) {
  std::vector<Field3> fields = {s.state().u, s.state().v, s.state().w, s.state().p};
  if (s.solid())
    for (int m = 0; m < n_solid_fields; ++m) fields.push_back(s.solid()->fields().q[m]);
  long bad = 0;
  for (const Field3& f : fields) {
    long n = 0;
    par_reduce(
        "guard_non_finite", s.grid().interior(),
        KOKKOS_LAMBDA(int i, int j, int k, long& acc) { acc += Kokkos::isfinite(f(i, j, k)) ? 0 : 1; },
        Kokkos::Sum<long>(n));
    bad += n;
  }
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_LONG, MPI_SUM, s.decomposition().comm);
  return bad;
}

}  // namespace softflow
