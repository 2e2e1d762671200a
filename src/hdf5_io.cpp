#include "hdf5_io.hpp"

#include <hdf5.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace softflow {

namespace {
void check(herr_t e, const std::string& what) {
  if (e < 0) throw std::runtime_error("HDF5: " + what);
}
hid_t check_id(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error("HDF5: " + what);
  return id;
}
}  // namespace

FieldFile::FieldFile(const Decomposition& dec, const Grid& g)
    : dec_(dec), g_(g), dev_("h5_stage", g.nxl, g.ny, g.nzl) {
  host_ = Kokkos::create_mirror_view(dev_);
}

void FieldFile::stage_out(const H5Item& it) {
  auto f = it.field;
  auto d = dev_;
  const Sample s = it.sample;
  const int ng = Grid::ng;
  par_for(
      "io_stage", Range3{0, g_.nxl, 0, g_.ny, 0, g_.nzl}, KOKKOS_LAMBDA(int i, int j, int k) {
        const int a = i + ng, b = j + ng, c = k + ng;
        Real x = f(a, b, c);
        if (s == Sample::x_face_to_centre) x = 0.5 * (x + f(a - 1, b, c));
        if (s == Sample::y_face_to_centre) x = 0.5 * (x + f(a, b - 1, c));
        if (s == Sample::z_face_to_centre) x = 0.5 * (x + f(a, b, c - 1));
        d(i, j, k) = x;
      });
  Kokkos::deep_copy(host_, dev_);
}

void FieldFile::write(const std::string& path, const std::vector<H5Item>& items,
                      const std::map<std::string, double>& attributes,
                      const std::map<std::string, std::vector<double>>& array_attributes) {
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_mpio(fapl, dec_.comm, MPI_INFO_NULL);
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  check_id(file, "cannot create '" + path + "'");
  hsize_t gdims[3] = {hsize_t(g_.nz), hsize_t(g_.ny), hsize_t(g_.nx)};
  hsize_t start[3] = {hsize_t(g_.z0), 0, hsize_t(g_.x0)};
  hsize_t count[3] = {hsize_t(g_.nzl), hsize_t(g_.ny), hsize_t(g_.nxl)};
  hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
  H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);
  for (const auto& it : items) {
    stage_out(it);
    hid_t fspace = H5Screate_simple(3, gdims, nullptr);
    hid_t dset = check_id(
        H5Dcreate2(file, it.name.c_str(), H5T_NATIVE_DOUBLE, fspace, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
        "cannot create dataset " + it.name);
    H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, nullptr, count, nullptr);
    hid_t mspace = H5Screate_simple(3, count, nullptr);
    check(H5Dwrite(dset, H5T_NATIVE_DOUBLE, mspace, fspace, dxpl, host_.data()),
          "writing " + it.name + " to '" + path + "'");
    H5Sclose(mspace);
    H5Sclose(fspace);
    H5Dclose(dset);
  }
  H5Pclose(dxpl);
  for (const auto& [name, value] : attributes) {
    hid_t sp = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(file, name.c_str(), H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, H5P_DEFAULT);
    check(H5Awrite(a, H5T_NATIVE_DOUBLE, &value), "attribute " + name);
    H5Aclose(a);
    H5Sclose(sp);
  }
  for (const auto& [name, values] : array_attributes) {
    const hsize_t n = values.size();
    hid_t sp = n ? H5Screate_simple(1, &n, nullptr) : H5Screate(H5S_NULL);
    hid_t a = H5Acreate2(file, name.c_str(), H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, H5P_DEFAULT);
    if (n) check(H5Awrite(a, H5T_NATIVE_DOUBLE, values.data()), "attribute " + name);
    H5Aclose(a);
    H5Sclose(sp);
  }
  check(H5Fclose(file), "closing '" + path + "'");
}

std::map<std::string, double> FieldFile::read(const std::string& path, const std::vector<H5Item>& items,
                                              const std::vector<std::string>& attribute_names) {
  if (!std::filesystem::exists(path)) throw InputError("restart file '" + path + "' does not exist");
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_mpio(fapl, dec_.comm, MPI_INFO_NULL);
  hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
  if (file < 0) throw InputError("restart file '" + path + "' is not a readable HDF5 file");
  std::map<std::string, double> attrs;
  for (const auto& name : attribute_names) {
    if (H5Aexists(file, name.c_str()) <= 0) {
      H5Fclose(file);
      throw InputError("restart file '" + path + "' has no attribute '" + name + "'");
    }
    hid_t a = H5Aopen(file, name.c_str(), H5P_DEFAULT);
    double v = 0;
    H5Aread(a, H5T_NATIVE_DOUBLE, &v);
    attrs[name] = v;
    H5Aclose(a);
  }
  hsize_t start[3] = {hsize_t(g_.z0), 0, hsize_t(g_.x0)};
  hsize_t count[3] = {hsize_t(g_.nzl), hsize_t(g_.ny), hsize_t(g_.nxl)};
  hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
  H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);
  for (const auto& it : items) {
    if (H5Lexists(file, it.name.c_str(), H5P_DEFAULT) <= 0) {
      H5Fclose(file);
      // a case with more colour fields than the run that wrote the checkpoint
      // (round 24 made one per sphere the default; one phi before)
      const std::string hint =
          it.name.rfind("colour_", 0) == 0
              ? " (it was written with fewer colour fields: give 'particles.colour_fields' its run's value, 0 "
                "for one phi field)"
              : "";
      throw InputError("restart file '" + path + "' has no dataset '" + it.name + "'" + hint);
    }
    hid_t dset = H5Dopen2(file, it.name.c_str(), H5P_DEFAULT);
    hid_t fspace = H5Dget_space(dset);
    hsize_t dims[3] = {0, 0, 0};
    if (H5Sget_simple_extent_ndims(fspace) != 3)
      dims[0] = 0;
    else
      H5Sget_simple_extent_dims(fspace, dims, nullptr);
    if (dims[0] != hsize_t(g_.nz) || dims[1] != hsize_t(g_.ny) || dims[2] != hsize_t(g_.nx)) {
      H5Sclose(fspace);
      H5Dclose(dset);
      H5Fclose(file);
      throw InputError("restart file '" + path + "': dataset '" + it.name + "' is " +
                       std::to_string(dims[2]) + " x " + std::to_string(dims[1]) + " x " +
                       std::to_string(dims[0]) + ", the case's grid is " + std::to_string(g_.nx) + " x " +
                       std::to_string(g_.ny) + " x " + std::to_string(g_.nz));
    }
    H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, nullptr, count, nullptr);
    hid_t mspace = H5Screate_simple(3, count, nullptr);
    check(H5Dread(dset, H5T_NATIVE_DOUBLE, mspace, fspace, dxpl, host_.data()), "reading " + it.name);
    H5Sclose(mspace);
    H5Sclose(fspace);
    H5Dclose(dset);
    Kokkos::deep_copy(dev_, host_);
    auto f = it.field;
    auto d = dev_;
    const int ng = Grid::ng;
    par_for(
        "io_unstage", Range3{0, g_.nxl, 0, g_.ny, 0, g_.nzl},
        KOKKOS_LAMBDA(int i, int j, int k) { f(i + ng, j + ng, k + ng) = d(i, j, k); });
  }
  H5Pclose(dxpl);
  H5Fclose(file);
  return attrs;
}

void commit_file(const Decomposition& dec, const std::string& tmp, const std::string& final_path) {
  MPI_Barrier(dec.comm);
  int ok = 1;
  if (dec.is_root()) ok = std::rename(tmp.c_str(), final_path.c_str()) == 0;
  MPI_Bcast(&ok, 1, MPI_INT, 0, dec.comm);
  if (!ok) throw std::runtime_error("cannot rename '" + tmp + "' to '" + final_path + "'");
}

std::vector<double> FieldFile::read_array(const std::string& path, const std::string& name) {
  std::vector<double> out;
  hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return out;
  if (H5Aexists(file, name.c_str()) > 0) {
    hid_t a = H5Aopen(file, name.c_str(), H5P_DEFAULT);
    hid_t sp = H5Aget_space(a);
    const hssize_t n = H5Sget_simple_extent_npoints(sp);
    if (n > 0) {
      out.resize(size_t(n));
      H5Aread(a, H5T_NATIVE_DOUBLE, out.data());
    }
    H5Sclose(sp);
    H5Aclose(a);
  }
  H5Fclose(file);
  return out;
}

}  // namespace softflow
