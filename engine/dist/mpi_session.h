// MPI for the program: initialised only when a launcher (mpirun, mpiexec) started it, so that
// without one the program runs as always, MPI untouched (docs/DISTRIBUTED.md).
#pragma once

#include <string>

namespace aeroflock::dist {

class MpiSession {
 public:
  // MPI_Init where a launcher's variables say one started this process; else nothing.
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  bool active() const { return active_; }  // MPI initialised
  int rank() const { return rank_; }
  int ranks() const { return ranks_; }
  bool root() const { return rank_ == 0; }
  // Ends every rank now with `code` (MPI_Abort where active, else exit): an error on one rank
  // that the others cannot know of, so that none waits for it forever.
  [[noreturn]] void abort(int code) const;
  // How this process runs, in words: "one process, MPI not initialised" or "rank 2 of 4".
  std::string describe() const;

 private:
  bool active_ = false;
  int rank_ = 0, ranks_ = 1;
};

// Whether a launcher started this process (OpenMPI's, MPICH's Hydra or PMIx variables).
bool launched_by_mpi();

}  // namespace aeroflock::dist
