// Parallel HDF5 files of whole fields: every rank writes (or reads) its block
// of a global (nz, ny, nx) dataset, x fastest, with collective MPI-IO.
// Files are written under "<name>.tmp" and renamed when complete, so an
// interrupted run never leaves a truncated file under the real name.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "decomposition.hpp"

namespace softflow {

// What to store from a field: its raw values (interior indices) or the
// average of a face-centred field to the cell centres.
enum class Sample { raw, x_face_to_centre, y_face_to_centre, z_face_to_centre };

struct H5Item {
  std::string name;
  Field3 field;
  Sample sample = Sample::raw;
};

class FieldFile {
 public:
  FieldFile(const Decomposition& dec, const Grid& g);
  // writes the items and scalar attributes; collective
  void write(const std::string& path, const std::vector<H5Item>& items,
             const std::map<std::string, double>& attributes,
             const std::map<std::string, std::vector<double>>& array_attributes = {});
  // reads raw items and the named scalar attributes; collective. Throws
  // InputError naming the file and what is missing or does not match.
  std::map<std::string, double> read(const std::string& path, const std::vector<H5Item>& items,
                                     const std::vector<std::string>& attribute_names);
  // a 1-D array attribute, empty if the file has none of that name
  static std::vector<double> read_array(const std::string& path, const std::string& name);

  // public only because nvcc forbids extended (KOKKOS_LAMBDA) lambdas in
  // private or protected member functions
  void stage_out(const H5Item& it);

 private:
  const Decomposition& dec_;
  Grid g_;
  Kokkos::View<Real***, Kokkos::LayoutLeft, MemSpace> dev_;  // interior block
  Kokkos::View<Real***, Kokkos::LayoutLeft, MemSpace>::host_mirror_type host_;
};

// Renames on rank 0 after every rank finished writing (collective).
void commit_file(const Decomposition& dec, const std::string& tmp, const std::string& final_path);

}  // namespace softflow
