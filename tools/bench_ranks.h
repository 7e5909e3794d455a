// aeroflock bench --weak-scaling: one point of the weak-scaling study over MPI ranks (docs/
// DISTRIBUTED.md "Speed"): P ranks fly P times a flock of N0 birds, the flock lengthened P times
// along x at the scenario's density, and say what a frame costs and what crosses between ranks.
// tools/weak_scaling.py runs it at several P and projects the efficiency to many more ranks.
#pragma once

#include "bench.h"
#include "dist/mpi_session.h"

namespace aeroflock {

int run_weak_scaling(const BenchOptions& options, const dist::MpiSession& mpi);

}  // namespace aeroflock
