// The MPI rank grid and the three pencil orientations the FFT Poisson solver
// moves data between.
//
// Physical fields are y-pencils: x split among px ranks, z among pz, y whole
// (the walls stay on every rank). For the FFTs:
//   x-pencil: x whole, y split among px (ranks of one x-row), z as in y-pencil
//   z-pencil: z whole, y split among pz (ranks of one z-column), x as in y-pencil
// so y<->x transposes run inside xcomm and y<->z inside zcomm.
#pragma once
#include <mpi.h>

#include "config.hpp"
#include "grid.hpp"

namespace softflow {

struct Decomposition {
  MPI_Comm comm = MPI_COMM_NULL;   // all ranks of the run
  MPI_Comm xcomm = MPI_COMM_NULL;  // ranks sharing this rank's z-block, ordered by x-block
  MPI_Comm zcomm = MPI_COMM_NULL;  // ranks sharing this rank's x-block, ordered by z-block
  int rank = 0, size = 1;
  int px = 1, pz = 1;  // rank grid
  int ix = 0, kz = 0;  // this rank's block coordinates
  int nx = 0, ny = 0, nz = 0;
  int nxl = 0, nzl = 0, x0 = 0, z0 = 0;  // y-pencil block
  int ny_x = 0, y0_x = 0;                // x-pencil: y block (ny / px)
  int ny_z = 0, y0_z = 0;                // z-pencil: y block (ny / pz)

  Decomposition() = default;
  Decomposition(MPI_Comm comm, const Config& cfg);  // cfg.parallel must be resolved
  Decomposition(const Decomposition&) = delete;
  Decomposition& operator=(const Decomposition&) = delete;
  ~Decomposition();

  Grid grid(const Config& cfg) const;
  bool is_root() const { return rank == 0; }
};

}  // namespace softflow
