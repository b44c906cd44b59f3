// The MPI module (distributed/mpi_module.h): Open MPI behind six plain functions.
#include "bouguer/distributed/mpi_module.h"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <thread>

namespace bouguer::mpi_module {
namespace {

constexpr std::uint64_t kChunkBytes = std::uint64_t{1} << 30;  // MPI counts are int

// Waits for a request by testing it with sleeps that grow from 20 µs to 1 ms: MPI's own blocking
// calls spin on a core, which a rank rendering on the same machine needs.
void wait(MPI_Request& request, MPI_Status* status) {
  auto pause = std::chrono::microseconds(20);
  for (int done = 0;;) {
    MPI_Test(&request, &done, status);
    if (done) return;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(1000));
  }
}

void send_bytes(int to, int tag, const void* data, int bytes) {
  MPI_Request request;
  MPI_Isend(data, bytes, MPI_BYTE, to, tag, MPI_COMM_WORLD, &request);
  wait(request, MPI_STATUS_IGNORE);
}

void receive_bytes(int from, int tag, void* data, int bytes, int* source) {
  MPI_Request request;
  MPI_Irecv(data, bytes, MPI_BYTE, from < 0 ? MPI_ANY_SOURCE : from, tag, MPI_COMM_WORLD, &request);
  MPI_Status status;
  wait(request, &status);
  if (source) *source = status.MPI_SOURCE;
}

void init(int* rank, int* ranks) {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, rank);
  MPI_Comm_size(MPI_COMM_WORLD, ranks);
}

void send(int to, int tag, const void* data, std::uint64_t bytes) {
  send_bytes(to, tag, &bytes, sizeof bytes);
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::uint64_t at = 0; at < bytes; at += kChunkBytes)
    send_bytes(to, tag, p + at, static_cast<int>(std::min(kChunkBytes, bytes - at)));
}

void receive_size(int from, int tag, int* source, std::uint64_t* bytes) {
  receive_bytes(from, tag, bytes, sizeof *bytes, source);
}

void receive(int from, int tag, void* data, std::uint64_t bytes) {
  auto* p = static_cast<unsigned char*>(data);
  for (std::uint64_t at = 0; at < bytes; at += kChunkBytes)
    receive_bytes(from, tag, p + at, static_cast<int>(std::min(kChunkBytes, bytes - at)), nullptr);
}

void abort_job(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);
}

void finalize() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

constexpr Api kApi{1, init, send, receive_size, receive, abort_job, finalize};

}  // namespace
}  // namespace bouguer::mpi_module

extern "C" __attribute__((visibility("default"))) const bouguer::mpi_module::Api* bouguer_mpi_module_api() {
  return &bouguer::mpi_module::kApi;
}
