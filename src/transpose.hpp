// Pencil transposes for the FFT Poisson solver, on MPI all-to-all.
//
// Work arrays are flat Views with the pencil's whole direction contiguous:
//   y-pencil: (j, i, k) -> j + ny * (i + nxl * k)        i < nxl,  k < nzl
//   x-pencil: (i, j, k) -> i + nx * (j + ny_x * k)       j < ny_x, k < nzl
//   z-pencil: (k, i, j) -> k + nz * (i + nxl * j)        j < ny_z
// so every 1-D FFT and the tridiagonal solves run over contiguous lines.
#pragma once
#include <vector>

#include "decomposition.hpp"
#include "mpi_buffers.hpp"

namespace softflow {

// One all-to-all group (the ranks of a row or a column of the rank grid):
// this rank's place in it and the MPI_Alltoallv counts, made once (no
// allocation in the solver's hot path); the own block's count is 0.
struct TransposeGroup {
  MPI_Comm comm = MPI_COMM_NULL;
  int p = 1, me = 0;
  std::vector<int> counts, displs;
  TransposeGroup(MPI_Comm c, int np, int rank, long block);
};

class Transposer {
 public:
  explicit Transposer(const Decomposition& dec);
  size_t y_size() const { return size_t(dec_.ny) * dec_.nxl * dec_.nzl; }
  size_t x_size() const { return size_t(dec_.nx) * dec_.ny_x * dec_.nzl; }
  size_t z_size() const { return size_t(dec_.nz) * dec_.nxl * dec_.ny_z; }

  void y_to_x(const Array1& y, const Array1& x);
  void x_to_y(const Array1& x, const Array1& y);
  void y_to_z(const Array1& y, const Array1& z);
  void z_to_y(const Array1& z, const Array1& y);

  // bytes this rank sends per transpose through MPI (0 where the group is one rank)
  size_t bytes_x() const { return dec_.px > 1 ? y_size() * sizeof(Real) : 0; }
  size_t bytes_z() const { return dec_.pz > 1 ? y_size() * sizeof(Real) : 0; }
  // bytes sent to other ranks by all transposes so far (for the perf harness)
  size_t bytes_sent() const { return bytes_sent_; }

 private:
  const Decomposition& dec_;
  TransposeGroup xgroup_, zgroup_;
  MpiBuffer send_, recv_;
  size_t bytes_sent_ = 0;
};

}  // namespace softflow
