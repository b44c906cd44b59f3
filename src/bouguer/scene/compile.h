#pragma once
// compile: SceneDesc -> RenderScene, the immutable scene the integrators read. Shapes become
// triangles in one RayScene; every geometry id maps to a Surface that says what it is and which
// media lie on its two sides. Nothing here is looked up by name during rendering.
#include <cstdint>
#include <string>
#include <vector>

#include "bouguer/geometry/ray_scene.h"
#include "bouguer/materials/bsdf.h"
#include "bouguer/scene/description.h"

namespace bouguer {

enum class SurfaceKind { interface, emitter, opaque };

struct Surface {
  SurfaceKind kind = SurfaceKind::interface;
  int medium_behind = -1;  // index into RenderScene::media, on the side opposite the normal
  int medium_front = -1;   // on the side the normal points to
  int emission = -1;       // index into emissions (emitters)
  int material = -1;       // index into materials (opaque surfaces)
  double roughness = 0.0;  // interfaces: GGX alpha (0: smooth)
  int albedo = -1;         // rough interfaces: index into RenderScene::dielectric_albedo
  std::string object;      // for messages
};

struct EmissiveTriangle {
  std::uint32_t geometry = 0, primitive = 0;
  double area_m2 = 0.0;
};

struct RenderScene {
  std::filesystem::path file;
  CameraDesc camera;
  RenderSettings render;
  RayScene rays;
  std::vector<Surface> surfaces;  // by geometry id
  std::vector<MediumDesc> media;
  int world_medium = 0;
  std::vector<EmissionDesc> emissions;
  std::vector<MaterialDesc> materials;
  EmissionDesc background;
  std::optional<EnvironmentMap> environment;  // replaces the background when present
  std::vector<DeltaLightDesc> delta_lights;
  std::vector<EmissiveTriangle> lights;
  std::vector<double> light_cdf;  // cumulative area fractions, last = 1
  double light_area_m2 = 0.0;
  // Energy compensation of rough interfaces, tabulated with the two media's indices at
  // kReferenceWavelengthNm (the albedo varies by well under 1 % over a glass's dispersion).
  std::vector<DielectricAlbedo> dielectric_albedo;
};

RenderScene compile(const SceneDesc& desc);

}  // namespace bouguer
