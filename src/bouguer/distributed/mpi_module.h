#pragma once
// The interface of the MPI module (libbouguer_mpi.so, distributed/mpi_module.cpp), the only code
// that includes MPI. distributed/distributed.cpp loads it with dlopen when the process was started
// by mpirun, so a build without MPI still builds, and a render without mpirun neither links nor
// starts MPI (Open MPI's libraries cost every start about 9 ms of relocation, as much as the rest
// of `bouguer --version`). Plain types only: the module shares no code with the library.
#include <cstdint>

namespace bouguer::mpi_module {

struct Api {
  int version = 1;
  // Starts MPI for one thread (the caller's: only it calls MPI afterwards) and gives this
  // process's rank and the ranks in the job. MPI stops at exit (finalize), or abort stops the job.
  void (*init)(int* rank, int* ranks);
  // Every call below blocks until done, by polling with short sleeps, so a waiting rank leaves
  // its cores to the renderers. Messages of any size (sent as a size, then pieces of at most 1 GiB).
  void (*send)(int to, int tag, const void* data, std::uint64_t bytes);
  // The size of the next message with `tag` from `from` (-1: any rank) and its sender, whose
  // bytes receive() must then take.
  void (*receive_size)(int from, int tag, int* source, std::uint64_t* bytes);
  void (*receive)(int from, int tag, void* data, std::uint64_t bytes);
  // Stops every rank of the job with this exit code (mpirun reports it); does not return.
  void (*abort)(int code);
  void (*finalize)();
};

}  // namespace bouguer::mpi_module

// The module's one exported symbol.
extern "C" const bouguer::mpi_module::Api* bouguer_mpi_module_api();
