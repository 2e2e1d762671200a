// Halo exchange in the periodic x and z directions (y is never split: the
// walls fill its ghosts, see kernels/wall_bc.hpp). x first over the interior
// z range, then z over the whole x range, so edge and corner ghosts are right.
#pragma once
#include <initializer_list>

#include "decomposition.hpp"
#include "mpi_buffers.hpp"

namespace softflow {

class Halo {
 public:
  static constexpr int max_fields = 8;
  Halo(const Decomposition& dec, const Grid& g);
  // Fills the x and z ghosts of up to max_fields fields of the grid's storage shape.
  void exchange(std::initializer_list<Field3> fields);
  // the same for nf <= max_fields fields in an array
  void exchange(const Field3* f, int nf);
  // bytes sent per exchange of one field (for the perf harness)
  size_t bytes_per_field() const;
  // bytes sent to other ranks by all exchanges so far (for the perf harness)
  size_t bytes_sent() const { return bytes_sent_; }
  MPI_Comm comm() const { return dec_.comm; }

  // public only because nvcc forbids extended (KOKKOS_LAMBDA) lambdas in
  // private or protected member functions
  void exchange_dir(int dir, const Field3* f, int nf);

 private:
  const Decomposition& dec_;
  Grid g_;
  int left_x_, right_x_, left_z_, right_z_;
  MpiBuffer send_lo_, send_hi_, recv_lo_, recv_hi_;
  size_t bytes_sent_ = 0;
};

}  // namespace softflow
