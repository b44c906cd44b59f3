#pragma once
// The bidirectional estimators' shared machinery (bdpt.cpp, vcm.cpp): the two subpaths of a sample
// built by the one random walk (walk.h), the densities of the vertex records, every connection
// strategy (s light vertices, t camera vertices) and the power-heuristic MIS over them — and, where
// merging is on (vcm.cpp), over the merging strategies too.
//
// Bidirectional path tracing (Veach 1997; pbrt-v4's BDPT): per camera sample one camera subpath
// and one light subpath, both built by the one random walk (integrators/walk.h), and every
// connection strategy (s light vertices, t camera vertices): the camera path meeting a lamp or
// escaping to a light at infinity (s = 0), next-event estimation (s = 1), light tracing to the
// camera (t = 1, splatted), and vertex connections, surface and medium vertices alike. The
// strategies are combined by the power heuristic over the densities of the vertex records; a
// lamp seen directly is left to s = 0 (the light tracer's lamp splat is not made), as in pbrt.
//
// Spectral. Both subpaths carry the sample's wavelengths (all 96 bins in full mode, the four of
// hero mode); in scattering media distances follow the sample's hero wavelength and every
// contribution is divided by the mean over the wavelengths of the product of its parts' spectral-MIS
// ratios (camera subpath, light subpath, connection), the one-sample balance over the hero choice.
// In a scene with dispersive media both subpaths carry every wavelength until a dispersive
// interface; from there on the surfaces are built for one kept wavelength, the same for both
// subpaths of a sample, and a contribution of a path that crossed one counts at that wavelength
// only (weight N), whichever subpath crossed it. Bouguer–Lambert along every segment and connection is the medium's
// exact transmittance.
//
// Depth: the connections and merges make the paths of s + t − 2 ≤ max_depth, where medium vertices
// count like surface vertices. A camera subpath that reaches that many vertices walks on as the
// path tracer does (radiance.h: its next-event estimation, MIS, splits into walks of one wavelength
// and thinning), and what that tail finds is the light of every longer path, which no connection
// makes: the strategies of a path are chosen by its length, so the weights of each still sum to 1,
// and a dense medium (a glass of milk, thousands of vertices a path) comes out as bright as the
// path tracer's image instead of losing what scattered more than max_depth times.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/radiance.h"
#include "bouguer/integrators/walk.h"

namespace bouguer::bidir {

constexpr double sq(double x) { return x * x; }

// Merging (vcm.cpp): the ratio of a merging strategy's density at a vertex to that of the
// connection just before it is p_light(x)·η, η = (light subpaths)·(the kernel's area πr², or its
// volume 4/3·πr³ at a medium vertex). Off (η = 0) in bdpt.
struct Merging {
  double eta_surface = 0.0, eta_medium = 0.0;
};

inline bool is_delta_light(const Light& light) {
  return std::holds_alternative<PointLight>(light) || std::holds_alternative<SpotLight>(light) ||
         std::holds_alternative<DistantLight>(light);
}

template <std::size_t N>
class Bdpt {
 public:
  // `kept`: in a dispersive scene, the sample's wavelengths with all but the kept one terminated.
  Bdpt(const SceneView<N>& v, const WalkMedia& media, SampledWavelengths<N>& w, const SampledWavelengths<N>* kept,
       Rng& rng, std::uint64_t& rays)
      : v_(v), s_(v.scene), media_(media), w_(w), kept_(kept), rng_(rng), rays_(rays) {}

  // The camera subpath's first max_depth + 2 vertices into `path`, and what its tail beyond them
  // finds into camera_tail(); `keep` (begin_sample's) weighs the tail's light of paths that have
  // crossed a dispersive interface (null: no tail, the walk stops there: bdpt_mis_check).
  void camera_subpath(const Ray& ray, std::vector<Vertex<N>>& path, const SampledSpectrum<N>* keep);
  const SampledSpectrum<N>& camera_tail() const { return tail_; }
  void light_subpath(std::vector<Vertex<N>>& path) { light_subpath(path, rng_); }
  // The same from its own random stream (vcm.cpp traces each light subpath twice: for the photons,
  // then for the connections of its pixel).
  void light_subpath(std::vector<Vertex<N>>& path, Rng& rng);
  // The strategy (s, t) over the two subpaths: its contribution, weighted; t = 1 splats it.
  SampledSpectrum<N> connect(std::vector<Vertex<N>>& light, std::vector<Vertex<N>>& camera, int s, int t,
                             FilmBuffer& film, const SampledSpectrum<N>& keep);
  // Every strategy (s, t) within the depth, summed (light tracing splatted).
  SampledSpectrum<N> connect_all(std::vector<Vertex<N>>& light, std::vector<Vertex<N>>& camera, FilmBuffer& film,
                                 const SampledSpectrum<N>& keep) {
    const int nc = static_cast<int>(camera.size()), nl = static_cast<int>(light.size());
    if (light.empty()) light.emplace_back();  // the slot of s = 1's own light sample
    SampledSpectrum<N> l;
    for (int t = 1; t <= nc; ++t)
      for (int k = 0; k <= std::max(nl, 1); ++k) {
        const int depth = k + t - 2;
        if ((k == 1 && t == 1) || depth < 0 || depth > v_.max_depth) continue;
        l += connect(light, camera, k, t, film, keep);
      }
    return l;
  }

  // The densities of the vertex records and the MIS weight (public for the check in
  // bdpt_mis_check below).
  double pdf_light_origin(const Vertex<N>& y) const;
  double pdf_light(const Vertex<N>& y, const Vertex<N>& next, double tau) const;
  double pdf_camera(const Vertex<N>& next, double tau) const;
  double pdf_at(const Vertex<N>& at, const Vertex<N>* prev, const Vertex<N>& next, double tau) const;
  SampledSpectrum<N> f(const Vertex<N>& x, const Vec3& wi, TransportMode mode) const;
  int medium_towards(const Vertex<N>& x, const Vec3& wi) const {
    return x.kind == VertexKind::surface ? x.event.medium_towards(wi) : x.medium;
  }
  PathVertex path_vertex(const Vertex<N>& x) const {
    return PathVertex{x.point, x.kind == VertexKind::medium ? nullptr : &x.hit, x.inside};
  }
  double mis_weight(std::vector<Vertex<N>>& light, std::vector<Vertex<N>>& camera, const Vertex<N>* sampled, int s,
                    int t, double tau) const;

  void set_merging(const Merging& m) { merging_ = m; }
  bool merges() const { return merging_.eta_surface > 0.0; }
  // Whether a subpath vertex can be merged at: a medium vertex, or a surface that is not specular.
  static bool mergeable(const Vertex<N>& x) {
    return x.kind == VertexKind::medium || (x.kind == VertexKind::surface && !x.delta);
  }
  double eta(const Vertex<N>& x) const {
    return x.kind == VertexKind::medium ? merging_.eta_medium : merging_.eta_surface;
  }

 private:
  const SceneView<N>& v_;
  const RenderScene& s_;
  const WalkMedia& media_;
  SampledWavelengths<N>& w_;
  const SampledWavelengths<N>* kept_;
  Rng& rng_;
  std::uint64_t& rays_;
  Merging merging_;
  SampledSpectrum<N> tail_;
};

// A camera subpath's visitor: it keeps the first `max_vertices` vertices for the connections and,
// from the last of them on, walks as the path tracer (radiance.h), into `tail`. The last kept
// vertex is the tail's first: its next-event estimation makes paths one vertex longer than any
// connection does (a lamp met there is the connections' s = 0).
template <std::size_t N>
struct KeepThenTrace {
  static constexpr bool kReverse = true;
  std::vector<Vertex<N>>& path;
  std::size_t max_vertices;
  Radiance<N> tail;
  bool with_tail = true;  // false: stop at the last kept vertex (bdpt_mis_check)
  bool tracing = false;   // past the kept vertices
  bool reversed = false;  // the last kept vertex's predecessor has its pdf_rev

  bool keeps_records() const { return !tracing; }
  bool vertex(const Vertex<N>& x) {
    if (tracing) return tail.vertex(x);
    path.push_back(x);
    if (path.size() < max_vertices) return true;
    if (x.kind == VertexKind::light || !with_tail) return false;
    tracing = true;
    for (std::size_t i = 1; i + 1 < path.size(); ++i)
      ++(path[i].kind == VertexKind::medium ? tail.scatterings : tail.surfaces);
    return tail.vertex(x);
  }
  bool medium_vertex(const Vec3& point) { return tail.medium_vertex(point); }
  bool wants_reverse() const { return !(tracing && reversed); }
  void reverse(double pdf_dir) {
    if (tracing) reversed = true;
    const Vertex<N>& at = path.back();
    Vertex<N>& prev = path[path.size() - 2];
    prev.pdf_rev = to_area_density(pdf_dir, at.point, prev, at.tau_in);
  }
  // Walks of one wavelength (only in the tail): one that has not crossed a dispersive interface
  // follows its own wavelength's indices from here, as the path tracer's do.
  Radiance<N> split(WalkState<N>& s, const SampledWavelengths<N>& wk, Rng& r) {
    if (!s.dispersed) s.kept = nullptr;
    return tail.split(s, wk, r);
  }
  void join(const Radiance<N>& child) { tail.join(child); }
};
static_assert(WalkVisitor<KeepThenTrace<kFullBins>, kFullBins> && KeepsRecords<KeepThenTrace<kFullBins>> &&
              ChoosesReverse<KeepThenTrace<kFullBins>> && SplitsWalks<KeepThenTrace<kFullBins>, kFullBins>);

template <std::size_t N>
void Bdpt<N>::camera_subpath(const Ray& ray, std::vector<Vertex<N>>& path, const SampledSpectrum<N>* keep_spectrum) {
  path.clear();
  Vertex<N> c;
  c.kind = VertexKind::camera;
  c.point = ray.origin;
  c.beta = SampledSpectrum<N>::constant(1.0f);
  c.pdf_fwd = 1.0;
  path.push_back(c);
  WalkState<N> state;
  state.ray = ray;
  state.start = ray.origin;
  state.medium = s_.world_medium;
  const auto pdf = v_.camera.pdf_we(ray);
  state.parallel = v_.camera.desc.type == CameraType::orthographic;
  state.pdf_dir = state.parallel ? pdf[0] : pdf[1];
  state.from = ray.origin;
  state.kept = kept_;
  // The pixel's ray cone, as the path tracer's (walk.h): textures seen from the camera side are
  // read at the level the pixel covers. Light subpaths start none and read the finest level.
  const Camera::Cone cone = v_.camera.pixel_cone();
  state.cone_width_m = cone.width_m;
  state.cone_spread_rad = cone.spread_rad;
  KeepThenTrace<N> keep{path, static_cast<std::size_t>(v_.max_depth) + 2,
                        Radiance<N>{v_, w_, state, rng_, rays_, ray.origin, {}, 0, 0, keep_spectrum},
                        keep_spectrum != nullptr};
  random_walk(v_, media_, TransportMode::radiance, state, w_, rng_, rays_, keep);
  tail_ = keep.tail.l;
}

template <std::size_t N>
void Bdpt<N>::light_subpath(std::vector<Vertex<N>>& path, Rng& rng) {
  path.clear();
  Vertex<N> y;
  WalkState<N> state;
  if (!start_light_subpath(v_, w_, rng, y, state)) return;
  path.push_back(y);
  state.kept = kept_;
  KeepVertices<N> keep{path, static_cast<std::size_t>(v_.max_depth) + 1};
  random_walk(v_, media_, TransportMode::importance, state, w_, rng, rays_, keep);
}

// The density with which a light subpath starts at light vertex y: the light's pmf times its
// origin density (lights at infinity: times the direction's).
template <std::size_t N>
double Bdpt<N>::pdf_light_origin(const Vertex<N>& y) const {
  const Light& light = s_.lights[static_cast<std::size_t>(y.light)];
  const double pmf = s_.emitters.pmf[static_cast<std::size_t>(y.light)];
  if (y.infinite) return pmf * pdf_le(light, s_.bounds, -y.light_dir).dir;
  return pmf * pdf_le(light, s_.bounds, Vec3{0.0, 0.0, 1.0}).pos;
}

// The density with which a light subpath from y reaches `next` (per unit area there).
template <std::size_t N>
double Bdpt<N>::pdf_light(const Vertex<N>& y, const Vertex<N>& next, double tau) const {
  const Light& light = s_.lights[static_cast<std::size_t>(y.light)];
  if (y.infinite) return to_area_density(pdf_le(light, s_.bounds, -y.light_dir).pos, next.point - y.light_dir, next, tau, true);
  return to_area_density(pdf_le(light, s_.bounds, normalize(next.point - y.point)).dir, y.point, next, tau);
}

// The density with which the camera's rays reach `next`.
template <std::size_t N>
double Bdpt<N>::pdf_camera(const Vertex<N>& next, double tau) const {
  const Camera& camera = v_.camera;
  if (camera.desc.type == CameraType::orthographic) {
    const Ray ray{next.point - camera.forward, camera.forward};
    return to_area_density(camera.pdf_we(ray)[0], ray.origin, next, tau, true);
  }
  const Ray ray{camera.desc.position_m, normalize(next.point - camera.desc.position_m)};
  return to_area_density(camera.pdf_we(ray)[1], ray.origin, next, tau);
}

// The density with which vertex `at`, reached from `prev`, samples `next` (per unit area there).
template <std::size_t N>
double Bdpt<N>::pdf_at(const Vertex<N>& at, const Vertex<N>* prev, const Vertex<N>& next, double tau) const {
  if (at.kind == VertexKind::camera) return pdf_camera(next, tau);
  if (at.kind == VertexKind::light) return pdf_light(at, next, tau);
  auto towards = [&](const Vertex<N>& x) { return x.infinite ? x.light_dir : normalize(x.point - at.point); };
  const Vec3 wo = prev ? towards(*prev) : at.wo, wi = towards(next);
  double pdf_dir = 0.0;
  if (at.kind == VertexKind::medium)
    pdf_dir = phase_value(scattering_medium(s_, at.medium)->phase, -wo, wi);
  else
    pdf_dir = at.event.pdf(wo, wi);
  return to_area_density(pdf_dir, at.point, next, tau);
}

// f·|cos θ| (the phase function in a medium) at x towards wi, x reached along x.wo.
template <std::size_t N>
SampledSpectrum<N> Bdpt<N>::f(const Vertex<N>& x, const Vec3& wi, TransportMode mode) const {
  if (x.kind == VertexKind::medium)
    return SampledSpectrum<N>::constant(
        static_cast<float>(phase_value(scattering_medium(s_, x.medium)->phase, -x.wo, wi)));
  return x.event.eval(x.wo, wi, mode);
}

// The power heuristic over every strategy that could have made the same path (pbrt-v4's
// MISWeight): the densities of the vertices next to the connection are set to what the other
// strategies would have used, and the ratios of densities walked outwards on both sides.
// `sampled` replaces light[0] (s = 1) or camera[0] (t = 1); `tau` is the connection's.
template <std::size_t N>
double Bdpt<N>::mis_weight(std::vector<Vertex<N>>& light, std::vector<Vertex<N>>& camera, const Vertex<N>* sampled,
                           int s, int t, double tau) const {
  if (s + t == 2) return 1.0;
  Vertex<N>* slot = sampled ? (s == 1 ? &light[0] : &camera[0]) : nullptr;
  Vertex<N> saved;
  if (slot) saved = std::exchange(*slot, *sampled);
  Vertex<N>* qs = s > 0 ? &light[static_cast<std::size_t>(s - 1)] : nullptr;
  Vertex<N>* pt = &camera[static_cast<std::size_t>(t - 1)];
  Vertex<N>* qs_minus = s > 1 ? &light[static_cast<std::size_t>(s - 2)] : nullptr;
  Vertex<N>* pt_minus = t > 1 ? &camera[static_cast<std::size_t>(t - 2)] : nullptr;
  // What the other strategies would have used next to the connection (computed before any edit).
  const double pt_rev = s > 0 ? pdf_at(*qs, qs_minus, *pt, tau) : pdf_light_origin(*pt);
  const double pt_minus_rev =
      pt_minus ? (s > 0 ? pdf_at(*pt, qs, *pt_minus, pt->tau_in) : pdf_light(*pt, *pt_minus, pt->tau_in)) : 0.0;
  const double qs_rev = qs ? pdf_at(*pt, pt_minus, *qs, tau) : 0.0;
  const double qs_minus_rev = qs_minus ? pdf_at(*qs, pt, *qs_minus, qs->tau_in) : 0.0;
  const double old_pt_rev = pt->pdf_rev, old_pt_minus_rev = pt_minus ? pt_minus->pdf_rev : 0.0,
               old_qs_rev = qs ? qs->pdf_rev : 0.0, old_qs_minus_rev = qs_minus ? qs_minus->pdf_rev : 0.0;
  const bool old_pt_delta = pt->delta, old_qs_delta = qs ? qs->delta : false;
  pt->pdf_rev = pt_rev;
  pt->delta = false;
  if (pt_minus) pt_minus->pdf_rev = pt_minus_rev;
  if (qs) qs->pdf_rev = qs_rev, qs->delta = false;
  if (qs_minus) qs_minus->pdf_rev = qs_minus_rev;

  auto remap0 = [](double p) { return p != 0.0 ? p : 1.0; };
  double sum = 0.0, ri = 1.0;
  for (int i = t - 1; i > 0; --i) {
    const Vertex<N>& x = camera[static_cast<std::size_t>(i)];
    if (merges() && mergeable(x)) sum += sq(ri * x.pdf_rev * eta(x));  // merging at x
    ri *= remap0(x.pdf_rev) / remap0(x.pdf_fwd);
    if (!x.delta && !camera[static_cast<std::size_t>(i - 1)].delta) sum += ri * ri;
  }
  ri = 1.0;
  for (int i = s - 1; i >= 0; --i) {
    const Vertex<N>& x = light[static_cast<std::size_t>(i)];
    ri *= remap0(x.pdf_rev) / remap0(x.pdf_fwd);
    const bool delta_before = i > 0 ? light[static_cast<std::size_t>(i - 1)].delta
                                    : is_delta_light(s_.lights[static_cast<std::size_t>(light[0].light)]);
    if (!x.delta && !delta_before) sum += ri * ri;
    if (merges() && i > 0 && mergeable(x)) sum += sq(ri * x.pdf_fwd * eta(x));
  }

  if (qs_minus) qs_minus->pdf_rev = old_qs_minus_rev;
  if (qs) qs->pdf_rev = old_qs_rev, qs->delta = old_qs_delta;
  if (pt_minus) pt_minus->pdf_rev = old_pt_minus_rev;
  pt->pdf_rev = old_pt_rev;
  pt->delta = old_pt_delta;
  if (slot) *slot = saved;
  return 1.0 / (1.0 + sum);
}

template <std::size_t N>
SampledSpectrum<N> Bdpt<N>::connect(std::vector<Vertex<N>>& light, std::vector<Vertex<N>>& camera, int s, int t,
                                    FilmBuffer& film, const SampledSpectrum<N>& keep) {
  // A path that crossed a dispersive interface counts at the kept wavelength only (weight N).
  auto mask = [&](bool dispersed) { return dispersed ? keep : SampledSpectrum<N>::constant(1.0f); };
  const Vertex<N>& pt = camera[static_cast<std::size_t>(t - 1)];
  if (s == 0) {  // the camera path met a lamp or escaped to a light at infinity
    if (pt.kind != VertexKind::light) return {};
    const SampledSpectrum<N> le = pt.infinite ? escaped(v_, -1, pt.light_dir, w_) : emitted(v_, pt.hit, pt.wo, w_);
    const SampledSpectrum<N> l = pt.beta * le * mask(pt.dispersed);
    if (l.is_zero()) return {};
    return l * static_cast<float>(mis_weight(light, camera, nullptr, 0, t, 0.0) / mean_ratio(s_, pt.r_u));
  }
  if (pt.kind == VertexKind::light || !pt.connectible()) return {};
  if (t == 1) {  // a light subpath vertex seen by the camera
    const Vertex<N>& qs = light[static_cast<std::size_t>(s - 1)];
    if (!qs.connectible() || qs.kind == VertexKind::light) return {};
    const auto c = v_.camera.connect(qs.point);
    if (!c) return {};
    const SampledSpectrum<N> fq = f(qs, c->wi, TransportMode::importance);
    if (fq.is_zero()) return {};
    const auto tr = transmission(v_, path_vertex(qs), c->wi, c->distance_m, medium_towards(qs, c->wi), w_, rng_,
                                 rays_, media_.sigma_mean);
    if (!tr) return {};
    SampledSpectrum<N> l = qs.beta * fq * tr->tr * static_cast<float>(c->factor) * mask(qs.dispersed);
    if (l.is_zero()) return {};
    Vertex<N> lens;
    lens.kind = VertexKind::camera;
    lens.point = qs.point + c->wi * c->distance_m;
    lens.pdf_fwd = 1.0;
    l *= static_cast<float>(mis_weight(light, camera, &lens, s, 1, tr->tau) / mean_ratio(s_, qs.r_u, tr->ratios.r_l));
    add_splat(film, v_.tables, w_, c->film_x, c->film_y, l);
    return {};
  }
  if (s == 1) {  // next-event estimation: a light drawn by power, as light subpaths start
    const double u = rng_.next_double(), u1 = rng_.next_double(), u2 = rng_.next_double();
    const auto chosen = s_.emitters.sample(u);
    if (!chosen) return {};
    const Light& lamp = s_.lights[static_cast<std::size_t>(chosen->first)];
    const auto li = sample_li(lamp, pt.point, u1, u2);
    if (!li || li->factor == 0.0) return {};
    const SampledSpectrum<N> fp = f(pt, li->wi, TransportMode::radiance);
    if (fp.is_zero()) return {};
    const auto tr = transmission(v_, path_vertex(pt), li->wi, li->distance_m, medium_towards(pt, li->wi), w_, rng_,
                                 rays_, media_.sigma_mean);
    if (!tr) return {};
    const SampledSpectrum<N> le = sample_radiance(v_, *li, w_);
    SampledSpectrum<N> l = pt.beta * fp * le * tr->tr *
                           static_cast<float>(li->factor / (chosen->second * li->pdf)) * mask(pt.dispersed);
    if (l.is_zero()) return {};
    Vertex<N> y;
    y.kind = VertexKind::light;
    y.light = chosen->first;
    y.infinite = std::isinf(li->distance_m);
    y.light_dir = li->wi;
    if (!y.infinite) y.point = pt.point + li->wi * li->distance_m;
    if (const auto* a = std::get_if<AreaLight>(&lamp)) y.normal = a->normal;
    y.pdf_fwd = pdf_light_origin(y);
    return l * static_cast<float>(mis_weight(light, camera, &y, 1, t, tr->tau) / mean_ratio(s_, pt.r_u, tr->ratios.r_l));
  }
  const Vertex<N>& qs = light[static_cast<std::size_t>(s - 1)];
  if (!qs.connectible()) return {};
  const Vec3 d = qs.point - pt.point;
  const double d2 = dot(d, d);
  if (!(d2 > 0.0)) return {};
  const double distance = std::sqrt(d2);
  const Vec3 wi = d / distance;
  const SampledSpectrum<N> fp = f(pt, wi, TransportMode::radiance);
  if (fp.is_zero()) return {};
  const SampledSpectrum<N> fq = f(qs, -wi, TransportMode::importance);
  if (fq.is_zero()) return {};
  const auto tr = transmission(v_, path_vertex(pt), wi, distance, medium_towards(pt, wi), w_, rng_, rays_,
                               media_.sigma_mean);
  if (!tr) return {};
  SampledSpectrum<N> l =
      pt.beta * fp * fq * qs.beta * tr->tr * static_cast<float>(1.0 / d2) * mask(pt.dispersed || qs.dispersed);
  if (l.is_zero()) return {};
  return l * static_cast<float>(mis_weight(light, camera, nullptr, s, t, tr->tau) /
                                mean_ratio(s_, pt.r_u * qs.r_u, tr->ratios.r_l));
}

// The σ̄_s of every medium over the sample's wavelengths (walk.h); their hero is the caller's
// (stratified: integrators.h, start_sample_wavelengths; vcm.cpp over its iterations). In a
// dispersive scene, `kept` becomes the sample's wavelengths with all but one terminated (the one
// both subpaths follow past a dispersive interface) and the result is N at that one, 0 elsewhere:
// what a contribution of a path that crossed such an interface is multiplied by. Otherwise all ones.
template <std::size_t N>
SampledSpectrum<N> begin_sample(const SceneView<N>& view, SampledWavelengths<N>& w, double dispersion_u, Rng& rng,
                                std::vector<double>& sigma_mean, SampledWavelengths<N>& kept) {
  const RenderScene& scene = view.scene;
  sigma_mean.assign(scene.media.size(), 0.0);
  if (scene.scatters)
    for (std::size_t m = 0; m < scene.media.size(); ++m)
      if (const ScatteringMedium* sm = scattering_medium(scene, static_cast<int>(m)))
        sigma_mean[m] = view.tables.at(sm->sigma_s, w).average();
  SampledSpectrum<N> keep = SampledSpectrum<N>::constant(1.0f);
  if (scene.dispersive && N > 1) {
    kept = w;
    const int j = keep_wavelength(view, kept, dispersion_u, rng);
    keep = {};
    keep[static_cast<std::size_t>(j)] = static_cast<float>(N);
  }
  return keep;
}

// Every strategy that could have made the full path light[0, s) + camera[t, 0): its subpaths cut
// at each place, the densities of every vertex recomputed from the geometry in both directions,
// and the MIS weights summed. Also the largest difference between the weight the renderer gives
// the original split (from the walk's own records) and the recomputed one.
// With merging on, also the merging strategies at every vertex where a path can merge:
// merge_weight(light subpath up to the vertex, camera subpath up to it) gives each's weight.
template <std::size_t N, typename MergeWeight>
void check_path(const Bdpt<N>& bdpt, const RenderScene& scene, const std::vector<Vertex<N>>& light,
                const std::vector<Vertex<N>>& camera, int s, int t, double tau_connection, double renderer_weight,
                BdptMisCheck& out, MergeWeight&& merge_weight) {
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
    p_camera[k] = i == n - 1 ? 1.0
                             : bdpt.pdf_at(at(i + 1), i + 2 < n ? &at(i + 2) : nullptr, at(i), tau[k]);
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
  };
  double sum = 0.0;
  for (int s2 = 0; s2 < n; ++s2) {
    const int t2 = n - s2;
    if (s2 == 0 && (t2 < 2 || is_delta_light(scene.lights[static_cast<std::size_t>(at(0).light)]))) continue;
    if (s2 >= 1 && !at(s2 - 1).connectible()) continue;
    if (!at(s2).connectible() || (s2 == 1 && t2 == 1)) continue;
    split(s2, false);
    if (l2.empty()) l2.emplace_back();
    const double w = bdpt.mis_weight(l2, c2, nullptr, s2, t2, s2 > 0 ? tau[static_cast<std::size_t>(s2 - 1)] : 0.0);
    sum += w;
    if (s2 == s) out.max_weight_difference = std::max(out.max_weight_difference, std::abs(w - renderer_weight));
  }
  if (bdpt.merges())
    for (int k = 1; k + 1 < n; ++k)
      if (Bdpt<N>::mergeable(at(k))) {
        split(k, true);
        sum += merge_weight(bdpt, l2, c2);
      }
  out.sums.push_back(sum);
}

// The check of one camera sample's subpaths (bdpt_mis_check, vcm_mis_check): `merging` sets the
// merging strategies' η, merge_weight as check_path's.
template <std::size_t N, typename MergeWeight>
void mis_check(const RenderScene& scene, const RenderSettings& settings, int x, int y, int sample,
               const Merging& merging, MergeWeight&& merge_weight, BdptMisCheck& out) {
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
  begin_sample(view, w, rng.next_double(), rng, sigma_mean, kept);
  const WalkMedia media{sigma_mean};
  std::uint64_t rays = 0;
  Bdpt<N> bdpt(view, media, w, scene.dispersive ? &kept : nullptr, rng, rays);
  bdpt.set_merging(merging);
  std::vector<Vertex<N>> camera_path, light_path;
  const auto [u, v] = subpixel(sample, settings.spp, rng);
  bdpt.camera_subpath(camera.generate_ray(x + u, y + v), camera_path, nullptr);
  bdpt.light_subpath(light_path);
  const int nc = static_cast<int>(camera_path.size()), nl = static_cast<int>(light_path.size());
  for (int t = 1; t <= nc; ++t)
    for (int s = 0; s <= nl; ++s) {
      if (s == 1 || s + t < 3) continue;  // s = 1 draws its own light; (0, 2) and (1, 1) are alone
      const Vertex<N>& pt = camera_path[static_cast<std::size_t>(t - 1)];
      if (s == 0 && pt.kind != VertexKind::light) continue;
      if (s > 0 && (pt.kind == VertexKind::light || !pt.connectible() ||
                    !light_path[static_cast<std::size_t>(s - 1)].connectible()))
        continue;
      if (t == 1 && !camera.connect(light_path[static_cast<std::size_t>(s - 1)].point)) continue;
      const Vertex<N>* qs = s > 0 ? &light_path[static_cast<std::size_t>(s - 1)] : nullptr;
      double tau = 0.0;
      if (qs && scene.scatters) {  // the connection's scattering depth, through the same medium as render
        const Vec3 from = t == 1 ? camera.desc.position_m : pt.point;
        const Vec3 d = qs->point - from;
        const double length_m = std::sqrt(dot(d, d));
        if (t > 1) {
          const Vec3 wi = d / length_m;
          const int m = pt.kind == VertexKind::surface ? pt.event.medium_towards(wi) : pt.medium;
          tau = scattering_depth(view, media, m, pt.point, wi, length_m);
        }
        if (t == 1) continue;  // through media the lens connection's depth needs the crossings: skip
      }
      Vertex<N> lens;
      const Vertex<N>* sampled = nullptr;
      if (t == 1) {
        const auto c = camera.connect(qs->point);
        lens.kind = VertexKind::camera;
        lens.point = qs->point + c->wi * c->distance_m;
        lens.pdf_fwd = 1.0;
        sampled = &lens;
      }
      const double w_render = bdpt.mis_weight(light_path, camera_path, sampled, s, t, tau);
      check_path(bdpt, scene, light_path, camera_path, s, t, tau, w_render, out, merge_weight);
    }
}

}  // namespace bouguer::bidir
