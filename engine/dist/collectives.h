// The MPI collectives the distributed code repeats, written once: plain data as bytes of its
// type, and vectors of it gathered onto one rank.
#pragma once

#include <mpi.h>

#include <climits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace aeroflock::dist {

// A datatype of one T as raw bytes (free it with MPI_Type_free).
template <class T>
MPI_Datatype bytes_of() {
  static_assert(std::is_trivially_copyable_v<T>);
  MPI_Datatype t;
  MPI_Type_contiguous(static_cast<int>(sizeof(T)), MPI_BYTE, &t);
  MPI_Type_commit(&t);
  return t;
}

// Every rank's `mine`, one after the other in rank order, on `root` (empty elsewhere). Collective.
// More than 2^31 - 1 elements in all is every rank's std::runtime_error alike.
template <class T>
std::vector<T> gather_to(int root, MPI_Comm comm, const std::vector<T>& mine) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const long long count = static_cast<long long>(mine.size());
  long long total = 0;
  MPI_Allreduce(&count, &total, 1, MPI_LONG_LONG, MPI_SUM, comm);
  if (total > INT_MAX)
    throw std::runtime_error(std::to_string(total) +
                             " elements are more than one MPI gather takes (2^31 - 1)");
  const int n = static_cast<int>(count);
  std::vector<int> counts(static_cast<size_t>(ranks)), at(static_cast<size_t>(ranks));
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, root, comm);
  int offset = 0;
  for (int q = 0; q < ranks; ++q) at[size_t(q)] = offset, offset += counts[size_t(q)];
  std::vector<T> all(rank == root ? static_cast<size_t>(total) : 0);
  MPI_Datatype type = bytes_of<T>();
  MPI_Gatherv(mine.data(), n, type, all.data(), counts.data(), at.data(), type, root, comm);
  MPI_Type_free(&type);
  return all;
}

}  // namespace aeroflock::dist
