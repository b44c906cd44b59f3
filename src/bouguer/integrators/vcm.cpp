// Vertex connection and merging (Georgiev, Křivánek, Davidovič, Slusallek 2012; Hachisuka,
// Pantaleoni, Jensen 2012 "unified path sampling"): bidirectional path tracing (bidirectional.h)
// and photon mapping in one estimator, weighted by the power heuristic over both families of
// strategies. It renders in iterations; iteration i (the sample index i of every pixel):
//   1. one light subpath per pixel of the whole image, traced from its own random stream and kept
//      for the iteration; every vertex where a path can merge (a non-specular surface, a medium)
//      becomes a photon, a record that points at its vertex;
//   2. the photons sorted into a grid of cells 2r wide, in an order that depends on nothing but
//      the paths (so neither the thread count nor the pixel region changes the sums);
//   3. per pixel of the region a camera subpath, connected to the kept light subpath of the same
//      pixel by every bidirectional strategy, and merged at each of its vertices with the photons
//      within r: surfaces by the disc πr², media by the ball 4/3·πr³.
// The radius shrinks as r_i = r_1·i^((α−1)/2), α = 0.75 (progressive photon mapping), so the
// estimator is consistent: its bias vanishes as iterations grow. r_1 is two pixel footprints at
// the camera's look-at distance unless the scene says (render.merge_radius).
//
// Spectral. Every path of an iteration carries the same wavelengths (the hero of hero mode, the
// wavelength kept at a dispersive interface, the hero that draws distances in media), so a photon
// from any pixel's light subpath meets a camera subpath at its own wavelengths. The wavelengths
// are stratified over the iterations instead of over a pixel's samples. (A camera subpath's tail,
// which no photon meets, splits into walks of one wavelength by its pixel's own strata.)
//
// MIS. One formulation for every strategy (bidirectional.h's mis_weight and merge_weight,
// Georgiev's recursion on the walk's area densities): the connections' weights count the merges
// too, and a merge's is the same sum written from the photon's side, whose light subpath is
// folded into one number in the photon record (Photon::sums), as SmallVCM's photons keep dVCM/dVM.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <numbers>
#include <span>
#include <tuple>
#include <unordered_map>

#include <fmt/format.h>

#include "bouguer/core/memory.h"
#include "bouguer/integrators/bidirectional.h"

namespace bouguer {
namespace {

using bidir::Bdpt;
using bidir::begin_sample;

constexpr std::uint64_t kCameraSalt = 6, kLightSalt = 7, kIterationSalt = 8;
constexpr double kAlpha = bidir::kVcmAlpha;

// A photon: a vertex of a light subpath where a path can merge. The vertex itself stays in the
// iteration's kept light subpaths (LightSubpaths), which the merges read through `vertex`; the
// record holds what the grid sorts and looks up by, and the subpath's folded MIS.
template <std::size_t N>
struct Photon {
  Vec3 point;
  const VertexCore<N>* vertex = nullptr;
  int medium = -1;    // a medium photon's medium, -1 on a surface
  double sums = 0.0;  // its subpath's folded MIS sum at the photon (Bdpt::subpath_sums)
  int index = 0;  // its place in the light subpath (≥ 1)
  std::uint32_t path = 0;
  std::uint64_t cell = 0;
};

// The light subpaths of an iteration, traced once: the photons point into them, and the camera
// pass connects each pixel's camera subpath to its own. A vertex is kept without its surface
// event (VertexCore: 1072 bytes in full mode against the whole vertex's 2000, 336 against 528 in
// hero; the merges read no event), and the camera pass builds the events of its pixel's subpath
// again (rebuilt_light_vertex, walk.h), from the same hit, nested set, direction, medium and
// wavelengths. Each tile's vertices are one array, found by the tile's first pixel, which the
// tile reuses over the iterations (fresh pages each iteration cost more than tracing the subpath
// again); each pixel's subpath is a span of its tile's.
template <std::size_t N>
struct LightSubpaths {
  std::unordered_map<std::uint64_t, std::vector<VertexCore<N>>> tiles;
  std::vector<std::span<const VertexCore<N>>> of_pixel;  // every pixel of the image
  std::size_t vertices = 0;
  // The memory they fill.
  std::uint64_t bytes() const { return vertices * sizeof(VertexCore<N>) + of_pixel.size() * sizeof(of_pixel[0]); }
};

// The grid cell of a point, packed: 21 bits per axis (neighbours never alias).
std::uint64_t cell_key(std::int64_t ix, std::int64_t iy, std::int64_t iz) {
  constexpr std::uint64_t m = (1u << 21) - 1;
  return ((static_cast<std::uint64_t>(ix) & m) << 42) | ((static_cast<std::uint64_t>(iy) & m) << 21) |
         (static_cast<std::uint64_t>(iz) & m);
}

// The photons of one iteration, sorted by cell, then by path and place: a lookup visits them in
// an order fixed by the paths alone.
template <std::size_t N>
class PhotonGrid {
 public:
  void build(std::vector<Photon<N>>&& photons, double radius_m) {
    photons_ = std::move(photons);
    radius_ = radius_m;
    cell_ = 2.0 * radius_m;
    for (Photon<N>& q : photons_) q.cell = key(q.point);
    std::sort(photons_.begin(), photons_.end(), [](const Photon<N>& a, const Photon<N>& b) {
      return std::tie(a.cell, a.path, a.index) < std::tie(b.cell, b.path, b.index);
    });
  }
  // visit(photon) for every photon within the radius of x.
  template <typename Visit>
  void around(const Vec3& x, Visit&& visit) const {
    if (photons_.empty()) return;
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = static_cast<std::int64_t>(std::floor((x[a] - radius_) / cell_));
      hi[a] = static_cast<std::int64_t>(std::floor((x[a] + radius_) / cell_));
    }
    const double r2 = radius_ * radius_;
    for (std::int64_t ix = lo[0]; ix <= hi[0]; ++ix)
      for (std::int64_t iy = lo[1]; iy <= hi[1]; ++iy)
        for (std::int64_t iz = lo[2]; iz <= hi[2]; ++iz) {
          const std::uint64_t k = cell_key(ix, iy, iz);
          auto first = std::lower_bound(photons_.begin(), photons_.end(), k,
                                        [](const Photon<N>& q, std::uint64_t c) { return q.cell < c; });
          for (; first != photons_.end() && first->cell == k; ++first) {
            const Vec3 d = first->point - x;
            if (dot(d, d) <= r2) visit(*first);
          }
        }
  }
  std::size_t size() const { return photons_.size(); }

 private:
  std::uint64_t key(const Vec3& p) const {
    return cell_key(static_cast<std::int64_t>(std::floor(p[0] / cell_)),
                    static_cast<std::int64_t>(std::floor(p[1] / cell_)),
                    static_cast<std::int64_t>(std::floor(p[2] / cell_)));
  }
  std::vector<Photon<N>> photons_;
  double radius_ = 0.0, cell_ = 1.0;
};

// What an iteration keeps: its light subpaths, and its photon lookup, the surface and the medium
// photons apart (kept by render over the iterations, so that each iteration reuses the last's
// storage).
template <std::size_t N>
struct IterationStore {
  LightSubpaths<N> light;
  PhotonGrid<N> surfaces, media;
};

template <std::size_t N>
Photon<N> make_photon(std::span<const Vertex<N>> lp, std::size_t j, const std::vector<double>& sums,
                      std::uint32_t path) {
  const Vertex<N>& x = lp[j];
  Photon<N> q;
  q.point = x.point;
  q.medium = x.kind == VertexKind::medium ? x.medium : -1;
  q.sums = sums[j];
  q.index = static_cast<int>(j);
  q.path = path;
  return q;
}

// The radius of iteration `it` (0-based): r_1·(it + 1)^((α − 1)/2).
double iteration_radius(double r1, int it) { return r1 * std::pow(static_cast<double>(it) + 1.0, 0.5 * (kAlpha - 1.0)); }

// One iteration of the estimator, in its stages: trace_light_subpaths (the photons),
// build_photon_lookup (the grids), camera_pass (per pixel: connections and merges) and merge (one
// camera vertex with the photons around it). Everything its paths share is fixed at construction;
// its light subpaths and photons go into `store`.
template <std::size_t N>
class Iteration {
 public:
  Iteration(const SceneView<N>& view, const RenderSettings& settings, int width, int height, int it, double r1,
            const WavelengthStrata& strata, const WavelengthStrata& heroes, IterationStore<N>& store)
      : view_(view), scene_(view.scene), settings_(settings), width_(width), height_(height), it_(it),
        w_(view.tables.wavelengths(0.0)), kept_(w_), store_(store) {
    // The iteration's wavelengths, hero, kept wavelength and σ̄_s, shared by all its paths.
    const bool hero = settings.spectral == SpectralMode::hero;
    Rng irng = sample_rng(settings.seed, 0, it, kIterationSalt);
    view.tables.restart(w_, hero ? strata.u(it) / static_cast<double>(N) : 0.0);
    // Every pixel of an iteration shares its hero, so a hero drawn at random tinted the whole
    // image (a chromatic medium's light went to the wavelengths near the heroes drawn); strata
    // over the iterations give each index its share.
    draw_hero(scene_, w_, heroes.u(it));
    const double dispersion_u = hero ? irng.next_double() : scene_.dispersive ? strata.u(it) : 0.0;
    kept_ = w_;
    keep_ = begin_sample(view, w_, dispersion_u, irng, sigma_mean_, kept_);
    media_ = WalkMedia{sigma_mean_};
    radius_m_ = iteration_radius(r1, it);
    merging_ = bidir::vcm_merging(radius_m_, static_cast<double>(width) * height);
  }
  Iteration(const Iteration&) = delete;  // media_ views sigma_mean_
  Iteration& operator=(const Iteration&) = delete;
  double radius_m() const { return radius_m_; }

  // 1. One light subpath per pixel of the whole image, from its own random stream, kept for the
  // camera pass's connections; its vertices where a path can merge become the photons (by tile,
  // as the threads made them).
  std::vector<std::vector<Photon<N>>> trace_light_subpaths(const RenderControl& control, RenderStats& stats) {
    LightSubpaths<N>& light = store_.light;
    light.vertices = 0;
    light.of_pixel.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), {});
    std::vector<std::vector<Photon<N>>> tiles_photons;
    std::mutex tiles_mutex;
    std::atomic<std::uint64_t> store_bytes{0};  // the arrays' capacity (for the message)
    for (const auto& [first_pixel, array] : light.tiles) store_bytes += array.capacity() * sizeof(VertexCore<N>);
    for_each_tile(PixelRegion{0, 0, width_, height_}, control, stats, [&](const PixelRegion& tile, std::uint64_t& rays) {
      std::vector<VertexCore<N>>* array = nullptr;
      {
        const std::lock_guard<std::mutex> lock(tiles_mutex);
        array = &light.tiles[pixel_index(tile.x0, tile.y0, width_)];
      }
      std::vector<VertexCore<N>>& vertices = *array;  // the tile's light subpaths, one after another
      vertices.clear();
      std::vector<Vertex<N>> traced;  // a subpath as the walk records it, events and all
      std::vector<Photon<N>> mine;
      struct Subpath {
        std::uint64_t pixel;
        std::size_t first, count;  // its vertices in `vertices`
      };
      std::vector<Subpath> subpaths;
      std::vector<double> sums;
      SampledWavelengths<N> wl = w_;
      for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
          const std::uint64_t pixel = pixel_index(x, y, width_);
          Rng lrng = sample_rng(settings_.seed, pixel, it_, kLightSalt);
          Bdpt<N> b = bdpt(wl, lrng, rays);
          // Room for a whole subpath, checked against the memory before the array grows.
          const std::size_t most = static_cast<std::size_t>(settings_.max_depth) + 1;
          if (vertices.capacity() - vertices.size() < most) {
            const std::size_t grown = std::max(2 * vertices.capacity(), vertices.size() + most);
            // The new array is whole before the old one goes.
            require_memory(grown * sizeof(VertexCore<N>),
                           fmt::format("{}: the store of light subpaths of iteration {} (past {} of them)",
                                       scene_.file.string(), it_ + 1, format_bytes(store_bytes.load())));
            store_bytes += (grown - vertices.capacity()) * sizeof(VertexCore<N>);
            vertices.reserve(grown);
          }
          const std::size_t first = vertices.size();
          traced.clear();
          const std::size_t n = b.append_light_subpath(traced, lrng);
          const std::span<const Vertex<N>> lp(traced.data(), n);
          vertices.insert(vertices.end(), lp.begin(), lp.end());  // (their cores)
          b.subpath_sums(lp, true, sums);
          for (std::size_t j = 1; j < n; ++j)
            if (Bdpt<N>::mergeable(lp[j]) && static_cast<int>(j) <= settings_.max_depth)
              mine.push_back(make_photon(lp, j, sums, static_cast<std::uint32_t>(pixel)));
          subpaths.push_back({pixel, first, n});
        }
      // `vertices` is whole: its addresses are final. A photon's vertex is its place in its path.
      for (const Subpath& p : subpaths)
        light.of_pixel[p.pixel] = std::span<const VertexCore<N>>(vertices.data() + p.first, p.count);
      for (Photon<N>& q : mine) q.vertex = &light.of_pixel[q.path][static_cast<std::size_t>(q.index)];
      const std::lock_guard<std::mutex> lock(tiles_mutex);
      light.vertices += vertices.size();
      tiles_photons.push_back(std::move(mine));
    });
    return tiles_photons;
  }

  // 2. The photons sorted into grids of cells 2r wide (surfaces and media apart), in an order
  // fixed by the paths alone.
  void build_photon_lookup(std::vector<std::vector<Photon<N>>>&& tiles_photons) {
    std::size_t count = 0;
    for (const auto& t : tiles_photons) count += t.size();
    require_memory(count * sizeof(Photon<N>) * 2,
                   fmt::format("{}: {} photons of iteration {}", scene_.file.string(), count, it_ + 1));
    std::vector<Photon<N>> on_surfaces, in_media;
    for (auto& t : tiles_photons)
      for (Photon<N>& q : t) (q.medium >= 0 ? in_media : on_surfaces).push_back(std::move(q));
    tiles_photons.clear();
    store_.surfaces.build(std::move(on_surfaces), radius_m_);
    store_.media.build(std::move(in_media), radius_m_);
  }
  std::size_t photons() const { return store_.surfaces.size() + store_.media.size(); }
  std::uint64_t light_subpath_bytes() const { return store_.light.bytes(); }

  // 3. Per pixel of the region a camera subpath, connected to the kept light subpath of the same
  // pixel by every bidirectional strategy, and merged at each of its vertices. Returns the merges
  // made.
  std::uint64_t camera_pass(PixelRegion region, const RenderControl& control, RenderStats& stats,
                            FilmBuffer& film) const {
    std::atomic<std::uint64_t> merges{0};
    for_each_tile(region, control, stats, [&](const PixelRegion& tile, std::uint64_t& rays) {
      std::uint64_t merged = 0;
      std::vector<Vertex<N>> camera_path, light_path;
      SampledWavelengths<N> wc = w_;
      for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
          const std::uint64_t pixel = pixel_index(x, y, width_);
          Rng rng = sample_rng(settings_.seed, pixel, it_, kCameraSalt);
          // The bins of the camera tail's splits (bidirectional.h), the pixel's own: no photon
          // meets a tail, so they need not be the iteration's.
          if (scene_.scatters) {
            WavelengthStrata splits;
            splits.reset(settings_.seed, pixel, settings_.spp, kSplitStrataSalt);
            wc.split_u = splits.u(it_);
          }
          Bdpt<N> b = bdpt(wc, rng, rays);
          const auto [u, v] = subpixel(it_, settings_.spp, settings_.seed, pixel, rng);
          b.camera_subpath(view_.camera.generate_ray(x + u, y + v), camera_path, &keep_);
          light_path.clear();
          for (const VertexCore<N>& core : store_.light.of_pixel[pixel])
            light_path.push_back(rebuilt_light_vertex(view_, core, w_, kept_));
          SampledSpectrum<N> l = b.connect_all(light_path, camera_path, film, keep_) + b.camera_tail();
          for (int t = 2; t <= static_cast<int>(camera_path.size()); ++t) merge(b, camera_path, t, wc, l, merged);
          add_camera_sample(film, view_.tables, wc, x, y, it_, l);
        }
      merges += merged;
    });
    return merges.load();
  }

  // 4. Camera vertex camera[t − 1] merged with the photons within r: surfaces by the disc πr²,
  // media by the ball 4/3·πr³, each merge weighted by Bdpt::merge_weight, added to l.
  void merge(const Bdpt<N>& b, const std::vector<Vertex<N>>& camera, int t, const SampledWavelengths<N>& wc,
             SampledSpectrum<N>& l, std::uint64_t& merged) const {
    const Vertex<N>& pt = camera[static_cast<std::size_t>(t - 1)];
    if (!Bdpt<N>::mergeable(pt)) return;
    const bool in_medium = pt.kind == VertexKind::medium;
    SampledSpectrum<N> sigma_s;  // a medium vertex: σ_s(x) at the carried wavelengths
    if (in_medium) {
      const ScatteringMedium& sm = *scattering_medium(scene_, pt.medium);
      sigma_s = view_.tables.at(sm.sigma_s, wc) * static_cast<float>(concentration_at(sm.density, pt.point));
    }
    const double norm = 1.0 / (in_medium ? merging_.eta_medium : merging_.eta_surface);
    auto one = [&](const Photon<N>& photon) {
      if (photon.index + t - 2 > settings_.max_depth) return;
      if (in_medium && photon.medium != pt.medium) return;
      const VertexCore<N>& q = *photon.vertex;
      SampledSpectrum<N> f;
      if (in_medium) {
        const float phase = static_cast<float>(phase_value(scattering_medium(scene_, pt.medium)->phase, -pt.wo, q.wo));
        for (std::size_t k = 0; k < N; ++k) f[k] = sigma_s[k] > 0.0f ? phase / sigma_s[k] : 0.0f;
        f *= static_cast<float>(norm);
      } else {
        if (dot(q.normal, pt.normal) <= 0.0) return;
        // f·|cos θi| over the geometric cosine the photons' flux density is per (events.h).
        const double cos_i = std::abs(dot(q.wo, pt.event.ng));
        if (!(cos_i > 1e-8)) return;
        f = b.f(pt, q.wo, TransportMode::radiance) * static_cast<float>(norm / cos_i);
      }
      const SampledSpectrum<N> c =
          pt.beta * f * q.beta * ((pt.dispersed || q.dispersed) ? keep_ : SampledSpectrum<N>::constant(1.0f));
      if (c.is_zero()) return;
      ++merged;
      l += c * static_cast<float>(b.merge_weight(camera, t, q, *(photon.vertex - 1), photon.sums) / mean_ratio(scene_, pt.r_u * q.r_u));
    };
    (in_medium ? store_.media : store_.surfaces).around(pt.point, one);
  }

 private:
  Bdpt<N> bdpt(SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays) const {
    Bdpt<N> b(view_, media_, w, scene_.dispersive ? &kept_ : nullptr, rng, rays);
    b.set_merging(merging_);
    return b;
  }

  const SceneView<N>& view_;
  const RenderScene& scene_;
  const RenderSettings& settings_;
  int width_, height_, it_;
  SampledWavelengths<N> w_, kept_;
  SampledSpectrum<N> keep_;
  std::vector<double> sigma_mean_;
  WalkMedia media_;
  double radius_m_ = 0.0;
  bidir::Merging merging_;
  IterationStore<N>& store_;
};

template <std::size_t N>
void render(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
            SampleRange range, const RenderControl& control, RenderStats& stats) {
  const SpectralTables<N> tables(scene.spectra, settings.spectral);
  const Camera camera(scene.camera);
  const SceneView<N> view{scene, tables, camera, settings.max_depth, exit_guide_enabled(settings, scene)};
  const double r1 = bidir::vcm_initial_radius(scene, settings);
  WavelengthStrata strata, heroes;
  strata.reset(settings.seed, ~std::uint64_t{0}, settings.spp);
  heroes.reset(settings.seed, ~std::uint64_t{0}, settings.spp, kHeroStrataSalt);
  const int iterations = range.end - range.begin;
  IterationStore<N> store;
  for (int it = range.begin; it < range.end; ++it) {
    if (control.cancel && control.cancel->load()) return;
    // Each iteration's two halves report progress: the light subpaths, then the camera pass.
    auto half = [&](int k) {
      RenderControl c{control.threads, control.cancel, {}};
      if (control.progress) {
        const double done = static_cast<double>(it - range.begin) + 0.5 * k;
        c.progress = [&, done](double f) { control.progress((done + 0.5 * f) / iterations); };
      }
      return c;
    };
    Iteration<N> iteration(view, settings, film.width(), film.height(), it, r1, strata, heroes, store);
    auto photons = iteration.trace_light_subpaths(half(0), stats);
    // Ctrl-C: the image keeps whole iterations only; the progress says how many, which the film's
    // splat normalisation reads.
    if (control.cancel && control.cancel->load()) {
      if (control.progress) control.progress(static_cast<double>(it - range.begin) / iterations);
      return;
    }
    iteration.build_photon_lookup(std::move(photons));
    // An iteration begun is finished: its camera pass is not cancelled.
    RenderControl camera_control = half(1);
    camera_control.cancel = nullptr;
    const std::uint64_t merges = iteration.camera_pass(region, camera_control, stats, film);
    ++stats.iterations;
    stats.light_paths += static_cast<std::uint64_t>(film.width()) * static_cast<std::uint64_t>(film.height());
    stats.photons += iteration.photons();
    stats.light_subpath_bytes = std::max(stats.light_subpath_bytes, iteration.light_subpath_bytes());
    stats.merges += merges;
    stats.radius_m = iteration.radius_m();
  }
}

}  // namespace

namespace bidir {

// r_1: the scene's, or two pixel footprints at the distance of the camera's look-at point (a cap
// by the scene's size, as SmallVCM's 0.3 % of its radius, starves small images of photons: the
// merges then are rare and heavy-tailed).
double vcm_initial_radius(const RenderScene& scene, const RenderSettings& settings) {
  if (settings.merge_radius_m > 0.0) return settings.merge_radius_m;
  const CameraDesc& c = scene.camera;
  const double pixels = std::min(c.width_px, c.height_px);
  const double footprint = c.type == CameraType::orthographic
                               ? c.width_m / pixels
                               : 2.0 * std::tan(0.5 * c.fov_deg * std::numbers::pi / 180.0) *
                                     length(c.look_at_m - c.position_m) / pixels;
  return 2.0 * footprint;
}

Merging vcm_merging(double r, double light_paths) {
  return {light_paths * std::numbers::pi * r * r, light_paths * 4.0 / 3.0 * std::numbers::pi * r * r * r};
}

Merging vcm_merging(const RenderScene& scene, const RenderSettings& settings, int iteration) {
  return vcm_merging(iteration_radius(vcm_initial_radius(scene, settings), iteration),
                     static_cast<double>(scene.camera.width_px) * scene.camera.height_px);
}

}  // namespace bidir

void render_vcm(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    render<N>(scene, settings, film, region, range, control, stats);
  });
}

}  // namespace bouguer
