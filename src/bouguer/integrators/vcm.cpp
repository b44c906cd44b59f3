// Vertex connection and merging (Georgiev, Křivánek, Davidovič, Slusallek 2012; Hachisuka,
// Pantaleoni, Jensen 2012 "unified path sampling"): bidirectional path tracing (bidirectional.h)
// and photon mapping in one estimator, weighted by the power heuristic over both families of
// strategies. It renders in iterations; iteration i (the sample index i of every pixel):
//   1. one light subpath per pixel of the whole image, traced from its own random stream; every
//      vertex where a path can merge (a non-specular surface, a medium) becomes a photon;
//   2. the photons sorted into a grid of cells 2r wide, in an order that depends on nothing but
//      the paths (so neither the thread count nor the pixel region changes the sums);
//   3. per pixel of the region a camera subpath, connected to the light subpath of the same pixel
//      (traced again from the same stream) by every bidirectional strategy, and merged at each of
//      its vertices with the photons within r: surfaces by the disc πr², media by the ball 4/3·πr³.
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
// MIS. The weights are those of the connections (bidirectional.h's mis_weight, with the merging
// terms on) and, for a merge, the same sum written from the photon's side: what it needs of the
// light subpath behind it (the light strategies' sum B, its predecessor's place and densities) is
// kept in the photon record, as Georgiev's recursive dVCM/dVM quantities keep it.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <numbers>
#include <tuple>

#include <fmt/format.h>

#include "bouguer/core/memory.h"
#include "bouguer/integrators/bidirectional.h"

namespace bouguer {
namespace {

using bidir::Bdpt;
using bidir::begin_sample;
using bidir::is_delta_light;
using bidir::sq;

constexpr std::uint64_t kCameraSalt = 6, kLightSalt = 7, kIterationSalt = 8;
constexpr double kAlpha = 0.75;

double remap0(double p) { return p != 0.0 ? p : 1.0; }

// What a merge needs of the light vertex before the photon: where it is (for the density of
// sampling it from the merge point) and the density with which the light subpath made it.
struct Predecessor {
  Vec3 point, normal;
  VertexKind kind = VertexKind::light;
  double sigma_rho = 0.0;
  bool infinite = false;
  double pdf_fwd = 0.0;
  bool delta = false;
  bool on_surface() const { return normal != Vec3{}; }
};

template <std::size_t N>
struct Photon {
  Vec3 point, normal;  // normal: zero at a medium photon
  Vec3 wo;             // unit, towards the predecessor
  int medium = -1;     // a medium photon's medium
  SampledSpectrum<N> beta, r_u;
  double pdf_fwd = 0.0;  // the light subpath's density of this vertex
  double b = 0.0;        // the light strategies' weight sum behind it (B_j, see light_sums)
  double tau_in = 0.0;
  Predecessor prev;
  bool dispersed = false;
  int index = 0;  // its place in the light subpath (≥ 1)
  std::uint32_t path = 0;
  std::uint64_t cell = 0;
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

// B_j for every vertex j ≥ 1 of a light subpath: the sum, over the strategies that hold vertices
// 0 … j−1 on the light side, of their squared density ratios to the connection (s = j), but for
// the factor (p_rev/p_fwd)² of vertex j − 1, which depends on the camera subpath the photon
// meets. B_1 = T_0, B_j = T_{j−1} + (p_rev/p_fwd)²_{j−2}·B_{j−1}, T_i the strategies at vertex i:
// the connection before it (s = i) and merging at it.
template <std::size_t N>
void light_sums(const Bdpt<N>& b, const RenderScene& scene, const std::vector<Vertex<N>>& lp,
                std::vector<double>& sums) {
  sums.assign(lp.size(), 0.0);
  auto strategies_at = [&](std::size_t i) {
    const Vertex<N>& x = lp[i];
    const bool delta_before = i > 0 ? lp[i - 1].delta : is_delta_light(scene.lights[static_cast<std::size_t>(lp[0].light)]);
    double t = !x.delta && !delta_before ? 1.0 : 0.0;
    if (i > 0 && Bdpt<N>::mergeable(x)) t += sq(x.pdf_fwd * b.eta(x));
    return t;
  };
  for (std::size_t j = 1; j < lp.size(); ++j)
    sums[j] = strategies_at(j - 1) +
              (j >= 2 ? sq(remap0(lp[j - 2].pdf_rev) / remap0(lp[j - 2].pdf_fwd)) * sums[j - 1] : 0.0);
}

template <std::size_t N>
Photon<N> make_photon(const std::vector<Vertex<N>>& lp, std::size_t j, double b, std::uint32_t path) {
  const Vertex<N>& x = lp[j];
  const Vertex<N>& p = lp[j - 1];
  Photon<N> q;
  q.point = x.point;
  q.normal = x.normal;
  q.wo = x.wo;
  q.medium = x.kind == VertexKind::medium ? x.medium : -1;
  q.beta = x.beta;
  q.r_u = x.r_u;
  q.pdf_fwd = x.pdf_fwd;
  q.b = b;
  q.tau_in = x.tau_in;
  q.prev = {p.point, p.normal, p.kind, p.sigma_rho, p.infinite, p.pdf_fwd, p.delta};
  q.dispersed = x.dispersed;
  q.index = static_cast<int>(j);
  q.path = path;
  return q;
}

// The density with which camera vertex x, reached along x.wo, samples direction wi (solid angle);
// `reverse`: x reached along wi, sampling x.wo.
template <std::size_t N>
double direction_pdf(const RenderScene& scene, const Vertex<N>& x, const Vec3& wi, bool reverse) {
  const Vec3 a = reverse ? wi : x.wo, b = reverse ? x.wo : wi;
  if (x.kind == VertexKind::medium) return phase_value(scattering_medium(scene, x.medium)->phase, -a, b);
  return x.event.pdf(a, b);
}

// The MIS weight of merging camera vertex camera[t − 1] with photon q: the merge's squared
// density over the sum of all strategies for the same path, relative to the connection of q's
// predecessor with the camera vertex (s = q.index, t).
template <std::size_t N>
double merge_weight(const Bdpt<N>& b, const RenderScene& scene, const std::vector<Vertex<N>>& camera, int t,
                    const Photon<N>& q) {
  const Vertex<N>& pt = camera[static_cast<std::size_t>(t - 1)];
  const double rev_prev = to_area_density(direction_pdf(scene, pt, q.wo, false), pt.point, q.prev, q.tau_in);
  const double c = remap0(rev_prev) / remap0(q.prev.pdf_fwd);
  double sum = (q.prev.delta ? 0.0 : 1.0) + c * c * q.b;
  const double rev_before =
      t >= 3 ? to_area_density(direction_pdf(scene, pt, q.wo, true), pt.point, camera[static_cast<std::size_t>(t - 2)],
                               pt.tau_in)
             : 0.0;
  const double own = sq(q.pdf_fwd * b.eta(pt));
  double ri = 1.0;
  for (int i = t - 1; i > 0; --i) {
    const Vertex<N>& x = camera[static_cast<std::size_t>(i)];
    const double rev = i == t - 1 ? q.pdf_fwd : i == t - 2 ? rev_before : x.pdf_rev;
    if (Bdpt<N>::mergeable(x)) sum += sq(ri * rev * b.eta(x));
    ri *= remap0(rev) / remap0(x.pdf_fwd);
    if (!x.delta && !camera[static_cast<std::size_t>(i - 1)].delta) sum += ri * ri;
  }
  return sum > 0.0 ? own / sum : 0.0;
}

// r_1: the scene's, or two pixel footprints at the distance of the camera's look-at point (a cap
// by the scene's size, as SmallVCM's 0.3 % of its radius, starves small images of photons: the
// merges then are rare and heavy-tailed).
double initial_radius(const RenderScene& scene, const RenderSettings& settings) {
  if (settings.merge_radius_m > 0.0) return settings.merge_radius_m;
  const CameraDesc& c = scene.camera;
  const double pixels = std::min(c.width_px, c.height_px);
  const double footprint = c.type == CameraType::orthographic
                               ? c.width_m / pixels
                               : 2.0 * std::tan(0.5 * c.fov_deg * std::numbers::pi / 180.0) *
                                     length(c.look_at_m - c.position_m) / pixels;
  return 2.0 * footprint;
}

// The merging strategies' η of an iteration with radius r over `light_paths` light subpaths.
bidir::Merging merging_at(double r, double light_paths) {
  return {light_paths * std::numbers::pi * r * r, light_paths * 4.0 / 3.0 * std::numbers::pi * r * r * r};
}

// The radius of iteration `it` (0-based): r_1·(it + 1)^((α − 1)/2).
double iteration_radius(double r1, int it) { return r1 * std::pow(static_cast<double>(it) + 1.0, 0.5 * (kAlpha - 1.0)); }

template <std::size_t N>
void render(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
            SampleRange range, const RenderControl& control, RenderStats& stats) {
  const SpectralTables<N> tables(scene.spectra, settings.spectral);
  const Camera camera(scene.camera);
  const SceneView<N> view{scene, tables, camera, settings.max_depth, exit_guide_enabled(settings, scene)};
  const int width = film.width(), height = film.height();
  const double light_paths = static_cast<double>(width) * height;
  const double r1 = initial_radius(scene, settings);
  const bool hero = settings.spectral == SpectralMode::hero;
  const bool stratify = hero || scene.dispersive;
  WavelengthStrata strata, heroes;
  strata.reset(settings.seed, ~std::uint64_t{0}, settings.spp);
  heroes.reset(settings.seed, ~std::uint64_t{0}, settings.spp, kHeroStrataSalt);
  const int iterations = range.end - range.begin;
  PhotonGrid<N> surface_grid, medium_grid;
  for (int it = range.begin; it < range.end; ++it) {
    if (control.cancel && control.cancel->load()) return;
    // The iteration's wavelengths, hero, kept wavelength and σ̄_s, shared by all its paths.
    Rng irng = sample_rng(settings.seed, 0, it, kIterationSalt);
    SampledWavelengths<N> w = tables.wavelengths(0.0);
    tables.restart(w, hero ? strata.u(it) / static_cast<double>(N) : 0.0);
    // Every pixel of an iteration shares its hero, so a hero drawn at random tinted the whole
    // image (a chromatic medium's light went to the wavelengths near the heroes drawn); strata
    // over the iterations give each index its share.
    draw_hero(scene, w, heroes.u(it));
    const double dispersion_u = hero ? irng.next_double() : stratify ? strata.u(it) : 0.0;
    std::vector<double> sigma_mean;
    SampledWavelengths<N> kept = w;
    const SampledSpectrum<N> keep = begin_sample(view, w, dispersion_u, irng, sigma_mean, kept);
    const WalkMedia media{sigma_mean};
    const double r = iteration_radius(r1, it);
    const bidir::Merging merging = merging_at(r, light_paths);
    const SampledWavelengths<N>* kept_ptr = scene.dispersive ? &kept : nullptr;
    auto stage = [&](int k) {
      RenderControl c{control.threads, control.cancel, {}};
      if (control.progress) {
        const double done = static_cast<double>(it - range.begin) + 0.5 * k;
        c.progress = [&, done](double f) { control.progress((done + 0.5 * f) / iterations); };
      }
      return c;
    };

    // 1. The photons: every pixel's light subpath.
    std::vector<std::vector<Photon<N>>> tiles_photons;
    std::mutex tiles_mutex;
    for_each_tile(PixelRegion{0, 0, width, height}, stage(0), stats, [&](const PixelRegion& tile, std::uint64_t& rays) {
      // (Cancelled here, the iteration is dropped whole below.)
      std::vector<Photon<N>> mine;
      std::vector<Vertex<N>> lp;
      std::vector<double> sums;
      SampledWavelengths<N> wl = w;
      for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
          const auto pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(width) + static_cast<std::uint64_t>(x);
          Rng lrng = sample_rng(settings.seed, pixel, it, kLightSalt);
          Bdpt<N> b(view, media, wl, kept_ptr, lrng, rays);
          b.set_merging(merging);
          b.light_subpath(lp, lrng);
          light_sums(b, scene, lp, sums);
          for (std::size_t j = 1; j < lp.size(); ++j)
            if (Bdpt<N>::mergeable(lp[j]) && static_cast<int>(j) <= settings.max_depth)
              mine.push_back(make_photon(lp, j, sums[j], static_cast<std::uint32_t>(pixel)));
        }
      const std::lock_guard<std::mutex> lock(tiles_mutex);
      tiles_photons.push_back(std::move(mine));
    });
    // Ctrl-C: the image keeps whole iterations only; the progress says how many, which the film's
    // splat normalisation reads.
    if (control.cancel && control.cancel->load()) {
      if (control.progress) control.progress(static_cast<double>(it - range.begin) / iterations);
      return;
    }
    std::size_t count = 0;
    for (const auto& t : tiles_photons) count += t.size();
    require_memory(count * sizeof(Photon<N>) * 2,
                   fmt::format("{}: {} photons of iteration {}", scene.file.string(), count, it + 1));
    std::vector<Photon<N>> on_surfaces, in_media;
    for (auto& t : tiles_photons)
      for (Photon<N>& q : t) (q.medium >= 0 ? in_media : on_surfaces).push_back(std::move(q));
    tiles_photons.clear();
    surface_grid.build(std::move(on_surfaces), r);
    medium_grid.build(std::move(in_media), r);

    // 2. The camera subpaths of the region: connections and merges (not cancelled: an iteration
    // begun is finished).
    const double norm_surface = 1.0 / merging.eta_surface, norm_medium = 1.0 / merging.eta_medium;
    RenderControl camera_control = stage(1);
    camera_control.cancel = nullptr;
    std::atomic<std::uint64_t> merges{0};
    for_each_tile(region, camera_control, stats, [&](const PixelRegion& tile, std::uint64_t& rays) {
      std::uint64_t merged = 0;
      std::vector<Vertex<N>> camera_path, light_path;
      SampledWavelengths<N> wc = w;
      for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
          const auto pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(width) + static_cast<std::uint64_t>(x);
          Rng rng = sample_rng(settings.seed, pixel, it, kCameraSalt);
          // The bins of the camera tail's splits (bidirectional.h), the pixel's own: no photon
          // meets a tail, so they need not be the iteration's.
          if (scene.scatters) {
            WavelengthStrata splits;
            splits.reset(settings.seed, pixel, settings.spp, kSplitStrataSalt);
            wc.split_u = splits.u(it);
          }
          Rng lrng = sample_rng(settings.seed, pixel, it, kLightSalt);
          Bdpt<N> b(view, media, wc, kept_ptr, rng, rays);
          b.set_merging(merging);
          const auto [u, v] = subpixel(it, settings.spp, rng);
          b.camera_subpath(camera.generate_ray(x + u, y + v), camera_path, &keep);
          b.light_subpath(light_path, lrng);
          SampledSpectrum<N> l = b.connect_all(light_path, camera_path, film, keep) + b.camera_tail();
          const int nc = static_cast<int>(camera_path.size());
          for (int t = 2; t <= nc; ++t) {
            const Vertex<N>& pt = camera_path[static_cast<std::size_t>(t - 1)];
            if (!Bdpt<N>::mergeable(pt)) continue;
            const bool in_medium = pt.kind == VertexKind::medium;
            SampledSpectrum<N> sigma_s;  // a medium vertex: σ_s(x) at the carried wavelengths
            if (in_medium) {
              const ScatteringMedium& sm = *scattering_medium(scene, pt.medium);
              sigma_s = tables.at(sm.sigma_s, wc) * static_cast<float>(concentration_at(sm.density, pt.point));
            }
            auto merge = [&](const Photon<N>& q) {
              if (q.index + t - 2 > settings.max_depth) return;
              SampledSpectrum<N> f;
              if (in_medium) {
                if (q.medium != pt.medium) return;
                const float phase =
                    static_cast<float>(phase_value(scattering_medium(scene, pt.medium)->phase, -pt.wo, q.wo));
                for (std::size_t k = 0; k < N; ++k) f[k] = sigma_s[k] > 0.0f ? phase / sigma_s[k] : 0.0f;
                f *= static_cast<float>(norm_medium);
              } else {
                if (dot(q.normal, pt.normal) <= 0.0) return;
                // f·|cos θi| over the geometric cosine the photons' flux density is per (events.h).
                const double cos_i = std::abs(dot(q.wo, pt.event.ng));
                if (!(cos_i > 1e-8)) return;
                f = b.f(pt, q.wo, TransportMode::radiance) * static_cast<float>(norm_surface / cos_i);
              }
              const SampledSpectrum<N> c =
                  pt.beta * f * q.beta * ((pt.dispersed || q.dispersed) ? keep : SampledSpectrum<N>::constant(1.0f));
              if (c.is_zero()) return;
              ++merged;
              l += c * static_cast<float>(merge_weight(b, scene, camera_path, t, q) /
                                          mean_ratio(scene, pt.r_u * q.r_u));
            };
            (in_medium ? medium_grid : surface_grid).around(pt.point, merge);
          }
          add_camera_sample(film, tables, wc, x, y, l);
        }
      merges += merged;
    });
    ++stats.iterations;
    stats.light_paths += static_cast<std::uint64_t>(light_paths);
    stats.photons += count;
    stats.merges += merges.load();
    stats.radius_m = r;
  }
}

}  // namespace

BdptMisCheck vcm_mis_check(const RenderScene& scene, const RenderSettings& settings, int x, int y, int sample) {
  BdptMisCheck out;
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    const double r = iteration_radius(initial_radius(scene, settings), sample);
    const bidir::Merging merging =
        merging_at(r, static_cast<double>(scene.camera.width_px) * scene.camera.height_px);
    std::vector<double> sums;
    bidir::mis_check<N>(
        scene, settings, x, y, sample, merging,
        [&](const Bdpt<N>& b, const std::vector<Vertex<N>>& light, const std::vector<Vertex<N>>& camera) {
          light_sums(b, scene, light, sums);
          const std::size_t k = light.size() - 1;
          return merge_weight(b, scene, camera, static_cast<int>(camera.size()), make_photon(light, k, sums[k], 0));
        },
        out);
  });
  return out;
}

void render_vcm(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    render<N>(scene, settings, film, region, range, control, stats);
  });
}

}  // namespace bouguer
