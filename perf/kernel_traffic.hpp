// Compulsory memory traffic of each labelled kernel, in Reals per cell of
// its domain, for the harness's bytes-per-cell and bandwidth
// figures. Counted from what each kernel's body reads and writes, assuming a
// stencil's neighbours come from cache (each array element read once per
// sweep), so these are lower bounds on the traffic: the bandwidth a kernel
// "achieves" is bytes / time with these bytes.
#pragma once
#include <optional>
#include <string>

namespace softflow::perf {

// Where a kernel runs: the whole interior, or only the solid's region (or
// that region plus one cell, for the force) of kernels/solid_region.hpp; the
// harness scales the latter two by the region's share of the interior.
enum class Domain { box, solid, solid_force };

struct Traffic {
  double reads = 0;       // Reals read per cell of its domain per call
  double writes = 0;      // Reals written per cell of its domain per call
  const char* what = "";  // the arrays, for the JSON and the report
  Domain domain = Domain::box;
};

// The traffic of the kernel with this label, or nothing for kernels whose
// work does not scale with the cell count (halo pack/unpack, wall ghosts,
// reductions over planes) or that are not counted.
std::optional<Traffic> kernel_traffic(const std::string& label);

}  // namespace softflow::perf
