// Message buffers for MPI from device memory. When host code can read the
// execution space's memory (OpenMP), MPI gets the View's pointer directly;
// otherwise (CUDA without GPU-aware MPI) the data is staged through a host
// mirror allocated once, next to the device buffer.
#pragma once
#include <mpi.h>

#include "types.hpp"

namespace softflow {

struct MpiBuffer {
  Array1 dev;
  Array1::host_mirror_type host;

  static constexpr bool host_accessible =
      Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpace>::accessible;

  MpiBuffer() = default;
  MpiBuffer(const char* label, size_t n) : dev(std::string(label), n) {
    if constexpr (!host_accessible) host = Kokkos::create_mirror_view(dev);
  }
  // pointer for MPI after the device side was written
  Real* send_ptr() {
    if constexpr (host_accessible) {
      Kokkos::fence("MpiBuffer::send");
      return dev.data();
    } else {
      Kokkos::deep_copy(host, dev);
      return host.data();
    }
  }
  Real* recv_ptr() {
    if constexpr (host_accessible) return dev.data();
    else return host.data();
  }
  // after MPI wrote into recv_ptr()
  void received() {
    if constexpr (!host_accessible) Kokkos::deep_copy(dev, host);
  }
};

}  // namespace softflow
