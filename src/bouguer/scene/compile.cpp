#include "bouguer/scene/compile.h"

#include <map>
#include <tuple>

#include "bouguer/core/error.h"

namespace bouguer {
namespace {

int medium_index(const RenderScene& s, const std::string& name) {
  for (std::size_t i = 0; i < s.media.size(); ++i)
    if (s.media[i].name == name) return static_cast<int>(i);
  return -1;  // the loader has checked every name
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

void add_lights(RenderScene& s, std::uint32_t geometry, const Mesh& m) {
  for (std::uint32_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    const double area = 0.5 * length(cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
    if (area > 0.0) s.lights.push_back({geometry, i, area});
  }
}

}  // namespace

RenderScene compile(const SceneDesc& desc) {
  RenderScene s;
  s.file = desc.file;
  s.camera = desc.camera;
  s.render = desc.render;
  s.background = desc.background;
  if (desc.environment) {
    try {
      s.environment = load_environment(*desc.environment);
    } catch (const Error& e) {
      fail("{}: background.environment: {}", desc.file.string(), e.what());
    }
  }
  s.delta_lights = desc.lights;
  for (const auto& [name, m] : desc.media) s.media.push_back(m);
  s.world_medium = medium_index(s, desc.world_medium);
  std::map<std::tuple<double, double, double>, int> albedo_index;  // (alpha, eta front, eta behind)

  for (const ObjectDesc& o : desc.objects) {
    std::vector<ShapePart> parts = make_shape(o.shape, fmt::format("{}: object '{}'", desc.file.string(), o.name));
    for (ShapePart& p : parts) p.mesh = transformed(std::move(p.mesh), o.transform);
    Surface base;
    base.object = o.name;
    base.roughness = o.roughness;
    if (o.inside) {
      if (!shape_is_closed(o.shape))
        fail("{}: object '{}': a flat shape cannot bound medium '{}'; use it as an emitter or a material, or use a "
             "closed shape",
             desc.file.string(), o.name, *o.inside);
      check_closed(parts, o, desc);
    } else if (o.emission) {
      base.kind = SurfaceKind::emitter;
      base.emission = static_cast<int>(s.emissions.size());
      s.emissions.push_back(*o.emission);
    } else {
      base.kind = SurfaceKind::opaque;
      base.material = static_cast<int>(s.materials.size());
      s.materials.push_back(*o.material);
    }
    const int inside = o.inside ? medium_index(s, *o.inside) : -1;
    const int outside = medium_index(s, o.outside.value_or(desc.world_medium));
    const int contents = o.contents ? medium_index(s, *o.contents) : -1;
    auto pick = [&](Side side) { return side == Side::object ? inside : side == Side::contents ? contents : outside; };
    for (const ShapePart& p : parts) {
      Surface surface = base;
      surface.medium_behind = pick(p.behind);
      surface.medium_front = pick(p.in_front);
      if (surface.kind == SurfaceKind::interface && surface.roughness > 0.0) {
        const auto key = std::make_tuple(surface.roughness, ior_at(s.media[surface.medium_front].ior, kReferenceWavelengthNm),
                                         ior_at(s.media[surface.medium_behind].ior, kReferenceWavelengthNm));
        const auto [it, added] = albedo_index.try_emplace(key, static_cast<int>(s.dielectric_albedo.size()));
        if (added)
          s.dielectric_albedo.push_back(DielectricAlbedo::compute(std::get<0>(key), std::get<1>(key), std::get<2>(key)));
        surface.albedo = it->second;
      }
      const std::uint32_t id = s.rays.add(p.mesh);
      if (id != s.surfaces.size()) fail("internal: geometry ids out of order");
      s.surfaces.push_back(surface);
      if (base.kind == SurfaceKind::emitter) add_lights(s, id, p.mesh);
    }
  }
  s.rays.commit();
  for (const auto& l : s.lights) s.light_area_m2 += l.area_m2;
  double running = 0.0;
  for (const auto& l : s.lights) s.light_cdf.push_back((running += l.area_m2) / s.light_area_m2);
  return s;
}

}  // namespace bouguer
