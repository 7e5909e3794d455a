// What crosses between ranks each frame (docs/DISTRIBUTED.md), for any backend's birds: the
// migrants with what the backend keeps of them, and the ghosts. Included by the backends' sources
// (distributed.cpp, distributed_gpu.cpp) alone.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <type_traits>
#include <vector>

#include <mpi.h>

#include "dist/collectives.h"
#include "dist/distributed.h"

namespace aeroflock::dist {

// Sends outgoing[q] to rank q, for every q at once; what every rank sent here, by rank.
template <class T>
std::vector<T> exchange(MPI_Comm comm, const std::vector<std::vector<T>>& outgoing, Traffic& t) {
  const int ranks = static_cast<int>(outgoing.size());
  std::vector<int> send_counts(static_cast<size_t>(ranks)), recv_counts(static_cast<size_t>(ranks));
  std::vector<int> send_at(static_cast<size_t>(ranks), 0), recv_at(static_cast<size_t>(ranks), 0);
  std::vector<T> send;
  for (int q = 0; q < ranks; ++q) {
    send_at[size_t(q)] = static_cast<int>(send.size());
    send_counts[size_t(q)] = static_cast<int>(outgoing[size_t(q)].size());
    send.insert(send.end(), outgoing[size_t(q)].begin(), outgoing[size_t(q)].end());
  }
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm);
  int total = 0;
  for (int q = 0; q < ranks; ++q) recv_at[size_t(q)] = total, total += recv_counts[size_t(q)];
  std::vector<T> received(static_cast<size_t>(total));
  MPI_Datatype type = bytes_of<T>();
  MPI_Alltoallv(send.data(), send_counts.data(), send_at.data(), type, received.data(),
                recv_counts.data(), recv_at.data(), type, comm);
  MPI_Type_free(&type);
  t.bytes_sent += send.size() * sizeof(T);
  return received;
}

// A bird handed to its new owner: all its state and the backend's `extra` of it (what it last
// perceived: a bird keeps that between its ticks).
template <class Extra>
struct Migrant {
  uint32_t id;
  BirdState bird;
  Extra extra;
};

template <class Extra>
void DistributedSimulation::migrate(std::vector<Extra>& extra) {
  static_assert(std::is_trivially_copyable_v<Migrant<Extra>>);
  const double start = MPI_Wtime();
  std::vector<std::vector<Migrant<Extra>>> out(static_cast<size_t>(ranks_));
  size_t kept = 0;
  for (size_t k = 0; k < birds_.size(); ++k) {
    const int owner = slabs_.owner(slabs_.cell_of(birds_[k].position));
    if (owner == rank_) {
      birds_[kept] = birds_[k], ids_[kept] = ids_[k], extra[kept] = extra[k];
      ++kept;
    } else {
      Migrant<Extra> m;
      std::memset(static_cast<void*>(&m), 0, sizeof m);  // no byte sent is left unset (padding)
      m.id = ids_[k], m.bird = birds_[k], m.extra = extra[k];
      out[size_t(owner)].push_back(m);
      ++traffic_.migrants_sent;
    }
  }
  birds_.resize(kept), ids_.resize(kept), extra.resize(kept);
  const std::vector<Migrant<Extra>> in = exchange(comm_, out, traffic_);
  if (!in.empty()) {
    // Merged in by id, so that this rank's birds stay in the one-rank order.
    for (const Migrant<Extra>& m : in)
      birds_.push_back(m.bird), ids_.push_back(m.id), extra.push_back(m.extra);
    std::vector<uint32_t> order(birds_.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](uint32_t a, uint32_t b) { return ids_[a] < ids_[b]; });
    std::vector<BirdState> birds(order.size());
    std::vector<uint32_t> ids(order.size());
    std::vector<Extra> extras(order.size());
    for (size_t k = 0; k < order.size(); ++k)
      birds[k] = birds_[order[k]], ids[k] = ids_[order[k]], extras[k] = extra[order[k]];
    birds_.swap(birds), ids_.swap(ids), extra.swap(extras);
  }
  traffic_.seconds += MPI_Wtime() - start;
}

template <class Ghost, class Make>
std::vector<Ghost> DistributedSimulation::exchange_ghosts(uint64_t frame, const Make& make) {
  static_assert(std::is_trivially_copyable_v<Ghost>);
  const double start = MPI_Wtime();
  // Each rank says how far past its cuts it looks; only birds that flock now are seen by anyone,
  // and they go to every rank that looks where they are.
  reach_ = reach_past_cuts(frame);
  std::vector<Reach> reaches(static_cast<size_t>(ranks_));
  MPI_Allgather(&reach_, 4, MPI_DOUBLE, reaches.data(), 4, MPI_DOUBLE, comm_);
  std::vector<std::vector<Ghost>> out(static_cast<size_t>(ranks_));
  for (size_t k = 0; k < birds_.size(); ++k) {
    if (!flocks_now(birds_[k])) continue;
    // A rank looks at most its perception radius and a cell past its cuts: only the owners of
    // the cells a halo and a cell round this bird's may ask for it.
    const double x = birds_[k].position[slabs_.axis];
    const int64_t c = slabs_.cell_of(birds_[k].position);
    for (int q = slabs_.owner(c - slabs_.halo - 1), last = slabs_.owner(c + slabs_.halo + 1);
         q <= last; ++q)
      if (q != rank_ && reaches[size_t(q)].holds(x)) {
        out[size_t(q)].push_back(make(k));
        ++traffic_.ghosts_sent;
      }
  }
  std::vector<Ghost> ghosts = exchange(comm_, out, traffic_);
  ghosts_ = ghosts.size();
  traffic_.seconds += MPI_Wtime() - start;
  std::sort(ghosts.begin(), ghosts.end(),
            [](const Ghost& a, const Ghost& b) { return a.id < b.id; });
  return ghosts;
}

// This rank's birds (their `ids`, ascending) and the `ghosts` (ordered by id) as one list by id:
// own(k) for this rank's bird k, ghost(g) for ghost g, in that order.
template <class Ghost, class Own, class OfGhost>
void merge_by_id(const std::vector<uint32_t>& ids, const std::vector<Ghost>& ghosts, const Own& own,
                 const OfGhost& ghost) {
  size_t g = 0;
  for (size_t k = 0; k < ids.size(); ++k) {
    for (; g < ghosts.size() && ghosts[g].id < ids[k]; ++g) ghost(g);
    own(k);
  }
  for (; g < ghosts.size(); ++g) ghost(g);
}

}  // namespace aeroflock::dist
