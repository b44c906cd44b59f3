// Films rendered in pieces, serialised and merged are bit for bit the film of one render, for
// every integrator; a truncated or hostile serialised film is an Error, never a crash.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "bouguer/core/error.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

const fs::path kExample = fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "examples" / "issue3.json";

SceneDesc small_example(IntegratorType integrator, SpectralMode mode) {
  SceneDesc desc = load_scene(kExample);
  desc.camera.width_px = 24;
  desc.camera.height_px = 18;
  desc.render.spp = 3;
  desc.render.integrator = integrator;
  desc.render.spectral = mode;
  return desc;
}

// The film of one render, and the same pieces handed round-robin to `parts` films, each
// serialised, read back and merged into an empty film (as rank 0 gathers them).
struct OneAndMerged {
  std::vector<std::byte> one, merged;
  Film image;
};

OneAndMerged render_one_and_merged(const RenderScene& scene, const RenderSettings& settings, bool spectra, int parts) {
  RenderControl control;
  control.threads = 2;
  RenderStats stats;
  FilmBuffer one = make_film(scene, spectra);
  render_into(scene, settings, one, PixelRegion::whole(scene.camera), {0, settings.spp}, control, stats);
  std::vector<FilmBuffer> films;
  for (int i = 0; i < parts; ++i) films.push_back(make_film(scene, spectra));
  // Bands of two rows, as the ranks of distributed/ take them, in an order no rank would keep.
  const int bands = (one.height() + 1) / 2;
  for (int b = 0; b < bands; ++b)
    render_into(scene, settings, films[static_cast<std::size_t>(b * 7 % parts)], {0, 2 * b, one.width(), 2 * b + 2},
                {0, settings.spp}, control, stats);
  FilmBuffer merged = make_film(scene, spectra);
  for (const FilmBuffer& f : films) merged.merge(FilmBuffer::deserialise(f.serialise(), "a part"));
  return {one.serialise(), merged.serialise(), resolve(one, settings.spp)};
}

bool any_light(const Film& film) {
  for (const float v : film.rgb)
    if (v > 0.0f) return true;
  return false;
}

TEST(FilmMerge, PiecesMergedEqualOneRenderBitForBitForEveryIntegrator) {
  for (const IntegratorInfo& integrator : integrator_table())
    for (const SpectralMode mode : {SpectralMode::full, SpectralMode::hero}) {
      // auto is resolved before any piece is rendered (the command line's trials, the same on
      // every rank: integrators/choose.h); the pieces are then the chosen estimator's.
      if (integrator.type == IntegratorType::automatic) continue;
      // (the path tracer also with its light paths, and bdpt, whose splats through glass land
      // anywhere: on the lit tumbler, a point and a spot lamp behind glass)
      for (const bool tumbler : {false, true}) {
        const bool light_paths = tumbler && integrator.type == IntegratorType::path;
        if (tumbler && !light_paths && integrator.type != IntegratorType::bdpt) continue;
        SCOPED_TRACE(fmt::format("{} {}{}", integrator.name, spectral_mode_name(mode), tumbler ? ", lit tumbler" : ""));
        SceneDesc desc = tumbler ? parse_scene(test::lit_tumbler(std::string(integrator.name).c_str()), "tumbler.json")
                                 : small_example(integrator.type, mode);
        desc.render.spp = 3;
        desc.render.spectral = mode;
        desc.render.light_paths = light_paths;
        const RenderScene scene = compile(desc);
        const RenderSettings& settings = desc.render;
        for (const int parts : {2, 3}) {
          const bool spectra = mode == SpectralMode::full;
          const OneAndMerged r = render_one_and_merged(scene, settings, spectra, parts);
          EXPECT_TRUE(any_light(r.image));  // a test of nothing would pass too
          EXPECT_EQ(r.one.size(), r.merged.size());
          EXPECT_TRUE(r.one == r.merged) << parts << " parts";
        }
      }
    }
}

// A film with camera sums, splats and spectra in it, serialised.
std::vector<std::byte> example_bytes() {
  const SceneDesc desc = small_example(IntegratorType::light, SpectralMode::full);
  const RenderScene scene = compile(desc);
  FilmBuffer film = make_film(scene, true);
  film.add_sample(1, 2, {0.5, 0.25, 0.125}, 1.0);
  RenderStats stats;
  render_into(scene, desc.render, film, {0, 0, 4, 4}, {0, 1}, {}, stats);
  return film.serialise();
}

template <typename T>
void put(std::vector<std::byte>& bytes, std::size_t at, T value) {
  std::memcpy(bytes.data() + at, &value, sizeof value);
}

std::string deserialise_outcome(const std::vector<std::byte>& bytes) {
  try {
    (void)FilmBuffer::deserialise(bytes, "film.bin");
    return "ok";
  } catch (const Error& e) {
    return e.what();
  }
}

TEST(FilmSerialise, RoundTripsEveryByte) {
  const auto bytes = example_bytes();
  EXPECT_EQ(FilmBuffer::deserialise(bytes, "film.bin").serialise(), bytes);
}

TEST(FilmSerialise, TruncatedOrExtendedBuffersAreErrors) {
  auto bytes = example_bytes();
  for (const std::size_t size : {std::size_t{0}, std::size_t{1}, std::size_t{39}, std::size_t{40}, std::size_t{47},
                                 bytes.size() / 2, bytes.size() - 1}) {
    const std::vector<std::byte> cut(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(size));
    EXPECT_NE(deserialise_outcome(cut).find("film.bin: "), std::string::npos) << size;
  }
  bytes.push_back(std::byte{0});
  EXPECT_NE(deserialise_outcome(bytes).find("takes"), std::string::npos);
}

TEST(FilmSerialise, HostileHeadersAreErrorsBeforeAnyAllocation) {
  const auto good = example_bytes();
  auto with = [&](auto change) {
    auto bytes = good;
    change(bytes);
    return test::run_with_memory_budget([&] { (void)FilmBuffer::deserialise(bytes, "film.bin"); }, 64 << 20);
  };
  auto has = [](const std::string& outcome, const char* text) { return outcome.find(text) != std::string::npos; };
  EXPECT_TRUE(has(with([](auto& b) { b[0] = std::byte{'X'}; }), "magic"));
  EXPECT_TRUE(has(with([](auto& b) { put<std::uint32_t>(b, 8, 2); }), "version 2"));
  EXPECT_TRUE(has(with([](auto& b) { put<std::uint32_t>(b, 12, 0x04030201); }), "byte order"));
  EXPECT_TRUE(has(with([](auto& b) { put<int>(b, 16, -1); }), "each side"));
  EXPECT_TRUE(has(with([](auto& b) { put<int>(b, 16, 65536), put<int>(b, 20, 65536); }), "limits"));
  EXPECT_TRUE(has(with([](auto& b) { put<std::uint64_t>(b, 24, ~std::uint64_t{0}); }), "limits"));
  EXPECT_TRUE(has(with([](auto& b) { put<int>(b, 16, 1000), put<int>(b, 20, 1000); }), "takes"));
  EXPECT_TRUE(has(with([](auto& b) { put<double>(b, 40, std::nan("")); }), "wavelength"));
  // Random damage anywhere in the header or the first wavelengths: an answer, never a crash.
  std::mt19937 rng(5);
  for (int i = 0; i < 2000; ++i) {
    auto bytes = good;
    bytes[rng() % 64] = static_cast<std::byte>(rng());
    const std::string outcome = deserialise_outcome(bytes);
    EXPECT_TRUE(outcome == "ok" || has(outcome, "film.bin: ")) << outcome;
  }
}

TEST(FilmMerge, RefusesOverlappingCameraSamplesAndOtherSizes) {
  FilmBuffer a(4, 3), b(4, 3), c(3, 4), d(4, 3, {500.0});
  a.add_sample(2, 1, {1, 1, 1}, 1.0);
  b.add_sample(2, 1, {1, 1, 1}, 1.0);
  EXPECT_THROW(a.merge(c), Error);
  EXPECT_THROW(a.merge(d), Error);
  try {
    a.merge(b);
    ADD_FAILURE() << "merged two films with samples in one pixel";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("pixel (2, 1)"), std::string::npos) << e.what();
  }
  // Splats only: any overlap, and the integer sums wrap as one process's atomic adds do.
  FilmBuffer e(4, 3), f(4, 3);
  e.add_splat(0.5, 0.5, {1.0, 2.0, 3.0});
  f.add_splat(0.5, 0.5, {4.0, 5.0, 6.0});
  e.merge(f);
  FilmBuffer g(4, 3);
  g.add_splat(0.5, 0.5, {1.0, 2.0, 3.0});
  g.add_splat(0.5, 0.5, {4.0, 5.0, 6.0});
  EXPECT_EQ(e.serialise(), g.serialise());
}

}  // namespace
}  // namespace bouguer
