// app/mpi_mode.hpp -- the same `tetia` executable under mpiexec: rank 0 runs the command (reads
// the files, writes every output, prints the JSON), the other ranks serve it; the supermesh of
// two tetrahedral meshes is computed by all the ranks (tetia/mpi.hpp).
//
// Contract. mpi_start() is the first thing main() does: where the process was started by
// mpiexec (Open MPI's, MPICH's or any PMI launcher's environment) and the build has MPI, it
// initializes MPI; a rank other than 0 then serves rank 0 until told to stop and returns the
// exit status main() must return at once; rank 0 (and a process not under mpiexec) gets
// nothing and goes on. mpi_finish(status) is the last: rank 0 sends the other ranks the exit
// status (so a bad file ends every rank with rank 0's status, and only rank 0 prints), then
// every rank finalizes MPI. parallel_supermesh(): on rank 0 with more than one rank, partitions
// both meshes (PartitionKind), sends each rank its parts, takes part in tetia::mpi::supermesh
// and gathers the pieces: the Supermesh one process computes, piece for piece (sorted by
// (target, source), local mixed mass matrices if asked), with `candidates` summed over the
// ranks and `seconds` the whole step's; otherwise tetia::supermesh itself. 2D meshes are always
// done by rank 0 alone (tetia/mpi.hpp is 3D).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "tetia/supermesh.hpp"

namespace tetia::app {

std::optional<int> mpi_start(int& argc, char**& argv);
int mpi_finish(int status);

/// The ranks in the MPI run (1 without mpiexec or without MPI in the build).
int mpi_ranks();

/// How the command line partitions the meshes under mpiexec: "morton" (both meshes cut into
/// runs along a Morton curve through the cell centroids, run r to rank r), "reversed" (the same,
/// but the target's run r to rank P - 1 - r: partitions that do not match, for testing),
/// "random" (each cell to a rank at random, fixed seed).
void check_partition(const std::string& kind);

Supermesh parallel_supermesh(std::shared_ptr<const TetMesh> source, std::shared_ptr<const TetMesh> target,
                             const SupermeshOptions& options, const std::string& partition);
Supermesh2 parallel_supermesh(std::shared_ptr<const TriMesh> source, std::shared_ptr<const TriMesh> target,
                              const SupermeshOptions& options, const std::string& partition);

}  // namespace tetia::app
