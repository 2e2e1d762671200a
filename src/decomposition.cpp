#include "decomposition.hpp"

namespace softflow {

Decomposition::Decomposition(MPI_Comm c, const Config& cfg) {
  MPI_Comm_dup(c, &comm);
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  px = cfg.parallel.px;
  pz = cfg.parallel.pz;
  ix = rank % px;
  kz = rank / px;
  MPI_Comm_split(comm, kz, ix, &xcomm);
  MPI_Comm_split(comm, ix, kz, &zcomm);
  nx = cfg.grid.nx;
  ny = cfg.grid.ny;
  nz = cfg.grid.nz;
  nxl = nx / px;
  nzl = nz / pz;
  x0 = ix * nxl;
  z0 = kz * nzl;
  ny_x = ny / px;
  y0_x = ix * ny_x;
  ny_z = ny / pz;
  y0_z = kz * ny_z;
}

Decomposition::~Decomposition() {
  for (MPI_Comm* c : {&xcomm, &zcomm, &comm})
    if (*c != MPI_COMM_NULL) MPI_Comm_free(c);
}

Grid Decomposition::grid(const Config& cfg) const {
  Grid g;
  g.nx = nx;
  g.ny = ny;
  g.nz = nz;
  g.nxl = nxl;
  g.nzl = nzl;
  g.x0 = x0;
  g.z0 = z0;
  g.lx = cfg.grid.lx;
  g.ly = cfg.grid.ly;
  g.lz = cfg.grid.lz;
  g.dx = g.lx / nx;
  g.dy = g.ly / ny;
  g.dz = g.lz / nz;
  return g;
}

}  // namespace softflow
