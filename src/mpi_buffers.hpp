// Message buffers for MPI from device memory. MPI gets the View's own pointer
// when host code can read the execution space's memory (OpenMP) or when the
// MPI library is GPU-aware (CMake option SOFTFLOW_GPU_AWARE_MPI, checked at
// run time with Open MPI's MPIX_Query_cuda_support where available);
// otherwise (CUDA without GPU-aware MPI) the data is staged through a host
// mirror allocated once, next to the device buffer.
#pragma once
#include <mpi.h>
#if defined(SOFTFLOW_GPU_AWARE_MPI) && defined(OPEN_MPI) && OPEN_MPI
#include <mpi-ext.h>
#endif

#include "types.hpp"

namespace softflow {

// Whether MPI may be handed pointers to MemSpace directly.
inline bool mpi_reads_device_memory() {
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpace>::accessible) return true;
#if defined(SOFTFLOW_GPU_AWARE_MPI)
#if defined(MPIX_CUDA_AWARE_SUPPORT) && defined(KOKKOS_ENABLE_CUDA)
  static const bool aware = MPIX_Query_cuda_support() == 1;  // built with it, and running with it
  return aware;
#else
  return true;  // the user says so (no way to ask this MPI library)
#endif
#else
  return false;
#endif
}

struct MpiBuffer {
  Array1 dev;
  Array1::host_mirror_type host;
  bool direct = true;  // MPI reads and writes dev itself

  MpiBuffer() = default;
  MpiBuffer(const char* label, size_t n) : dev(std::string(label), n), direct(mpi_reads_device_memory()) {
    if (!direct) host = Kokkos::create_mirror_view(dev);
  }
  // pointer for MPI after the device side was written
  Real* send_ptr() {
    if (direct) {
      Kokkos::fence("MpiBuffer::send");
      return dev.data();
    }
    Kokkos::deep_copy(host, dev);
    return host.data();
  }
  Real* recv_ptr() { return direct ? dev.data() : host.data(); }
  // after MPI wrote into recv_ptr()
  void received() {
    if (!direct) Kokkos::deep_copy(dev, host);
  }
};

}  // namespace softflow
