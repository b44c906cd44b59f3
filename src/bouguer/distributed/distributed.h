#pragma once
// One render spread over the ranks of `mpirun -np N bouguer render ...` (docs/distributed.md).
// The image is cut into pieces of whole rows, every sample of each pixel in one piece; ranks ask
// rank 0 for the next piece whenever they finish one (rank 0 renders pieces too, between
// answering them), each into a film of the full size; at the end rank 0 receives every rank's
// film and merges it exactly (FilmBuffer::merge), so the image is bit for bit the one-process
// image. MPI itself lives in a module loaded only here (distributed/mpi_module.h).
#include <cstdint>
#include <functional>
#include <vector>

#include "bouguer/render/integrator.h"

namespace bouguer::distributed {

// Whether this process is one rank of a job that mpirun (or a PMIx launcher) started: read from
// the launcher's environment, without starting MPI.
bool launched_by_mpirun();

// The pieces of a film for `ranks` ranks: bands of whole rows, about `per_rank` per rank (16, or
// BOUGUER_PIECES_PER_RANK), top to bottom.
int pieces_per_rank();
std::vector<PixelRegion> make_pieces(int width_px, int height_px, int ranks, int per_rank);

// Renders every pixel and sample of the settings over all ranks of the job. On rank 0 it returns
// true with the merged film in `film` (stats: the wall time, the rays of every rank); on the
// others false once their film is sent (they write nothing). Any error on any rank prints one
// line naming the rank and stops the whole job (exit 1), so no rank waits for a dead one and no
// output is written. `film` must be empty (as make_film gives it); `progress` is called on rank 0,
// which also prints one line on the pieces and the gather unless `quiet`.
bool render_over_ranks(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, int threads,
                       bool quiet, const std::function<void(double fraction_done)>& progress, RenderStats& stats,
                       const PathGuide* guide = nullptr);

}  // namespace bouguer::distributed
