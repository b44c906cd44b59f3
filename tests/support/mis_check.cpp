// The MIS check of the bidirectional estimators (mis_check.h): every full path of one camera
// sample cut at every place, each cut's weight recomputed from the geometry.
#include "support/mis_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bouguer/integrators/bidirectional.h"

namespace bouguer {
namespace {

using bidir::Bdpt;

// Every strategy that could have made the full path light[0, s) + camera[t, 0): its subpaths cut
// at each place, the densities of every vertex recomputed from the geometry in both directions,
// and the MIS weights summed, merges included where `bdpt` merges. Also the largest difference
// between the weight the renderer gave the original split (from the walk's own records) and the
// recomputed one.
// (A path a merge makes: renderer_weight NaN, none compared; the count of connections that could
// make it goes to `connections`.)
template <std::size_t N>
void check_path(Bdpt<N>& bdpt, const RenderScene& scene, const std::vector<Vertex<N>>& light,
                const std::vector<Vertex<N>>& camera, int s, int t, double tau_connection, double renderer_weight,
                BdptMisCheck& out, int* connections = nullptr) {
  std::vector<Vertex<N>> full(light.begin(), light.begin() + s);
  for (int j = t - 1; j >= 0; --j) full.push_back(camera[static_cast<std::size_t>(j)]);
  const int n = s + t;
  // tau[i]: the segment between full[i] and full[i + 1].
  std::vector<double> tau(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i + 1 < n; ++i)
    tau[static_cast<std::size_t>(i)] = i + 1 < s ? full[static_cast<std::size_t>(i + 1)].tau_in
                                       : i + 1 == s ? tau_connection
                                                    : full[static_cast<std::size_t>(i)].tau_in;
  auto at = [&](int i) -> const Vertex<N>& { return full[static_cast<std::size_t>(i)]; };
  std::vector<double> p_light(static_cast<std::size_t>(n)), p_camera(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    p_light[k] = i == 0 ? bdpt.pdf_light_origin(at(0))
                        : bdpt.pdf_at(at(i - 1), i >= 2 ? &at(i - 2) : nullptr, at(i), tau[k - 1]);
    p_camera[k] = i == n - 1 ? 1.0 : bdpt.pdf_at(at(i + 1), i + 2 < n ? &at(i + 2) : nullptr, at(i), tau[k]);
  }
  // The full path cut before vertex s2: its light subpath [0, s2) and camera subpath (n − 1 … s2],
  // their densities recomputed; `upto` (merging) keeps vertex s2 on both sides.
  std::vector<Vertex<N>> l2, c2;
  // A vertex's wo points along its subpath, which depends on the cut.
  auto towards = [&](int i, int j) { return at(j).infinite ? at(j).light_dir : normalize(at(j).point - at(i).point); };
  auto split = [&](int s2, bool upto) {
    l2.clear();
    c2.clear();
    for (int i = 0; i < s2 + (upto ? 1 : 0); ++i) {
      Vertex<N> x = at(i);
      x.pdf_fwd = p_light[static_cast<std::size_t>(i)];
      x.pdf_rev = p_camera[static_cast<std::size_t>(i)];
      x.tau_in = i > 0 ? tau[static_cast<std::size_t>(i - 1)] : 0.0;
      if (i > 0) x.wo = towards(i, i - 1);
      l2.push_back(x);
    }
    for (int i = n - 1; i >= s2; --i) {
      Vertex<N> x = at(i);
      x.pdf_fwd = p_camera[static_cast<std::size_t>(i)];
      x.pdf_rev = p_light[static_cast<std::size_t>(i)];
      x.tau_in = i < n - 1 ? tau[static_cast<std::size_t>(i)] : 0.0;
      if (i < n - 1) x.wo = towards(i, i + 1);
      c2.push_back(x);
    }
    if (l2.empty()) l2.emplace_back();  // the slot of s = 1's own light sample, as connect_all's
    bdpt.fold_mis(l2, c2);
  };
  double sum = 0.0;
  for (int s2 = 0; s2 < n; ++s2) {
    const int t2 = n - s2;
    if (s2 == 0 && (t2 < 2 || bidir::is_delta_light(scene.lights[static_cast<std::size_t>(at(0).light)]))) continue;
    if (s2 >= 1 && !at(s2 - 1).connectible()) continue;
    if (!at(s2).connectible() || (s2 == 1 && t2 == 1)) continue;
    split(s2, false);
    const double w = bdpt.mis_weight(l2, c2, nullptr, s2, t2, s2 > 0 ? tau[static_cast<std::size_t>(s2 - 1)] : 0.0);
    sum += w;
    if (connections) ++*connections;
    if (s2 == s && !std::isnan(renderer_weight))
      out.max_weight_difference = std::max(out.max_weight_difference, std::abs(w - renderer_weight));
  }
  if (bdpt.merges()) {
    std::vector<double> sums;
    for (int k = 1; k + 1 < n; ++k)
      if (Bdpt<N>::mergeable(at(k))) {
        split(k, true);
        bdpt.subpath_sums(l2, true, sums);
        const auto q = static_cast<std::size_t>(k);
        sum += bdpt.merge_weight(c2, static_cast<int>(c2.size()), l2[q], l2[q - 1], sums[q]);
      }
  }
  out.sums.push_back(sum);
}

// The check of one camera sample's subpaths: `merging` sets the merging strategies' η.
template <std::size_t N>
void mis_check(const RenderScene& scene, const RenderSettings& settings, int x, int y, int sample,
               const bidir::Merging& merging, BdptMisCheck& out) {
  const SpectralTables<N> tables(scene.spectra, settings.spectral);
  const Camera camera(scene.camera);
  const SceneView<N> view{scene, tables, camera, settings.max_depth, exit_guide_enabled(settings, scene)};
  const auto pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(scene.camera.width_px) +
                     static_cast<std::uint64_t>(x);
  Rng rng = sample_rng(settings.seed, pixel, sample, 2);
  SampledWavelengths<N> w = tables.wavelengths(0.0);
  tables.restart(w, 0.0);
  std::vector<double> sigma_mean;
  SampledWavelengths<N> kept = w;
  draw_hero(scene, w, rng);
  bidir::begin_sample(view, w, rng.next_double(), rng, sigma_mean, kept);
  const WalkMedia media{sigma_mean};
  std::uint64_t rays = 0;
  Bdpt<N> bdpt(view, media, w, scene.dispersive ? &kept : nullptr, rng, rays);
  bdpt.set_merging(merging);
  std::vector<Vertex<N>> camera_path, light_path, lens_path;
  const auto [u, v] = subpixel(sample, settings.spp, settings.seed, pixel, rng);
  bdpt.camera_subpath(camera.generate_ray(x + u, y + v), camera_path, nullptr);
  bdpt.light_subpath(light_path);
  const int nc = static_cast<int>(camera_path.size()), nl = static_cast<int>(light_path.size());
  for (int t = 1; t <= nc; ++t)
    for (int s = 0; s <= nl; ++s) {
      if (s == 1 || s + t < 3) continue;  // s = 1 draws its own light; (0, 2) and (1, 1) are alone
      const Vertex<N>& pt = camera_path[static_cast<std::size_t>(t - 1)];
      if (s == 0 && pt.kind != VertexKind::light) continue;
      const Vertex<N>* qs = s > 0 ? &light_path[static_cast<std::size_t>(s - 1)] : nullptr;
      if (qs && (pt.kind == VertexKind::light || !pt.connectible() || !qs->connectible())) continue;
      // The connection as the renderer makes it (Bdpt::connect): to the lens for t = 1, its
      // scattering depth from transmission(), through the media and index-matched crossings.
      Vertex<N> lens;
      const Vertex<N>* sampled = nullptr;
      double tau = 0.0;
      if (qs && t == 1) {
        const auto c = camera.connect(qs->point);
        if (!c) continue;
        lens.kind = VertexKind::camera;
        lens.point = qs->point + c->wi * c->distance_m;
        lens.pdf_fwd = 1.0;
        sampled = &lens;
        const auto tr = transmission(view, vertex_at(*qs), c->wi, c->distance_m,
                                     vertex_medium_towards(*qs, c->wi), w, rng, rays, media.sigma_mean);
        if (!tr) continue;
        tau = tr->tau;
        if (tau > 0.0) ++out.lens_through_media;
      } else if (qs) {
        const Vec3 d = qs->point - pt.point;
        const double length_m = std::sqrt(dot(d, d));
        if (!(length_m > 0.0)) continue;
        const Vec3 wi = d / length_m;
        const auto tr = transmission(view, vertex_at(pt), wi, length_m, vertex_medium_towards(pt, wi), w, rng,
                                     rays, media.sigma_mean);
        if (!tr) continue;
        tau = tr->tau;
      }
      bdpt.fold_mis(light_path, camera_path);
      const double w_render = bdpt.mis_weight(light_path, camera_path, sampled, s, t, tau);
      lens_path = camera_path;
      if (sampled) lens_path[0] = lens;
      check_path(bdpt, scene, light_path, lens_path, s, t, tau, w_render, out);
    }
  // The paths merges make: light vertex j (a photon) standing in for camera vertex t − 1 where both
  // can merge (the same medium, or surfaces), joined to the camera subpath before it.
  if (!bdpt.merges()) return;
  for (int t = 2; t <= nc; ++t)
    for (int j = 1; j < nl; ++j) {
      const Vertex<N>& pt = camera_path[static_cast<std::size_t>(t - 1)];
      const Vertex<N>& q = light_path[static_cast<std::size_t>(j)];
      if (!Bdpt<N>::mergeable(pt) || !Bdpt<N>::mergeable(q) || pt.kind != q.kind ||
          (pt.kind == VertexKind::medium && pt.medium != q.medium))
        continue;
      int connections = 0;
      check_path(bdpt, scene, light_path, camera_path, j + 1, t - 1, pt.tau_in,
                 std::numeric_limits<double>::quiet_NaN(), out, &connections);
      ++out.merge_paths;
      if (connections == 0) ++out.merge_only_paths;
    }
}

}  // namespace

BdptMisCheck bdpt_mis_check(const RenderScene& scene, const RenderSettings& settings, int x, int y, int sample) {
  BdptMisCheck out;
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    mis_check<N>(scene, settings, x, y, sample, {}, out);
  });
  return out;
}

BdptMisCheck vcm_mis_check(const RenderScene& scene, const RenderSettings& settings, int x, int y, int sample) {
  BdptMisCheck out;
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    mis_check<N>(scene, settings, x, y, sample, bidir::vcm_merging(scene, settings, sample), out);
  });
  return out;
}

}  // namespace bouguer
