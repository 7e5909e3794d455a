#include "mpi_session.h"

#include <cstdio>
#include <cstdlib>

#include <mpi.h>

namespace aeroflock::dist {

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(v)) return true;
  return false;
}

MpiSession::MpiSession(int* argc, char*** argv) {
  if (!launched_by_mpi()) return;
  // MPI is called from the run's thread alone (OpenMP and the writers' threads never call it).
  int provided = MPI_THREAD_SINGLE;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  active_ = true;
  if (provided < MPI_THREAD_FUNNELED) {
    std::fprintf(stderr,
                 "aeroflock: error: this MPI does not let a threaded program call it from "
                 "its main thread (MPI_THREAD_FUNNELED)\n");
    abort(2);
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks_);
}

MpiSession::~MpiSession() {
  if (active_) MPI_Finalize();
}

void MpiSession::abort(int code) const {
  if (active_) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

std::string MpiSession::describe() const {
  if (!active_) return "one process, MPI not initialised";
  return "rank " + std::to_string(rank_) + " of " + std::to_string(ranks_);
}

}  // namespace aeroflock::dist
