// The piece protocol of distributed/distributed.h. Messages (distributed/mpi_module.h), all to or
// from rank 0:
//   request  rank r → 0: the job as rank r sees it (Job: what it renders), each time it wants a piece;
//   piece    0 → rank r: the index of its next piece, or -1 when none is left;
//   rays     rank r → 0: the rays rank r traced (after its -1);
//   film     rank r → 0: its serialised film (FilmBuffer::serialise), merged by rank 0.
#include "bouguer/distributed/distributed.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>

#include "bouguer/core/error.h"
#include "bouguer/core/memory.h"
#include "bouguer/core/module.h"
#include "bouguer/distributed/mpi_module.h"
#include "bouguer/core/csv.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/integrators/shell_hops.h"

namespace bouguer::distributed {
namespace {

constexpr int kPiecesPerRank = 16;  // BOUGUER_PIECES_PER_RANK overrides it (docs/distributed.md)
enum Tag : int { kRequest = 1, kPiece = 2, kRays = 3, kFilm = 4 };

// The module, loaded once (an Error before MPI starts when this build has none).
const mpi_module::Api& mpi() {
  std::string problem = "this build has no MPI module";
  const mpi_module::Api* api = nullptr;
#ifdef BOUGUER_MPI_MODULE
  api = module_api_once<mpi_module::Api>(BOUGUER_MPI_MODULE, "bouguer_mpi_module_api", true, problem);
#endif
  if (!api)
    fail(
        "started by mpirun, but this bouguer cannot use MPI ({}): build it with Open MPI installed (libopenmpi-dev, "
        "see docs/distributed.md), or run it without mpirun",
        problem);
  return *api;
}

// What a rank renders; every rank must agree with rank 0 (the scene file by its FNV-1a hash).
using Job = std::array<std::uint64_t, 9>;
constexpr std::array<const char*, 9> kJobFields = {
    "width", "height", "spp", "integrator", "spectral mode", "max depth", "seed", "spectra kept", "scene file hash"};

std::uint64_t fnv1a(std::string_view bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (const char c : bytes) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  return h;
}

Job job_of(const RenderScene& scene, const RenderSettings& s, const FilmBuffer& film) {
  const std::uint64_t scene_hash = scene.file.empty() ? 0 : fnv1a(read_file_bytes(scene.file, kMaxTextFileBytes));
  return {static_cast<std::uint64_t>(film.width()),
          static_cast<std::uint64_t>(film.height()),
          static_cast<std::uint64_t>(s.spp),
          static_cast<std::uint64_t>(s.integrator),
          static_cast<std::uint64_t>(s.spectral),
          static_cast<std::uint64_t>(s.max_depth),
          s.seed,
          film.has_spectra() ? 1u : 0u,
          scene_hash};
}

void check_same_job(const Job& mine, const Job& theirs, int rank) {
  for (std::size_t i = 0; i < mine.size(); ++i)
    if (mine[i] != theirs[i])
      fail(
          "rank {} renders another job than rank 0 ({} {} against {}): every rank must read the same scene file with "
          "the same options",
          rank, kJobFields[i], theirs[i], mine[i]);
}

struct Context {
  const RenderScene& scene;
  const RenderSettings& settings;
  int threads;
  std::vector<PixelRegion> pieces;
  Job job;
  const PathGuide* guide = nullptr;  // the same on every rank (integrators/guiding.h)
  const ShellSet* shells = nullptr;  // made once a rank, not once a piece (integrators/shell_hops.h)
};

void render_piece(const Context& c, std::size_t piece, FilmBuffer& film, RenderStats& stats) {
  RenderControl control;
  control.threads = c.threads;
  control.guide = c.guide;
  control.shells = c.shells;
  render_into(c.scene, c.settings, film, c.pieces[piece], {0, c.settings.spp}, control, stats);
}

// The next message with `tag` from `from` (-1: any rank), which must be `bytes` long; its sender.
int receive_exact(const mpi_module::Api& api, int from, int tag, void* data, std::uint64_t bytes, const char* what) {
  int source = -1;
  std::uint64_t size = 0;
  api.receive_size(from, tag, &source, &size);
  if (size != bytes) fail("rank {} sent {} of {} bytes ({} expected)", source, what, size, bytes);
  api.receive(source, tag, data, bytes);
  return source;
}

void render_as_worker(const Context& c, const mpi_module::Api& api, FilmBuffer& film) {
  RenderStats stats;
  for (;;) {
    api.send(0, kRequest, c.job.data(), sizeof c.job);
    std::int64_t piece = -1;
    receive_exact(api, 0, kPiece, &piece, sizeof piece, "a piece number");
    if (piece < 0) break;
    if (static_cast<std::uint64_t>(piece) >= c.pieces.size())
      fail("rank 0 handed out piece {} of {}", piece, c.pieces.size());
    render_piece(c, static_cast<std::size_t>(piece), film, stats);
  }
  api.send(0, kRays, &stats.rays, sizeof stats.rays);
  const std::vector<std::byte> bytes = film.serialise();
  api.send(0, kFilm, bytes.data(), bytes.size());
}

// Rank 0's answers to requests, until every other rank has been told that no piece is left.
void serve(const Context& c, const mpi_module::Api& api, int ranks, std::atomic<std::size_t>& next,
           const std::function<void()>& piece_done) {
  std::vector<bool> has_piece(static_cast<std::size_t>(ranks), false);
  for (int working = ranks - 1; working > 0;) {
    Job theirs{};
    const int from = receive_exact(api, -1, kRequest, theirs.data(), sizeof theirs, "a request");
    check_same_job(c.job, theirs, from);
    if (has_piece[static_cast<std::size_t>(from)]) piece_done();
    const std::size_t p = next++;
    const std::int64_t answer = p < c.pieces.size() ? static_cast<std::int64_t>(p) : -1;
    has_piece[static_cast<std::size_t>(from)] = answer >= 0;
    if (answer < 0) --working;
    api.send(from, kPiece, &answer, sizeof answer);
  }
}

// Every other rank's film, in rank order, merged into rank 0's; the seconds it took.
double gather(const mpi_module::Api& api, int ranks, FilmBuffer& film, RenderStats& stats) {
  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t bytes = film.serialised_bytes();
  for (int r = 1; r < ranks; ++r) {
    std::uint64_t rays = 0;
    receive_exact(api, r, kRays, &rays, sizeof rays, "a ray count");
    const std::string source = fmt::format("the film of rank {}", r);
    require_memory(2 * bytes, source);  // the bytes and the film they become
    std::vector<std::byte> received(bytes);
    receive_exact(api, r, kFilm, received.data(), bytes, "a film");
    const FilmBuffer theirs = FilmBuffer::deserialise(received, source);
    received = {};
    try {
      film.merge(theirs);
    } catch (const Error& e) {
      fail("{}: {}", source, e.what());
    }
    stats.rays += rays;
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

[[noreturn]] void stop_job(const mpi_module::Api& api, int rank, int ranks, const char* message) {
  fmt::print(stderr, "bouguer: error: rank {} of {}: {}\n", rank, ranks, message);
  std::fflush(stderr);
  api.abort(1);
  std::_Exit(1);
}

// Rank 0: a thread renders pieces from the same counter the requests draw from, while this
// thread answers the requests (MPI stays on this one thread), then the films are gathered.
void render_as_root(const Context& c, const mpi_module::Api& api, int ranks, FilmBuffer& film, bool quiet,
                    const std::function<void(double)>& progress, RenderStats& stats) {
  std::atomic<std::size_t> next{0}, done{0};
  const auto piece_done = [&] {
    const std::size_t d = ++done;
    if (progress) progress(static_cast<double>(d) / static_cast<double>(c.pieces.size()));
  };
  std::exception_ptr failure;
  std::size_t own_pieces = 0;
  std::thread renderer([&] {
    try {
      for (std::size_t p; (p = next++) < c.pieces.size();) {
        render_piece(c, p, film, stats);
        ++own_pieces;
        piece_done();
      }
    } catch (...) {
      failure = std::current_exception();
    }
  });
  try {
    serve(c, api, ranks, next, piece_done);
  } catch (const std::exception& e) {
    stop_job(api, 0, ranks, e.what());  // without unwinding past the running thread
  }
  renderer.join();
  if (failure) std::rethrow_exception(failure);
  const double seconds = gather(api, ranks, film, stats);
  if (!quiet)
    fmt::print(stderr,
               "bouguer: {} ranks, {} pieces of {} rows ({} rendered by rank 0); the films of {} other ranks ({} each) "
               "gathered in {:.3f} s\n",
               ranks, c.pieces.size(), c.pieces.front().y1 - c.pieces.front().y0, own_pieces, ranks - 1,
               format_bytes(film.serialised_bytes()), seconds);
}

}  // namespace

bool launched_by_mpirun() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr;
}

int pieces_per_rank() {
  const char* text = std::getenv("BOUGUER_PIECES_PER_RANK");
  if (!text || !*text) return kPiecesPerRank;
  char* end = nullptr;
  const long n = std::strtol(text, &end, 10);
  if (*end != '\0' || n < 1 || n > 65536) fail("BOUGUER_PIECES_PER_RANK: expected 1 to 65536 (got '{}')", text);
  return static_cast<int>(n);
}

std::vector<PixelRegion> make_pieces(int width_px, int height_px, int ranks, int per_rank) {
  const int rows = std::max(1, height_px / std::max(per_rank * std::max(ranks, 1), 1));
  std::vector<PixelRegion> pieces;
  for (int y = 0; y < height_px; y += rows) pieces.push_back({0, y, width_px, std::min(y + rows, height_px)});
  return pieces;
}

bool render_over_ranks(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, int threads,
                       bool quiet, const std::function<void(double fraction_done)>& progress, RenderStats& stats,
                       const PathGuide* guide) {
  const mpi_module::Api& api = mpi();
  int rank = 0, ranks = 1;
  api.init(&rank, &ranks);
  std::atexit([] { mpi().finalize(); });
  const auto start = std::chrono::steady_clock::now();
  try {
    // vcm: every piece traces the light subpaths of the whole image (its photons), so one per rank.
    const int per_rank = settings.integrator == IntegratorType::vcm ? 1 : pieces_per_rank();
    // (Up to kShellPrebuiltSamples, 64 MiB a phase function, 128 with kept collisions; beyond,
    // each piece makes its own in chunks, integrators.h: render_camera_paths.)
    std::optional<ShellSet> shells;
    if (settings.integrator == IntegratorType::path && settings.shell_transport && scene.scatters &&
        settings.spp <= kShellPrebuiltSamples)
      shells.emplace(scene, settings.seed).make(SampleRange{0, settings.spp}, threads);
    const Context c{scene, settings, threads, make_pieces(film.width(), film.height(), ranks, per_rank),
                    job_of(scene, settings, film), guide, shells ? &*shells : nullptr};
    if (rank != 0) {
      render_as_worker(c, api, film);
      return false;
    }
    RenderStats all;
    render_as_root(c, api, ranks, film, quiet, progress, all);
    stats.rays += all.rays;
  } catch (const std::exception& e) {
    stop_job(api, rank, ranks, e.what());
  }
  stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return true;
}

}  // namespace bouguer::distributed
