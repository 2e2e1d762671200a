// softflow: run one case.
//   softflow CASE.toml [--set table.key=value]... [--restart CHECKPOINT.h5]
#include <mpi.h>

#include <cstring>
#include <iostream>

#include "output.hpp"
#include "run.hpp"
#include "run_guard.hpp"
#include "shared_paths.hpp"

namespace {

const char* usage =
    "usage: softflow CASE.toml [--set table.key=value]... [--restart CHECKPOINT.h5]\n"
    "  --set      override a key of the case file, e.g. --set grid.nx=64 (repeatable)\n"
    "  --restart  continue from a checkpoint written by an earlier run of the case\n"
    "The case-file keys are documented in docs/case-file.md.\n";

int fail(int rank, const std::string& msg) {
  if (rank == 0) std::cerr << "softflow: error: " << msg << std::endl;
  return 2;
}

int run(int argc, char** argv, int rank, int size) {
  std::string case_file;
  std::vector<std::string> overrides;
  std::string restart;
  for (int a = 1; a < argc; ++a) {
    std::string s = argv[a];
    if (s == "-h" || s == "--help") {
      if (rank == 0) std::cout << usage;
      return 0;
    } else if (s == "--set" && a + 1 < argc) {
      overrides.push_back(argv[++a]);
    } else if (s.rfind("--set=", 0) == 0) {
      overrides.push_back(s.substr(6));
    } else if (s == "--restart" && a + 1 < argc) {
      restart = argv[++a];
    } else if (s.rfind("-", 0) == 0) {
      return fail(rank, "unknown option '" + s + "'\n" + usage);
    } else if (case_file.empty()) {
      case_file = s;
    } else {
      return fail(rank, "more than one case file given ('" + case_file + "', '" + s + "')");
    }
  }
  if (case_file.empty()) return fail(rank, std::string("no case file given\n") + usage);

  softflow::Config cfg;
  try {
    softflow::check_shared_path("case file", case_file);
    cfg = softflow::load_config(case_file, overrides);
    if (!restart.empty()) cfg.restart = restart;
    softflow::check_shared_path("output folder", cfg.output.dir);
    softflow::check_shared_path("restart file", cfg.restart);
    softflow::resolve_rank_grid(cfg, size);
  } catch (const softflow::InputError& e) {
    return fail(rank, e.what());
  }
  // the output folder is checked by rank 0 only, before anything is written
  std::string err;
  if (rank == 0) {
    try {
      softflow::check_output_dir(cfg.output.dir);
    } catch (const softflow::InputError& e) {
      err = e.what();
    }
  }
  int n = int(err.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (n) return fail(rank, err);

  try {
    softflow::run_case(cfg, MPI_COMM_WORLD, std::cout);
  } catch (const softflow::InputError& e) {
    return fail(rank, e.what());
  } catch (const softflow::RunFailure& e) {
    // every rank stops here together: the run went bad (exit 3, not bad input)
    fail(rank, e.what());
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "softflow: rank " << rank << ": " << e.what() << std::endl;
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  Kokkos::initialize(argc, argv);
  int rc = run(argc, argv, rank, size);
  Kokkos::finalize();
  MPI_Finalize();
  return rc;
}
