// softflow's floating-point type on its own, for code that needs no Kokkos:
// config.cpp (the TOML reader) includes only this, so that CUDA builds can
// compile it with the host compiler alone (nvcc cannot parse toml++'s
// headers; see CMakeLists.txt).
#pragma once

namespace softflow {

using Real = double;

}  // namespace softflow
