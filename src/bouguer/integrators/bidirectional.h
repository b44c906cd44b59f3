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
// camera (t = 1, splatted), and vertex connections, surface and medium vertices alike; and, in
// bdpt, where no other strategy reaches, next-event estimation through glass (through_glass) and
// its mirror image, light subpath vertices splatted to the camera through glass
// (through_glass_to_camera). The
// strategies are combined by the power heuristic over the densities of the vertex records, by
// Georgiev's recursion (Bdpt::mis_weight: each subpath folded once, O(1) a strategy), the one
// formulation vcm's merges share; a lamp seen directly is left to s = 0 (the light tracer's lamp
// splat is not made), as in pbrt.
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
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/light_prefix.h"
#include "bouguer/integrators/radiance.h"
#include "bouguer/integrators/splats.h"
#include "bouguer/integrators/walk.h"

namespace bouguer::bidir {

constexpr double sq(double x) { return x * x; }

// Merging (vcm.cpp): the ratio of a merging strategy's density at a vertex to that of the
// connection just before it is p_light(x)·η, η = (light subpaths)·(the kernel's area πr², or its
// volume 4/3·πr³ at a medium vertex). Off (η = 0) in bdpt.
struct Merging {
  double eta_surface = 0.0, eta_medium = 0.0;
};

// vcm's radius shrinks as r_i = r_1·i^((α−1)/2) (progressive photon mapping), so the variance of
// its merges' mean over n iterations falls as n^−α on surfaces (a kernel of area πr²), not n^−1,
// and as n^−(1 − 3(1 − α)/2) = n^−0.625 in media (of volume 4/3·πr³).
constexpr double kVcmAlpha = 0.75;
constexpr double kVcmMediumRate = 1.0 - 1.5 * (1.0 - kVcmAlpha);

// vcm.cpp's merging: its first radius (the scene's, or two pixel footprints), and the η of an
// iteration with radius r over `light_paths` light subpaths, or of iteration `iteration`.
double vcm_initial_radius(const RenderScene& scene, const RenderSettings& settings);
Merging vcm_merging(double r, double light_paths);
Merging vcm_merging(const RenderScene& scene, const RenderSettings& settings, int iteration);

inline bool is_delta_light(const Light& light) {
  return std::holds_alternative<PointLight>(light) || std::holds_alternative<SpotLight>(light) ||
         std::holds_alternative<DistantLight>(light);
}

// A density 0 (a specular vertex's, a vertex's reached through one, or a light's at infinity)
// counting as 1, as pbrt-v4's remap0: the unknown delta factor is the same in every strategy of a
// path, so it is taken as 1 in all of them, ratios and merges alike.
inline double remap0(double p) { return p != 0.0 ? p : 1.0; }

// (p_rev/p_fwd)² of a vertex, passing specular vertices by (remap0).
inline double ratio2(double pdf_rev, double pdf_fwd) { return sq(remap0(pdf_rev) / remap0(pdf_fwd)); }

// A merge's density at x relative to the connection just before it, squared: (p·η)², p the
// density with which the subpath that stores the photon reached x, remapped as ratio2's (a vertex
// reached through a specular one has p = 0, and merging there is often its path's only
// strategy: light scattered once in a liquid behind glass from a point lamp).
inline double merge2(double pdf, double eta) { return sq(remap0(pdf) * eta); }

template <std::size_t N>
class Bdpt {
 public:
  // `kept`: in a dispersive scene, the sample's wavelengths with all but the kept one terminated.
  Bdpt(const SceneView<N>& v, const WalkMedia& media, SampledWavelengths<N>& w, const SampledWavelengths<N>* kept,
       Rng& rng, std::uint64_t& rays)
      : v_(v), s_(v.scene), media_(media), w_(w), kept_(kept), rng_(rng), rays_(rays) {}

  // The camera subpath's first max_depth + 2 vertices into `path`, and what its tail beyond them
  // finds into camera_tail(); `keep` (begin_sample's) weighs the tail's light of paths that have
  // crossed a dispersive interface (null: no tail, the walk stops there: the MIS check,
  // tests/support/mis_check.h).
  void camera_subpath(const Ray& ray, std::vector<Vertex<N>>& path, const SampledSpectrum<N>* keep);
  const SampledSpectrum<N>& camera_tail() const { return tail_; }
  void light_subpath(std::vector<Vertex<N>>& path) {
    path.clear();
    append_light_subpath(path, rng_);
  }
  // A light subpath from its own random stream appended to `vertices` (vcm.cpp: one per pixel and
  // iteration, all of a tile's in one array); returns the number of its vertices.
  std::size_t append_light_subpath(std::vector<Vertex<N>>& vertices, Rng& rng);
  // The strategy (s, t) over the two subpaths: its contribution, weighted; t = 1 splats it.
  SampledSpectrum<N> connect(std::span<const Vertex<N>> light, const std::vector<Vertex<N>>& camera, int s, int t,
                             FilmBuffer& film, const SampledSpectrum<N>& keep);
  // Every strategy (s, t) within the depth, summed (light tracing splatted).
  SampledSpectrum<N> connect_all(std::span<const Vertex<N>> light, std::vector<Vertex<N>>& camera, FilmBuffer& film,
                                 const SampledSpectrum<N>& keep) {
    const int nc = static_cast<int>(camera.size()), nl = static_cast<int>(light.size());
    std::optional<Vertex<N>> slot;  // where the light subpath is empty, the slot of s = 1's own light sample
    if (light.empty()) light = std::span<const Vertex<N>>(&slot.emplace(), 1);
    fold_mis(light, camera);
    SampledSpectrum<N> l;
    for (int t = 1; t <= nc; ++t)
      for (int k = 0; k <= std::max(nl, 1); ++k) {
        const int depth = k + t - 2;
        if ((k == 1 && t == 1) || depth < 0 || depth > v_.max_depth) continue;
        l += connect(light, camera, k, t, film, keep);
      }
    if (!merges()) {
      l += through_glass(camera, keep);
      through_glass_to_camera(light, film, keep);
    }
    return l;
  }
  // bdpt's next-event estimation through smooth glass (manifold.h) to the point, spot and distant lamps, at
  // each non-specular vertex of the camera subpath that the camera sees through specular ones (a
  // liquid or a floor behind glass), up to the first two non-specular vertices side by side: there
  // it is the only strategy of the paths it makes, so they are not weighted (below, where it is
  // defined). through_glass_at: at one vertex.
  SampledSpectrum<N> through_glass(const std::vector<Vertex<N>>& camera, const SampledSpectrum<N>& keep);
  SampledSpectrum<N> through_glass_at(const Vertex<N>& x, const SampledSpectrum<N>& keep);
  // Its mirror image on the light subpath: the light subpath's non-specular vertices reached from a
  // point, spot or distant lamp through specular ones along a path next-event estimation through glass
  // does not make (a glass's or a mirror's reflection on the way: light_prefix.h), splatted to a
  // pinhole through smooth glass (splats.cpp), up to the first two non-specular vertices side by
  // side; unweighted for the same reason (below, where it is defined).
  void through_glass_to_camera(std::span<const Vertex<N>> light, FilmBuffer& film, const SampledSpectrum<N>& keep);

  // The densities of the vertex records, from the geometry (public for the MIS check,
  // tests/support/mis_check.h).
  double pdf_light_origin(const Vertex<N>& y) const;
  double pdf_light(const Vertex<N>& y, const Vertex<N>& next, double tau) const;
  double pdf_camera(const Vertex<N>& next, double tau) const;
  double pdf_at(const Vertex<N>& at, const Vertex<N>* prev, const Vertex<N>& next, double tau) const;
  double direction_pdf(const Vertex<N>& x, const Vec3& wi, bool reverse) const;
  SampledSpectrum<N> f(const Vertex<N>& x, const Vec3& wi, TransportMode mode) const;

  // The MIS (below mis_weight): fold_mis(light, camera) once the subpaths are made, then the
  // weight of any strategy over them in O(1). `sampled` stands for light[0] (s = 1) or
  // camera[0] (t = 1).
  void fold_mis(std::span<const Vertex<N>> light, const std::vector<Vertex<N>>& camera) {
    subpath_sums(light, true, light_sums_);
    subpath_sums(camera, false, camera_sums_);
  }
  void subpath_sums(std::span<const Vertex<N>> path, bool light, std::vector<double>& sums) const;
  double mis_weight(std::span<const Vertex<N>> light, const std::vector<Vertex<N>>& camera,
                    const Vertex<N>* sampled, int s, int t, double tau) const;
  // A merge of camera[t − 1] with light vertex q (≥ 1st of its subpath, `prev` before it, `sums`
  // its subpath's folded sum at q: subpath_sums).
  double merge_weight(const std::vector<Vertex<N>>& camera, int t, const VertexCore<N>& q, const VertexCore<N>& prev,
                      double sums) const;

  void set_merging(const Merging& m) { merging_ = m; }
  bool merges() const { return merging_.eta_surface > 0.0; }
  // Whether a subpath vertex can be merged at: a medium vertex, or a surface that is not specular.
  static bool mergeable(const VertexCore<N>& x) {
    return x.kind == VertexKind::medium || (x.kind == VertexKind::surface && !x.delta);
  }
  double eta(const VertexCore<N>& x) const {
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
  // subpath_sums of the subpaths connected: buffers of the thread, reused from sample to sample
  // (a Bdpt lives for one sample, and a thread weighs one sample's strategies at a time), where
  // vectors of its own cost two allocations a sample (2 % of a glass scene's instructions).
  std::vector<double>& light_sums_ = thread_buffer(0);
  std::vector<double>& camera_sums_ = thread_buffer(1);
  static std::vector<double>& thread_buffer(int k) {
    thread_local std::vector<double> buffers[2];
    return buffers[k];
  }

  double light_side(std::span<const Vertex<N>> light, int s, const Vertex<N>& qs, double qs_rev,
                    double qs_minus_rev) const;
  double camera_side(const std::vector<Vertex<N>>& camera, int t, double pt_rev, double pt_minus_rev) const;
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
  bool with_tail = true;  // false: stop at the last kept vertex (the MIS check)
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
  Radiance<N> split(WalkState<N>& s, const SampledWavelengths<N>& wk, Rng& r, float weight) {
    if (!s.dispersed) s.kept = nullptr;
    return tail.split(s, wk, r, weight);
  }
  void join(const Radiance<N>& child) { tail.join(child); }
  float split_weight() const { return tail.split_weight(); }
  // The tail's exit guide and distance bound (radiance.h): neither is set before the tail begins.
  GuideTrail& exit_guide_trail() { return tail.exit_guide_trail(); }
  const SurfaceDistance& surface_distance() const { return tail.surface_distance(); }
};
static_assert(WalkVisitor<KeepThenTrace<kFullBins>, kFullBins> && KeepsRecords<KeepThenTrace<kFullBins>> &&
              ChoosesReverse<KeepThenTrace<kFullBins>> && SplitsWalks<KeepThenTrace<kFullBins>, kFullBins> &&
              GuidesExits<KeepThenTrace<kFullBins>> && BoundsSurfaceDistance<KeepThenTrace<kFullBins>>);

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
std::size_t Bdpt<N>::append_light_subpath(std::vector<Vertex<N>>& vertices, Rng& rng) {
  const std::size_t first = vertices.size();
  Vertex<N> y;
  WalkState<N> state;
  if (!start_light_subpath(v_, w_, rng, y, state)) return 0;
  vertices.push_back(y);
  state.kept = kept_;
  KeepVertices<N> keep{vertices, static_cast<std::size_t>(v_.max_depth) + 1, first};
  random_walk(v_, media_, TransportMode::importance, state, w_, rng, rays_, keep);
  return vertices.size() - first;
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
  return to_area_density(pdf_le(light, s_.bounds, normalize(next.point - y.point), y.normal).dir, y.point, next, tau);
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
  return vertex_f(s_, x, x.wo, wi, mode);
}

// The power heuristic over every strategy that could have made the same path, by Georgiev's
// recursion ("Implementing VCM", SmallVCM's dVCM/dVC/dVM) written on the walk's area densities:
// subpath_sums (once per subpath) folds each side's strategies into one number per vertex, and a
// strategy's weight recomputes only the ≤ 4 densities next to its joint (the other side's
// vertex, and the one before it, as the other strategies would reach them) and adds the two
// sides' folded sums to them: O(1) a connection or merge. Nothing is modified, so a sampled
// light or lens vertex is just passed in. `tau` is the connection's scattering depth.
template <std::size_t N>
double Bdpt<N>::mis_weight(std::span<const Vertex<N>> light, const std::vector<Vertex<N>>& camera,
                           const Vertex<N>* sampled, int s, int t, double tau) const {
  if (s + t == 2) return 1.0;
  const Vertex<N>& pt = sampled && t == 1 ? *sampled : camera[static_cast<std::size_t>(t - 1)];
  const Vertex<N>* pt_minus = t > 1 ? &camera[static_cast<std::size_t>(t - 2)] : nullptr;
  if (s == 0) {  // pt is a lamp the camera path met: what light subpaths starting there would do
    const double pt_rev = pdf_light_origin(pt);
    const double pt_minus_rev = pdf_light(pt, *pt_minus, pt.tau_in);
    return 1.0 / (1.0 + camera_side(camera, t, pt_rev, pt_minus_rev));
  }
  const Vertex<N>& qs = sampled && s == 1 ? *sampled : light[static_cast<std::size_t>(s - 1)];
  const Vertex<N>* qs_minus = s > 1 ? &light[static_cast<std::size_t>(s - 2)] : nullptr;
  double sum = 0.0;
  if (t > 1) sum += camera_side(camera, t, pdf_at(qs, qs_minus, pt, tau),
                                pt_minus ? pdf_at(pt, &qs, *pt_minus, pt.tau_in) : 0.0);
  const double qs_rev = pdf_at(pt, pt_minus, qs, tau);
  const double qs_minus_rev = qs_minus ? pdf_at(qs, &pt, *qs_minus, qs.tau_in) : 0.0;
  sum += light_side(light, s, qs, qs_rev, qs_minus_rev);
  return 1.0 / (1.0 + sum);
}

// What the strategies with fewer light vertices than s add, relative to the connection (s, t):
// qs = light[s − 1] (or the sampled light vertex), its density qs_rev from the camera side and
// qs_minus_rev its predecessor's; the rest is light_sums_[s − 1], folded when the subpath was made.
template <std::size_t N>
double Bdpt<N>::light_side(std::span<const Vertex<N>> light, int s, const Vertex<N>& qs, double qs_rev,
                           double qs_minus_rev) const {
  // qs's own strategies: the connection just before it (qs is not specular: it connects) and
  // merging at it.
  const bool delta_before = s > 1 ? light[static_cast<std::size_t>(s - 2)].delta : is_delta_light(s_.lights[static_cast<std::size_t>(qs.light)]);
  double at_qs = delta_before ? 0.0 : 1.0;
  if (merges() && s > 1 && mergeable(qs)) at_qs += merge2(qs.pdf_fwd, eta(qs));
  if (s > 1)
    at_qs += ratio2(qs_minus_rev, light[static_cast<std::size_t>(s - 2)].pdf_fwd) * light_sums_[static_cast<std::size_t>(s - 1)];
  return ratio2(qs_rev, qs.pdf_fwd) * at_qs;
}

// What the strategies with more camera vertices than t add (merging at pt and beyond included),
// relative to a connection or merge at pt = camera[t − 1]: pt_rev and pt_minus_rev are pt's and
// its predecessor's densities from the light side; the rest is camera_sums_[t − 2].
template <std::size_t N>
double Bdpt<N>::camera_side(const std::vector<Vertex<N>>& camera, int t, double pt_rev, double pt_minus_rev) const {
  if (t < 2) return 0.0;
  const Vertex<N>& pt = camera[static_cast<std::size_t>(t - 1)];
  const Vertex<N>& pt_minus = camera[static_cast<std::size_t>(t - 2)];
  double merge_at_pt = merges() && mergeable(pt) ? merge2(pt_rev, eta(pt)) : 0.0;
  double beyond = pt_minus.delta ? 0.0 : 1.0;  // the connection between pt and pt_minus
  if (t > 2) {
    const Vertex<N>& before = camera[static_cast<std::size_t>(t - 3)];
    if (merges() && mergeable(pt_minus)) beyond += merge2(pt_minus_rev, eta(pt_minus));
    beyond += ratio2(pt_minus_rev, pt_minus.pdf_fwd) *
              ((!pt_minus.delta && !before.delta ? 1.0 : 0.0) + camera_sums_[static_cast<std::size_t>(t - 2)]);
  }
  return merge_at_pt + ratio2(pt_rev, pt.pdf_fwd) * beyond;
}

// The folded sums of a subpath's strategies (see mis_weight), from the densities its walk
// recorded. Light: sums[j] (j ≥ 1), the strategies that hold vertices 0 … j − 1 on the light side
// (the connection before vertex i and merging at i, for i < j), relative to the connection
// s = j, less the factor (p_rev/p_fwd)² of vertex j − 1, which depends on what meets the subpath
// there. Camera: sums[k] (k ≥ 1), the same for the camera vertices 1 … k − 1, relative to a
// connection at camera[k].
template <std::size_t N>
void Bdpt<N>::subpath_sums(std::span<const Vertex<N>> path, bool light, std::vector<double>& sums) const {
  sums.assign(path.size() + 1, 0.0);
  if (light) {
    for (std::size_t j = 1; j < path.size(); ++j) {
      const Vertex<N>& x = path[j - 1];
      const bool delta_before = j > 1 ? path[j - 2].delta : is_delta_light(s_.lights[static_cast<std::size_t>(path[0].light)]);
      double at_x = !x.delta && !delta_before ? 1.0 : 0.0;
      if (merges() && j > 1 && mergeable(x)) at_x += merge2(x.pdf_fwd, eta(x));
      sums[j] = at_x + (j >= 2 ? ratio2(path[j - 2].pdf_rev, path[j - 2].pdf_fwd) * sums[j - 1] : 0.0);
    }
    return;
  }
  for (std::size_t k = 2; k < path.size(); ++k) {
    const Vertex<N>& x = path[k - 1];
    const double merge_at_x = merges() && mergeable(x) ? merge2(x.pdf_rev, eta(x)) : 0.0;
    sums[k] = merge_at_x + ratio2(x.pdf_rev, x.pdf_fwd) * ((!x.delta && !path[k - 2].delta ? 1.0 : 0.0) + sums[k - 1]);
  }
}

// The MIS weight of merging camera[t − 1] with a photon (light vertex q, q.wo towards its
// predecessor): the merge's squared density over that of every strategy for the same path,
// relative to the connection of q's predecessor with camera[t − 1] (s = q's place, t). The
// light side is folded into `sums` at the photon's own place, as SmallVCM's photons keep dVCM
// and dVM: the merge point stands in for q there.
template <std::size_t N>
double Bdpt<N>::merge_weight(const std::vector<Vertex<N>>& camera, int t, const VertexCore<N>& q, const VertexCore<N>& prev,
                             double sums) const {
  const Vertex<N>& pt = camera[static_cast<std::size_t>(t - 1)];
  const Vec3& wo = q.wo;
  const double rev_prev = to_area_density(direction_pdf(pt, wo, false), pt.point, prev, q.tau_in);
  const double rev_before =
      t >= 3 ? to_area_density(direction_pdf(pt, wo, true), pt.point, camera[static_cast<std::size_t>(t - 2)], pt.tau_in)
             : 0.0;
  const double own = merge2(q.pdf_fwd, eta(pt));
  const double sum = (prev.delta ? 0.0 : 1.0) + ratio2(rev_prev, prev.pdf_fwd) * sums +
                     camera_side(camera, t, q.pdf_fwd, rev_before);
  return sum > 0.0 ? own / sum : 0.0;
}

// The density with which camera vertex x, reached along x.wo, samples direction wi (solid angle);
// `reverse`: x reached along wi, sampling x.wo.
template <std::size_t N>
double Bdpt<N>::direction_pdf(const Vertex<N>& x, const Vec3& wi, bool reverse) const {
  return reverse ? vertex_pdf(s_, x, wi, x.wo) : vertex_pdf(s_, x, x.wo, wi);
}

// The paths this makes: the lens, the camera subpath up to a non-specular vertex x whose
// predecessor is specular, a chain of smooth refractions that the straight segment from x to a
// point or spot lamp meets, the lamp (or the chains, plane or sphere that lead towards a sun:
// manifold.h, distant_light_through_interface). No other strategy of bdpt makes them where no two
// non-specular vertices of the camera subpath up to x lie side by side (the lens counts as one):
// a connection joins two such neighbours, light tracing (t = 1) the lens and the camera's first
// vertex, and next-event estimation's straight segment (s = 1) is blocked; the lamp itself is met
// by no camera path (s = 0). So the weight is 1, and the other strategies' weights are unchanged
// (this one has density 0 for every path they make). From the first such pair on, the paths have
// other strategies, and it stops. A surface vertex past max_depth gets nothing, as s = 1 and the
// path tracer give it nothing. Without it, bdpt left the light scattered once in a liquid behind
// glass, and a caustic seen through the glass that casts it, black (0.61 of the path tracer on the
// lit tumbler's liquid). Not in vcm, whose merges make these paths and are weighted against them.
template <std::size_t N>
SampledSpectrum<N> Bdpt<N>::through_glass(const std::vector<Vertex<N>>& camera, const SampledSpectrum<N>& keep) {
  if (!v_.manifold || s_.delta_lights.empty()) return {};
  SampledSpectrum<N> sum;
  bool before_specular = false;  // (the lens is not)
  for (std::size_t i = 1; i < camera.size(); ++i) {
    const Vertex<N>& x = camera[i];
    if (x.kind == VertexKind::light) break;
    const bool specular = x.kind == VertexKind::surface && x.delta;
    if (!specular && !before_specular) break;  // two non-specular neighbours: other strategies
    before_specular = specular;
    if (specular || (x.kind == VertexKind::surface && i > static_cast<std::size_t>(v_.max_depth))) continue;
    sum += through_glass_at(x, keep);
  }
  return sum;
}

template <std::size_t N>
SampledSpectrum<N> Bdpt<N>::through_glass_at(const Vertex<N>& x, const SampledSpectrum<N>& keep) {
  const PathVertex at = vertex_at(x);
  auto towards = [&](const Vec3& wi, double& pdf) {
    pdf = direction_pdf(x, wi, false);
    return f(x, wi, TransportMode::radiance);
  };
  auto leaves_into = [&](const Vec3& wi) { return vertex_medium_towards(x, wi); };
  SampledSpectrum<N> sum;
  if (!s_.casters.empty()) {  // (exact glass spheres: every delta light, no area light)
    Rng side(rng_.next_u32(), kManifoldStream);
    sum += through_casters(v_, at, towards, leaves_into, std::nullopt, 0.0, 0.0, w_, x.r_u, side, rays_);
  }
  for (const int index : s_.delta_lights) {
    const Light& lamp = s_.lights[static_cast<std::size_t>(index)];
    const auto li = sample_li(lamp, x.point, 0.0, 0.0);
    if (!li || li->factor == 0.0 || v_.tables.at(li->spectrum, w_).is_zero()) continue;
    double pdf = 0.0;
    if (towards(li->wi, pdf).is_zero()) continue;
    bool glass = false;
    Hit blocker;
    // (Where the straight segment is clear, s = 1 has the lamp.)
    if (transmission(v_, at, li->wi, li->distance_m, leaves_into(li->wi), w_, rng_, rays_, {}, &glass, &blocker) ||
        !glass)
      continue;
    sum += delta_light_through_interface(v_, at, lamp, blocker, towards, leaves_into, w_, x.r_u, rng_, rays_);
  }
  return x.beta * sum * (x.dispersed ? keep : SampledSpectrum<N>::constant(1.0f));
}

// The paths this makes: a point, spot or distant lamp, a chain of specular vertices (the light subpath's)
// along which next-event estimation through glass does not reach the lamp from the chain's end y
// (light_prefix.h: a reflection in the chain, or refractions it does not solve), y and the light
// subpath on from y, up to a non-specular vertex x, then a chain of smooth refractions to the
// pinhole that the straight segment from x to it meets (or through a caster). No other strategy
// of bdpt makes them where no two non-specular vertices of the light subpath up to x lie side by
// side (the lamp counts as one): a connection or the straight segment of light tracing (t = 1)
// needs such neighbours, the camera's own next-event estimation through glass (through_glass) the
// chain before y to be one it solves, and the camera path meets no point lamp (s = 0). So the
// weight is 1 and the other strategies' weights are unchanged, as for through_glass. Without it,
// bdpt left out the light a glass reflects inside itself before it is scattered once in a liquid
// seen through that glass (2.5 % of the lit tumbler's liquid; what scatters more than once
// bdpt's connections make). The light subpath ends at max_depth + 1 vertices, medium vertices
// counted: paths with their x beyond are made by no strategy of bdpt's (the camera tail's
// next-event estimation does not go through glass).
template <std::size_t N>
void Bdpt<N>::through_glass_to_camera(std::span<const Vertex<N>> light, FilmBuffer& film,
                                      const SampledSpectrum<N>& keep) {
  if (!v_.manifold || !s_.smooth_glass || v_.camera.desc.type != CameraType::pinhole || light.size() < 2 ||
      light[0].kind != VertexKind::light)
    return;
  auto prefix = light_prefix<N>(s_.lights[static_cast<std::size_t>(light[0].light)], light[0].point);
  if (!prefix) return;
  bool decided = false, before_specular = false;  // (the lamp is not)
  for (std::size_t i = 1; i < light.size(); ++i) {
    const Vertex<N>& x = light[i];
    if (x.kind == VertexKind::light) return;
    if (!decided) {
      const PrefixVerdict verdict = prefix->add(v_, x, w_, rays_);
      if (verdict == PrefixVerdict::made) return;
      decided = verdict == PrefixVerdict::beyond;
    }
    const bool specular = x.kind == VertexKind::surface && x.delta;
    if (!specular && !before_specular) return;  // two non-specular neighbours: other strategies
    before_specular = specular;
    if (specular) continue;
    splat_vertex_to_camera(v_, x, x.beta * (x.dispersed ? keep : SampledSpectrum<N>::constant(1.0f)), w_, rng_, film,
                           rays_, CameraPaths::through_glass);
  }
}

template <std::size_t N>
SampledSpectrum<N> Bdpt<N>::connect(std::span<const Vertex<N>> light, const std::vector<Vertex<N>>& camera, int s, int t,
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
    const auto tr = transmission(v_, vertex_at(qs), c->wi, c->distance_m, vertex_medium_towards(qs, c->wi), w_, rng_,
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
    const auto tr = transmission(v_, vertex_at(pt), li->wi, li->distance_m, vertex_medium_towards(pt, li->wi), w_, rng_,
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
    if (const auto* sp = std::get_if<SphereLight>(&lamp)) y.normal = normalize(y.point - sp->centre_m);
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
  const auto tr = transmission(v_, vertex_at(pt), wi, distance, vertex_medium_towards(pt, wi), w_, rng_, rays_,
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

}  // namespace bouguer::bidir
