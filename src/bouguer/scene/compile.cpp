#include "bouguer/scene/compile.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <tuple>

#include "bouguer/core/error.h"
#include "bouguer/core/memory.h"
#include "bouguer/core/limits.h"
#include "bouguer/scene/builder.h"
#include "bouguer/scene/update.h"
#include "bouguer/spectra/cie.h"

namespace bouguer {
namespace {

int medium_index(const RenderScene& s, const std::string& name) {
  for (std::size_t i = 0; i < s.media.size(); ++i)
    if (s.media[i].name == name) return static_cast<int>(i);
  return -1;  // the builder has checked every name
}

int add_spectrum(RenderScene& s, std::variant<Spectrum, IorModel> source, SpectrumRole role) {
  s.spectra.push_back({std::move(source), role});
  return static_cast<int>(s.spectra.size()) - 1;
}

// Peak memory per triangle while a scene is built: its mesh, welding and closedness checks and
// Embree's BVH. Measured 234 bytes each with the old weld (3.9 GB for 16.7 million triangles); with
// the cell-table weld and shading normals, 181 (peak RSS of a whole render of a 4.19-million-
// triangle sphere, 760 MB). Kept at 256: the margin is what lets a refusal come before an
// address-space limit does.
constexpr std::uint64_t kGeometryBytesPerTriangle = 256;

// The scene's triangles so far must fit the scene limit and the memory that was available when
// compile began (the estimate counts every triangle from the first).
void require_geometry_room(std::uint64_t triangles, std::uint64_t available, const SceneDesc& desc,
                           const ObjectDesc& o) {
  if (triangles > kMaxSceneTriangles)
    fail("{}: object '{}': the scene would have {} triangles, more than the limit of {}", desc.file.string(), o.name,
         triangles, kMaxSceneTriangles);
  require_memory(triangles * kGeometryBytesPerTriangle,
                 fmt::format("{}: object '{}': the scene up to it ({} triangles)", desc.file.string(), o.name, triangles),
                 available);
}

// After its transform, every vertex must still be a finite point within the scene's extent.
void check_world_positions(const Mesh& m, const SceneDesc& desc, const ObjectDesc& o) {
  for (const Vec3& p : m.positions) {
    for (int c = 0; c < 3; ++c)
      if (!(std::abs(p[c]) <= kMaxSceneCoordinateM))
        fail("{}: object '{}': its transform puts a vertex at {} = {:g} m, beyond the scene's extent of ±{:g} m",
             desc.file.string(), o.name, "xyz"[c], p[c], kMaxSceneCoordinateM);
  }
}

bool is_dispersive(const IorModel& ior) {
  const double n0 = ior_at(ior, kLambdaMinNm);
  for (double nm = kLambdaMinNm + 1.0; nm <= kLambdaMaxNm; nm += 1.0)
    if (std::abs(ior_at(ior, nm) - n0) > 1e-7) return true;
  return false;
}

// An interface must enclose its medium: the object's own volume (all parts with the object
// behind them) and, for a filled vessel, the liquid (the wet wall seen from the liquid plus the
// free surface) must each be closed and outward-facing.
void check_closed(const std::vector<ShapePart>& parts, const ObjectDesc& o, const SceneDesc& desc) {
  Mesh body, contents;
  for (const ShapePart& p : parts) {
    if (p.behind == Side::object) append(body, p.mesh);
    if (p.behind == Side::contents) append(contents, p.mesh);
    if (p.in_front == Side::contents) append(contents, flipped(p.mesh));
  }
  const double tolerance = 1e-9 * std::max(max_extent(body), 1e-6);
  if (const auto problem = closed_surface_problem(welded(body, tolerance)))
    fail("{}: object '{}': cannot bound medium '{}': {}", desc.file.string(), o.name, *o.inside, *problem);
  if (!contents.triangles.empty())
    if (const auto problem = closed_surface_problem(welded(contents, tolerance)))
      fail("{}: object '{}': its contents do not form a closed volume: {}", desc.file.string(), o.name, *problem);
}

// A spot light with a radius is a one-sided disk emitter facing along its axis, with the spot's
// angular profile. Its radiance I / A (A the disk's area) gives the point spot's on-axis intensity
// I, so a radius changes the penumbrae and makes the lamp visible (in mirrors, through glass),
// not the light's strength.
ObjectDesc spot_disk(const DeltaLightDesc& l, const std::string& name) {
  constexpr int segments = 64;
  ObjectDesc o;
  o.name = name;
  o.shape = DiskShape{l.radius_m, segments};
  const Vec3 z{0, 0, 1};
  const double c = dot(z, l.direction);
  Transform t;
  if (c < -1.0 + 1e-12)
    t = Transform::rotate_deg(180.0, {1, 0, 0});
  else if (c < 1.0 - 1e-12)
    t = Transform::rotate_deg(std::acos(c) * 180.0 / std::numbers::pi, cross(z, l.direction));
  o.transform = t.then(Transform::translate(l.position_m));
  const double area_m2 = 0.5 * segments * l.radius_m * l.radius_m * std::sin(2.0 * std::numbers::pi / segments);
  EmissionDesc e;
  e.radiance = scaled(l.intensity, 1.0 / area_m2);
  e.spot = SpotProfile{l.direction, l.cone_deg, l.falloff_deg};
  o.emission = e;
  return o;
}

// A texture's mean over a triangle where it is almost black still gives the triangle a small share
// of the light choice, so that light paths and next-event estimation reach every emitting point.
constexpr double kMinTextureMean = 1e-3;

// One area light per triangle; `texture` (-1: none) is the emission texture's id.
void add_area_lights(RenderScene& s, Surface& surface, std::uint32_t geometry, const Mesh& m, const EmissionDesc& e,
                     int texture) {
  const int radiance = add_spectrum(s, e.radiance, SpectrumRole::radiance);
  surface.first_light = static_cast<int>(s.lights.size());
  for (std::uint32_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    AreaLight a;
    a.geometry = geometry;
    a.primitive = i;
    a.p0 = m.positions[t[0]], a.p1 = m.positions[t[1]], a.p2 = m.positions[t[2]];
    const Vec3 c = cross(a.p1 - a.p0, a.p2 - a.p0);
    a.area_m2 = 0.5 * length(c);
    a.normal = a.area_m2 > 0.0 ? normalize(c) : Vec3{0, 0, 1};
    a.radiance = radiance;
    a.two_sided = e.two_sided;
    a.spot = e.spot;
    if (texture >= 0) {
      a.texture = texture;
      for (std::size_t k = 0; k < 3; ++k) a.uv[k] = m.uvs[t[k]];
      a.texture_mean = std::max(texture_mean_luminance(s.textures, texture, a.uv), kMinTextureMean);
    }
    s.lights.push_back(a);
  }
}

void add_delta_light(RenderScene& s, const DeltaLightDesc& l) {
  const int spectrum = add_spectrum(s, l.intensity, SpectrumRole::radiance);
  s.delta_lights.push_back(static_cast<int>(s.lights.size()));
  switch (l.type) {
    case DeltaLightType::point: s.lights.push_back(PointLight{l.position_m, spectrum}); break;
    case DeltaLightType::spot:
      s.lights.push_back(SpotLight{l.position_m, {l.direction, l.cone_deg, l.falloff_deg}, spectrum});
      break;
    case DeltaLightType::distant: s.lights.push_back(DistantLight{l.direction, spectrum}); break;
  }
}

SceneBounds bounds_of(const RenderScene& s) {
  Vec3 lo{1e300, 1e300, 1e300}, hi = -lo;
  for (std::uint32_t g = 0; g < s.surfaces.size(); ++g) {
    const auto [glo, ghi] = s.rays.bounds(g);
    for (std::size_t i = 0; i < 3; ++i) lo[i] = std::min(lo[i], glo[i]), hi[i] = std::max(hi[i], ghi[i]);
  }
  if (s.surfaces.empty()) return {};
  const Vec3 centre = (lo + hi) * 0.5;
  return {centre, std::max(length(hi - centre), 1e-3)};
}

void add_lights_distributions(RenderScene& s) {
  s.bounds = bounds_of(s);
  set_light_distributions(s);  // scene/update.cpp: also after a light's scale changes
}

// ---- the steps of compile, in order --------------------------------------------------------

// A scattering medium: its density scales the absorption too, each absorber's field becoming
// its concentration times the density (the builder requires numbers for those concentrations).
ScatteringMedium lower_scattering(RenderScene& s, const MediumDesc& m) {
  ScatteringMedium sc;
  const ConcentrationField density = m.scattering->density.value_or(ConcentrationField{ConstantField{1.0}});
  auto absorber = [&](const Spectrum& epsilon, double concentration) {
    sc.absorbers.push_back({add_spectrum(s, epsilon, SpectrumRole::absorption), scaled(density, concentration)});
  };
  const bool scale = m.scattering->density && m.scattering->density_scales_absorption;
  auto unscaled = [&](const Spectrum& epsilon, const ConcentrationField& field) {
    sc.absorbers.push_back({add_spectrum(s, epsilon, SpectrumRole::absorption), field});
  };
  if (m.field_absorbers.empty()) {
    if (m.absorbing) scale ? absorber(m.sigma_a_per_m, 1.0) : unscaled(m.sigma_a_per_m, ConstantField{1.0});
  } else {
    for (const FieldAbsorberDesc& a : m.field_absorbers) {
      if (!scale) unscaled(a.epsilon_per_m, a.field);
      else absorber(a.epsilon_per_m, std::get<ConstantField>(a.field).value);
    }
  }
  if (m.scattering->sigma_a_per_m) absorber(*m.scattering->sigma_a_per_m, 1.0);
  assert(sc.absorbers.size() <= kMaxAbsorbersPerMedium);  // SceneBuilder::medium counts them
  sc.sigma_s = add_spectrum(s, m.scattering->sigma_s_per_m, SpectrumRole::coefficient);
  sc.density = density;
  sc.phase = m.scattering->phase;
  return sc;
}

SceneMedium lower_medium(RenderScene& s, const MediumDesc& m) {
  SceneMedium sm;
  sm.name = m.name;
  if (m.scattering) {
    sm.medium = lower_scattering(s, m);
    s.scatters = true;
  } else if (m.field_absorbers.empty()) {
    sm.medium = HomogeneousMedium{add_spectrum(s, m.sigma_a_per_m, SpectrumRole::absorption), m.absorbing};
  } else {
    FieldMedium f;
    for (const FieldAbsorberDesc& a : m.field_absorbers)
      f.absorbers.push_back({add_spectrum(s, a.epsilon_per_m, SpectrumRole::absorption), a.field});
    sm.medium = std::move(f);
  }
  sm.ior = add_spectrum(s, m.ior, SpectrumRole::point);
  sm.ior_reference = ior_at(m.ior, kReferenceWavelengthNm);
  sm.dispersive = is_dispersive(m.ior);
  s.dispersive = s.dispersive || sm.dispersive;
  return sm;
}

// Every medium, the predefined ones first (unless the scene redefines them), then the world's.
void lower_media(RenderScene& s, const SceneDesc& desc) {
  for (const MediumDesc& m : predefined_media())
    if (!desc.media.contains(m.name)) s.media.push_back(lower_medium(s, m));
  for (const auto& [name, m] : desc.media) s.media.push_back(lower_medium(s, m));
  s.world_medium = medium_index(s, desc.world_medium);
  assert(!scattering(s.media[static_cast<std::size_t>(s.world_medium)].medium));  // SceneBuilder::build refuses it
}

// The scene's objects, and a disk emitter for each spot light with a radius.
std::vector<ObjectDesc> objects_with_spot_disks(const SceneDesc& desc) {
  std::vector<ObjectDesc> objects = desc.objects;
  for (std::size_t i = 0; i < desc.lights.size(); ++i)
    if (desc.lights[i].radius_m > 0.0) objects.push_back(spot_disk(desc.lights[i], fmt::format("lights[{}]", i)));
  return objects;
}

// The object's triangles in world space, within the memory and triangle limits.
std::vector<ShapePart> tessellate(const ObjectDesc& o, const SceneDesc& desc, std::uint64_t& triangles,
                                  std::uint64_t available) {
  require_geometry_room(triangles + triangle_bound(o.shape), available, desc, o);
  std::vector<ShapePart> parts = make_shape(o.shape, fmt::format("{}: object '{}'", desc.file.string(), o.name));
  for (ShapePart& p : parts) {
    p.mesh = transformed(std::move(p.mesh), o.transform);
    check_world_positions(p.mesh, desc, o);
    triangles += p.mesh.triangles.size();
  }
  require_geometry_room(triangles, available, desc, o);  // a mesh file's count is known only now
  return parts;
}

// A texture of the object's material as an id into RenderScene::textures (-1: none). A texture
// needs texture coordinates on every part (`parts`: the object's triangles; nullptr for an
// analytic shape, whose hits always carry them).
int material_texture(RenderScene& s, const std::optional<TextureDesc>& t, TextureUse use, const ObjectDesc& o,
                     const std::vector<ShapePart>* parts, const SceneDesc& desc) {
  if (!t) return -1;
  if (parts)
    for (const ShapePart& part : *parts)
      if (part.mesh.uvs.empty())
        fail("{}: object '{}': its texture needs texture coordinates, and its shape has none", desc.file.string(), o.name);
  return add_texture(s.textures, *t->image, use, t->transform, t->sampler);
}

SurfaceMaterial surface_material(RenderScene& s, const MaterialDesc& material, const ObjectDesc& o,
                                 const std::vector<ShapePart>* parts, const SceneDesc& desc) {
  if (const auto* d = std::get_if<DiffuseDesc>(&material))
    return DiffuseMaterial{add_spectrum(s, d->reflectance, SpectrumRole::reflectance),
                           material_texture(s, d->reflectance_texture, TextureUse::reflectance, o, parts, desc)};
  if (const auto* t = std::get_if<ThinDielectricDesc>(&material))
    return ThinDielectricMaterial{t->ior, add_spectrum(s, t->tint, SpectrumRole::reflectance),
                                  material_texture(s, t->tint_texture, TextureUse::reflectance, o, parts, desc)};
  if (const auto* g = std::get_if<MetallicRoughnessDesc>(&material))
    return MetallicRoughnessMaterial{
        add_spectrum(s, g->base_colour, SpectrumRole::reflectance),
        material_texture(s, g->base_colour_texture, TextureUse::reflectance, o, parts, desc), g->metalness,
        g->roughness, material_texture(s, g->metallic_roughness_texture, TextureUse::data, o, parts, desc)};
  const auto& c = std::get<ConductorDesc>(material);
  return ConductorMaterial{add_spectrum(s, c.n, SpectrumRole::point), add_spectrum(s, c.k, SpectrumRole::point),
                           c.roughness, material_texture(s, c.roughness_texture, TextureUse::data, o, parts, desc)};
}

// What the object's surfaces are (an interface, which must be a closed shape; an emitter; an
// opaque material), the same for all its parts but their media.
Surface object_surface(RenderScene& s, const ObjectDesc& o, const std::vector<ShapePart>* parts, const SceneDesc& desc) {
  Surface base;
  base.object = o.name;
  base.roughness = o.roughness;
  if (o.normal_map) {
    base.normal_map = material_texture(s, o.normal_map->texture, TextureUse::data, o, parts, desc);
    base.normal_scale = o.normal_map->scale;
  }
  if (o.inside) {
    if (!shape_is_closed(o.shape))
      fail("{}: object '{}': a flat shape cannot bound medium '{}'; use it as an emitter or a material, or use a "
           "closed shape",
           desc.file.string(), o.name, *o.inside);
  } else if (o.emission) {
    base.kind = SurfaceKind::emitter;
  } else {
    base.kind = SurfaceKind::opaque;
    base.material = static_cast<int>(s.materials.size());
    s.materials.push_back(surface_material(s, *o.material, o, parts, desc));
  }
  return base;
}

// An interface's optics from the media on its two sides: index-matched (smooth), or the energy
// compensation table of its roughness and indices (one per distinct triple).
using AlbedoIndex = std::map<std::tuple<double, double, double>, int>;  // (alpha, eta front, eta behind)

void set_interface_optics(RenderScene& s, Surface& surface, AlbedoIndex& albedo_index) {
  if (surface.kind != SurfaceKind::interface) return;
  const SceneMedium& front = s.media[static_cast<std::size_t>(surface.medium_front)];
  const SceneMedium& behind = s.media[static_cast<std::size_t>(surface.medium_behind)];
  if (surface.roughness == 0.0) {
    surface.index_matched = indices_match(s, surface.medium_front, surface.medium_behind);
    s.smooth_glass = s.smooth_glass || !surface.index_matched;
    return;
  }
  const auto key = std::make_tuple(surface.roughness, front.ior_reference, behind.ior_reference);
  const auto [it, added] = albedo_index.try_emplace(key, static_cast<int>(s.dielectric_albedo.size()));
  if (added) s.dielectric_albedo.push_back(DielectricAlbedo::compute(std::get<0>(key), std::get<1>(key), std::get<2>(key)));
  surface.albedo = it->second;
}

// Each part into the ray scene, with its surface: the media on its two sides, its optics, its
// area lights.
void add_parts(RenderScene& s, const ObjectDesc& o, const std::vector<ShapePart>& parts, const Surface& base,
               const SceneDesc& desc, AlbedoIndex& albedo_index) {
  const int inside = o.inside ? medium_index(s, *o.inside) : -1;
  const int outside = medium_index(s, o.outside.value_or(desc.world_medium));
  const int contents = o.contents ? medium_index(s, *o.contents) : -1;
  auto pick = [&](Side side) { return side == Side::object ? inside : side == Side::contents ? contents : outside; };
  const int emission_texture =
      o.emission ? material_texture(s, o.emission->texture, TextureUse::reflectance, o, &parts, desc) : -1;
  for (const ShapePart& p : parts) {
    Surface surface = base;
    surface.medium_behind = pick(p.behind);
    surface.medium_front = pick(p.in_front);
    set_interface_optics(s, surface, albedo_index);
    const std::uint32_t id = s.rays.add(p.mesh);
    if (id != s.surfaces.size()) fail("internal error: geometry ids out of order");
    if (base.kind == SurfaceKind::emitter) add_area_lights(s, surface, id, p.mesh, *o.emission, emission_texture);
    s.surfaces.push_back(surface);
  }
}

// The objects with a priority as RenderScene::nested, by priority and then by their order in the
// scene; returns each object's index there (-1: none).
std::vector<int> order_nested(RenderScene& s, const std::vector<ObjectDesc>& objects, const SceneDesc& desc) {
  std::vector<std::size_t> with;
  for (std::size_t i = 0; i < objects.size(); ++i)
    if (objects[i].priority) with.push_back(i);
  if (with.size() > kMaxNestedObjects)
    fail("{}: object '{}': at most {} objects may have a priority", desc.file.string(), objects[with.back()].name,
         kMaxNestedObjects);
  std::stable_sort(with.begin(), with.end(),
                   [&](std::size_t a, std::size_t b) { return *objects[a].priority < *objects[b].priority; });
  std::vector<int> k_of(objects.size(), -1);
  for (const std::size_t i : with) {
    const ObjectDesc& o = objects[i];
    k_of[i] = static_cast<int>(s.nested.size());
    s.nested.push_back({static_cast<int>(*o.priority), medium_index(s, *o.inside), medium_index(s, o.outside.value_or(desc.world_medium))});
  }
  return k_of;
}

// A nested object's surfaces: geometry ids [first, last), and their bounding box, for the
// overlap check.
struct NestedRange {
  std::uint32_t first = 0, last = 0;
  std::string name;
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
};

NestedRange nested_range(const RenderScene& s, std::uint32_t first, std::uint32_t last, const std::string& name) {
  NestedRange r{first, last, name};
  for (std::uint32_t g = first; g < last; ++g) {
    const auto [lo, hi] = s.rays.bounds(g);
    for (std::size_t i = 0; i < 3; ++i) r.lo[i] = std::min(r.lo[i], lo[i]), r.hi[i] = std::max(r.hi[i], hi[i]);
  }
  return r;
}

bool boxes_overlap(const NestedRange& a, const NestedRange& b) {
  for (std::size_t i = 0; i < 3; ++i)
    if (a.hi[i] < b.lo[i] || b.hi[i] < a.lo[i]) return false;
  return true;
}

// How many times a ray from p along d crosses the surfaces of geometry ids [first, last).
int crossings_of(const RenderScene& s, Vec3 p, const Vec3& d, std::uint32_t first, std::uint32_t last) {
  constexpr int kMaxProbeHits = 1024;
  int count = 0;
  for (int step = 0; step < kMaxProbeHits; ++step) {
    const auto hit = s.rays.intersect({p, d});
    if (!hit) break;
    if (hit->geometry >= first && hit->geometry < last) ++count;
    p = offset_ray_origin(*hit, d);
  }
  return count;
}

// Whether some vertex of `a` (up to kOverlapProbes of them, evenly spread) lies inside `b`: an
// odd number of crossings of b's surface along a direction no axis-aligned face is parallel to.
// An analytic sphere or cylinder has no vertices: its centre, a point inside it, stands for them.
bool vertex_inside(const RenderScene& s, const NestedRange& a, const NestedRange& b) {
  constexpr std::size_t kOverlapProbes = 256;
  const Vec3 d = normalize(Vec3{0.5773, 0.6172, 0.5345});
  std::vector<Vec3> points;
  for (std::uint32_t g = a.first; g < a.last; ++g) {
    const auto& positions = s.rays.mesh(g).positions;
    if (positions.empty()) {
      const auto [lo, hi] = s.rays.bounds(g);
      points.push_back((lo + hi) * 0.5);
    }
    points.insert(points.end(), positions.begin(), positions.end());
  }
  const std::size_t stride = std::max<std::size_t>(1, points.size() / kOverlapProbes);
  for (std::size_t i = 0; i < points.size(); i += stride)
    if (crossings_of(s, points[i], d, b.first, b.last) % 2 == 1) return true;
  return false;
}

// Two overlapping objects of one priority with different media leave the overlap's medium
// undecided: refused, naming both. The overlap is found where a vertex of one lies inside the
// other (vertex_inside); one that no probed vertex shows goes to the later object (docs).
void check_priority_ties(const RenderScene& s, const std::vector<NestedRange>& ranges, const SceneDesc& desc) {
  for (std::size_t a = 0; a < ranges.size(); ++a)
    for (std::size_t b = a + 1; b < ranges.size(); ++b) {
      const NestedObject &na = s.nested[a], &nb = s.nested[b];
      if (na.priority != nb.priority || na.inside == nb.inside || !boxes_overlap(ranges[a], ranges[b])) continue;
      if (vertex_inside(s, ranges[a], ranges[b]) || vertex_inside(s, ranges[b], ranges[a]))
        fail("{}: objects '{}' and '{}' overlap with the same priority {} and different media ('{}', '{}'): give one "
             "a higher priority",
             desc.file.string(), ranges[a].name, ranges[b].name, na.priority,
             s.media[static_cast<std::size_t>(na.inside)].name, s.media[static_cast<std::size_t>(nb.inside)].name);
    }
}

// Whether an emitting object is an exact emitting sphere (lights/light.h: SphereLight, sampled by
// the solid angle it subtends): an analytic sphere whose emission is one-sided, untextured and
// without a spot profile, placed by a transform that keeps it a sphere (a rotation, a uniform
// scale and a translation).
bool emitting_sphere(const ObjectDesc& o) {
  const auto* sphere = std::get_if<SphereShape>(&o.shape);
  if (!sphere || sphere->tessellate || !o.emission || o.inside || o.emission->two_sided || o.emission->spot ||
      o.emission->texture)
    return false;
  return o.transform.similarity_scale() > 0.0;
}

// A sphere, cylinder or disk that is not an emitter stays exact, and so does an emitting sphere
// (emitting_sphere); other emitters are sampled by triangle (lights/light.h: AreaLight), so they
// are tessellated.
std::optional<AnalyticShape> analytic_shape(const ObjectDesc& o, const SceneDesc& desc) {
  if (o.normal_map) return std::nullopt;  // a normal map needs the triangles' tangents
  if (o.emission && !emitting_sphere(o)) return std::nullopt;
  const auto surface = analytic_surface(o.shape, fmt::format("{}: object '{}'", desc.file.string(), o.name));
  if (!surface) return std::nullopt;
  return AnalyticShape{*surface, o.transform};
}

// An analytic shape is one part, closed by construction (a sphere or a capped cylinder) or flat
// (a disk, refused as a medium's boundary by object_surface): nothing to weld or check.
void add_analytic(RenderScene& s, const ObjectDesc& o, const AnalyticShape& shape, const Surface& base,
                  const SceneDesc& desc, AlbedoIndex& albedo_index) {
  Surface surface = base;
  surface.medium_behind = o.inside ? medium_index(s, *o.inside) : -1;
  surface.medium_front = medium_index(s, o.outside.value_or(desc.world_medium));
  set_interface_optics(s, surface, albedo_index);
  const std::uint32_t id = s.rays.add(shape);
  if (id != s.surfaces.size()) fail("internal error: geometry ids out of order");
  if (surface.kind == SurfaceKind::emitter) {  // an emitting sphere: one light, its hits' primitive 0
    surface.first_light = static_cast<int>(s.lights.size());
    const double radius_m =
        std::get<SphereSurface>(shape.surface).radius_m * length(shape.to_world.linear * Vec3{1, 0, 0});
    s.lights.push_back(SphereLight{id, shape.to_world.apply(Vec3{}), radius_m,
                                   add_spectrum(s, o.emission->radiance, SpectrumRole::radiance)});
  }
  const auto [lo, hi] = s.rays.bounds(id);
  Mesh corners;
  corners.positions = {lo, hi};
  check_world_positions(corners, desc, o);
  s.surfaces.push_back(surface);
}

void add_geometry(RenderScene& s, const SceneDesc& desc) {
  AlbedoIndex albedo_index;
  std::uint64_t triangles = 0;
  const std::uint64_t available = memory_available_bytes();
  const std::vector<ObjectDesc> objects = objects_with_spot_disks(desc);
  const std::vector<int> nested = order_nested(s, objects, desc);
  std::vector<NestedRange> ranges(s.nested.size());
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const ObjectDesc& o = objects[i];
    const auto first = static_cast<std::uint32_t>(s.surfaces.size());
    if (const auto shape = analytic_shape(o, desc)) {
      Surface base = object_surface(s, o, nullptr, desc);
      base.nested = nested[i];
      add_analytic(s, o, *shape, base, desc, albedo_index);
    } else {
      const std::vector<ShapePart> parts = tessellate(o, desc, triangles, available);
      Surface base = object_surface(s, o, &parts, desc);
      base.nested = nested[i];
      if (o.inside) check_closed(parts, o, desc);
      add_parts(s, o, parts, base, desc, albedo_index);
    }
    if (nested[i] >= 0)
      ranges[static_cast<std::size_t>(nested[i])] =
          nested_range(s, first, static_cast<std::uint32_t>(s.surfaces.size()), o.name);
  }
  s.rays.commit();
  for (const Surface& surface : s.surfaces)
    if (surface.medium_behind >= 0) s.media[static_cast<std::size_t>(surface.medium_behind)].enclosed = true;
  check_priority_ties(s, ranges, desc);
}

// The delta lights (spots with a radius became disks), then the environment map or the
// constant background.
void add_lights(RenderScene& s, const SceneDesc& desc) {
  for (const DeltaLightDesc& l : desc.lights)
    if (!(l.radius_m > 0.0)) add_delta_light(s, l);
  if (s.environment) {
    s.environment_light = static_cast<int>(s.lights.size());
    s.lights.push_back(EnvironmentLight{s.environment.get()});
  } else {
    s.background_light = static_cast<int>(s.lights.size());
    s.lights.push_back(BackgroundLight{add_spectrum(s, desc.background.radiance, SpectrumRole::radiance)});
  }
}

// Whether a surface is smooth glass that next-event estimation solves its way through: a smooth
// interface between two media, neither dispersive, without a normal map.
bool clear_smooth_interface(const RenderScene& s, const Surface& f) {
  return f.kind == SurfaceKind::interface && f.roughness == 0.0 && !f.index_matched && f.normal_map < 0 &&
         f.medium_front >= 0 && f.medium_behind >= 0 && !s.media[static_cast<std::size_t>(f.medium_front)].dispersive &&
         !s.media[static_cast<std::size_t>(f.medium_behind)].dispersive;
}

// The exact spheres next-event estimation reaches lights through (ManifoldCaster), the first
// kMaxCasters of them: each costs a solve at every vertex.
void add_casters(RenderScene& s) {
  for (std::uint32_t g = 0; g < s.surfaces.size() && s.casters.size() < kMaxCasters; ++g) {
    const Surface& f = s.surfaces[g];
    if (!clear_smooth_interface(s, f) || f.nested >= 0) continue;
    const AnalyticShape* shape = s.rays.analytic(g);
    const auto* sphere = shape ? std::get_if<SphereSurface>(&shape->surface) : nullptr;
    const double scale = shape ? shape->to_world.similarity_scale() : 0.0;
    if (!sphere || scale == 0.0) continue;
    const bool inside_scatters = scattering(s.media[static_cast<std::size_t>(f.medium_behind)].medium) != nullptr;
    s.casters.push_back(ManifoldCaster{g, shape->to_world.apply(Vec3{}), sphere->radius_m * scale, !inside_scatters});
  }
}

// Which emitters are small seen from the glass (Surface::small_lamp): those that subtend less than
// kLampChainSolidAngle seen from the nearest point of a smooth refracting mesh or exact cylinder (an
// area light's whole emitter: its area over the squared distance from its centroid; a sphere: its
// cone from its centre's distance). A lamp inside a glass globe or tube is measured from its wall.
// Also whether there is such a cylinder (RenderScene::glass_cylinders).
void mark_small_lamps(RenderScene& s) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<std::uint32_t> glass;
  // An exact cylinder whose side stays circular (its base's centre, axis and radius; its length):
  // its distance exactly, to its side or a cap (from inside, to the nearest wall).
  struct Cylinder {
    CircularSide side;
    double length_m = 0.0;
    double distance(const Vec3& p) const {
      const Vec3 rel = p - side.on_axis;
      const double t = dot(rel, side.axis), r = length(rel - side.axis * t);
      const double beyond = t < 0.0 ? -t : t > length_m ? t - length_m : 0.0;
      if (beyond > 0.0) return std::hypot(beyond, std::max(0.0, r - side.radius_m));
      return r > side.radius_m ? r - side.radius_m : std::min({side.radius_m - r, t, length_m - t});
    }
  };
  std::vector<std::optional<Cylinder>> cylinders;  // by entry of `glass`
  std::size_t triangles = 0, emitters = 0;
  for (std::uint32_t g = 0; g < s.surfaces.size(); ++g) {
    const Surface& f = s.surfaces[g];
    const bool smooth = f.kind == SurfaceKind::interface && f.roughness == 0.0 && !f.index_matched && f.normal_map < 0;
    const AnalyticShape* shape = s.rays.analytic(g);
    if (smooth && !shape) glass.push_back(g), cylinders.emplace_back(), triangles += s.rays.mesh(g).triangles.size();
    const auto* cylinder = shape ? std::get_if<CylinderSurface>(&shape->surface) : nullptr;
    const auto side = cylinder ? circular_side(*cylinder, shape->to_world) : std::nullopt;
    if (side && clear_smooth_interface(s, f)) {
      const double length_m = cylinder->height_m * length(shape->to_world.linear * Vec3{0, 1, 0});
      glass.push_back(g), cylinders.emplace_back(Cylinder{*side, length_m}), s.glass_cylinders = true;
    }
    emitters += f.kind == SurfaceKind::emitter;
  }
  if (glass.empty()) return;
  // The distance from p to the nearest glass: to every triangle, or (past some 10⁸ tests, which a
  // scene of many lamps and dense glass would take seconds over) to each mesh's bounding box, which
  // is never farther (a lamp then counts as larger than it is, and the chains run less).
  const bool every_triangle = triangles * emitters < 100'000'000;
  std::vector<std::array<Vec3, 2>> boxes;
  for (const std::uint32_t g : glass) boxes.push_back(s.rays.bounds(g));
  auto nearest_glass = [&](const Vec3& p) {
    double best = kInf;
    for (std::size_t k = 0; k < glass.size(); ++k) {
      if (cylinders[k]) {
        best = std::min(best, cylinders[k]->distance(p));
        continue;
      }
      const auto& [lo, hi] = boxes[k];
      const Vec3 outside{std::max({0.0, lo.x - p.x, p.x - hi.x}), std::max({0.0, lo.y - p.y, p.y - hi.y}),
                         std::max({0.0, lo.z - p.z, p.z - hi.z})};
      const double to_box = length(outside);
      if (!every_triangle || to_box >= best) {
        best = std::min(best, to_box);
        continue;
      }
      const Mesh& m = s.rays.mesh(glass[k]);
      for (const auto& t : m.triangles)
        best = std::min(best, triangle_distance(p, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]));
    }
    return best;
  };
  for (std::uint32_t g = 0; g < s.surfaces.size(); ++g) {
    Surface& f = s.surfaces[g];
    if (f.kind != SurfaceKind::emitter || f.first_light < 0) continue;
    const Light& light = s.lights[static_cast<std::size_t>(f.first_light)];
    double solid_angle = kInf;
    if (const auto* sphere = std::get_if<SphereLight>(&light)) {
      const double d = nearest_glass(sphere->centre_m);
      if (d > sphere->radius_m)
        solid_angle = 2.0 * std::numbers::pi *
                      (1.0 - std::sqrt(1.0 - sphere->radius_m * sphere->radius_m / (d * d)));
    } else if (std::holds_alternative<AreaLight>(light)) {
      // Its triangles' area lights (one each): the emitter's area and area-weighted centroid.
      double area_m2 = 0.0;
      Vec3 centroid{};
      const std::size_t count = s.rays.mesh(g).triangles.size();
      for (std::size_t p = 0; p < count; ++p) {
        const auto& a = std::get<AreaLight>(s.lights[static_cast<std::size_t>(f.first_light) + p]);
        area_m2 += a.area_m2;
        centroid += (a.p0 + a.p1 + a.p2) * (a.area_m2 / 3.0);
      }
      const double d = area_m2 > 0.0 ? nearest_glass(centroid / area_m2) : 0.0;
      if (d > 0.0) solid_angle = area_m2 / (d * d);
    }
    f.small_lamp = solid_angle < kLampChainSolidAngle;
    s.small_lamps = s.small_lamps || f.small_lamp;
  }
}

}  // namespace

bool indices_match(const RenderScene& s, int a, int b) {
  if (a == b) return true;
  const SceneMedium& ma = s.media[static_cast<std::size_t>(a)];
  const SceneMedium& mb = s.media[static_cast<std::size_t>(b)];
  return !ma.dispersive && !mb.dispersive && ma.ior_reference == mb.ior_reference;
}

namespace {

// SceneMedium::sealed: a path's medium changes only at a surface, and a shadow ray crosses one
// only where its two sides' indices match (indices_match); where no medium on any surface, nor the
// world's, matches this one's, a ray that starts inside it stops at the first surface that leaves
// it (a mesh object's inside is closed: check_closed).
void mark_sealed_media(RenderScene& s) {
  std::vector<bool> used(s.media.size(), false);
  used[static_cast<std::size_t>(s.world_medium)] = true;
  for (const Surface& surface : s.surfaces)
    for (const int m : {surface.medium_front, surface.medium_behind})
      if (m >= 0) used[static_cast<std::size_t>(m)] = true;
  for (std::size_t m = 0; m < s.media.size(); ++m) {
    SceneMedium& medium = s.media[m];
    if (!medium.enclosed || static_cast<int>(m) == s.world_medium) continue;
    medium.sealed = true;
    for (std::size_t k = 0; k < s.media.size(); ++k)
      if (k != m && used[k] && indices_match(s, static_cast<int>(m), static_cast<int>(k))) medium.sealed = false;
  }
}

}  // namespace

RenderScene compile(const SceneDesc& desc) {
  RenderScene s;
  s.file = desc.file;
  s.camera = desc.camera;
  assert(!desc.environment || desc.environment_map);  // the builder reads the map
  s.environment = desc.environment_map;
  lower_media(s, desc);
  add_geometry(s, desc);
  mark_sealed_media(s);
  add_lights(s, desc);
  add_lights_distributions(s);
  add_casters(s);
  mark_small_lamps(s);
  return s;
}

}  // namespace bouguer
