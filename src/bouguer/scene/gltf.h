#pragma once
// glTF 2.0 assets (.gltf with its buffers, .glb; Draco meshes) into the SceneBuilder's plain inputs.
// One job: read the asset, bounded (the file's size, and every index, count, offset and stride it
// declares checked against what it has before anything is allocated), into plain records in the
// asset's metres with its node transforms applied; then hand them to the builder as objects,
// media, a camera and lights, whose values the builder checks. What each glTF quantity becomes
// is in docs/assets.md. Every error is one line naming the file and the place in it:
//   bottle.glb: accessors[3]: count 10 exceeds bufferView 1 (64 bytes hold 5 of stride 12)
// Textures: embedded images are decoded by OpenImageIO as tinygltf meets them, external ones when
// a material uses them (gltf.cpp); a sampler's wrap modes and magFilter come with them.
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bouguer/geometry/shapes.h"
#include "bouguer/geometry/transform.h"
#include "bouguer/scene/builder.h"
#include "bouguer/scene/description.h"
#include "bouguer/scene/values.h"

namespace bouguer {

// A material's texture: its image decoded (OpenImageIO, through io/texture_image.h), its
// KHR_texture_transform, its sampler's wrapS and wrapT (as the builder's names: "repeat", "clamp",
// "mirror") and magFilter NEAREST, and its place in the asset for messages.
struct GltfTexture {
  std::shared_ptr<const TextureImage> image;
  UvTransform transform;
  std::string name;  // "images[2]" or the file it came from
  std::array<std::string, 2> wrap{"repeat", "repeat"};
  bool nearest_magnification = false;
};

// A glTF material's factors and textures, with the extensions Bouguer reads.
struct GltfMaterial {
  std::string name;
  Vec3 base_color{1, 1, 1};  // linear
  // baseColorTexture, its texels already multiplied by base_color (and so linear).
  std::optional<GltfTexture> base_color_texture;
  double metallic = 1.0, roughness = 1.0;
  // metallicRoughnessTexture, its texels (as stored: data) times the factors: G roughness, B metalness.
  std::optional<GltfTexture> metallic_roughness_texture;
  Vec3 emissive{0, 0, 0};  // linear emissiveFactor
  double emissive_strength = 1.0;  // KHR_materials_emissive_strength
  // emissiveTexture, its texels sRGB-decoded and multiplied by `emissive` (as the base colour's).
  std::optional<GltfTexture> emissive_texture;
  // normalTexture (data, as stored) and its scale; occlusionTexture is not read (docs/assets.md).
  std::optional<GltfTexture> normal_texture;
  double normal_scale = 1.0;
  double transmission = 0.0;  // KHR_materials_transmission
  double thickness = 0.0;     // KHR_materials_volume: 0 is thin-walled
  Vec3 attenuation_color{1, 1, 1};
  std::optional<double> attenuation_distance_m;  // none: no absorption
  double ior = 1.5;         // KHR_materials_ior
  double dispersion = 0.0;  // KHR_materials_dispersion: 20 / V_d
  // The values clamped into what Bouguer models ("baseColorFactor[0] 1.2 as 1"), for the one
  // warning of the material (docs/assets.md).
  std::vector<std::string> clamped;
};

// One triangle primitive under one node, in the asset's frame (the node's world transform applied).
struct GltfPrimitive {
  TriangleMeshShape shape;
  int material = -1;  // into GltfAsset::materials; -1: the default material
  std::string place;  // "nodes[2].mesh 0.primitives[1]"
};

struct GltfCamera {
  Vec3 position_m, forward, up;  // the node's −z and +y in the asset's frame
  double yfov_rad = 0.8;
  double aspect = 0.0;  // width / height; 0 when the asset does not say
  std::string place;    // "cameras[0].perspective"
  std::vector<std::string> clamped;  // as GltfMaterial's
};

struct GltfLight {
  DeltaLightType type = DeltaLightType::point;
  Vec3 position_m, direction{0, 0, -1};
  Vec3 color{1, 1, 1};
  double intensity = 1.0;  // candela (point, spot) or lux (directional)
  double inner_cone_rad = 0.0, outer_cone_rad = 0.785398163397448;
  std::string place;  // "extensions.KHR_lights_punctual.lights[0]"
  std::vector<std::string> clamped;  // as GltfMaterial's
};

struct GltfAsset {
  std::vector<GltfMaterial> materials;
  std::vector<GltfPrimitive> primitives;
  std::vector<GltfCamera> cameras;  // in node order
  std::vector<GltfLight> lights;    // in node order
  std::optional<bool> studio;       // the default scene's extras.bouguer_studio, where it is a boolean
  // What was left out, with its place ("nodes[3]": a node of scale 0), one warning each.
  std::vector<std::pair<std::string, std::string>> notes;
};

bool is_gltf_file(const std::filesystem::path& path);  // by extension: .gltf or .glb

// The asset's default scene (or its root nodes), checked; an Error of one line otherwise.
GltfAsset read_gltf(const std::filesystem::path& path);

// What a Bouguer scene gives instead of a glTF material, by the material's name: one role, as an
// object takes it (scene-format.md).
struct GltfMaterialOverride {
  std::optional<std::string> inside, outside;
  std::optional<MaterialDesc> material;  // resolved by the front end (resolve_surface_material)
  std::optional<EmissionDesc> emission;
  double roughness = 0.0;
  std::optional<std::int64_t> priority;  // nested media (scene/nested.h); checked by the builder
};

struct GltfObjectInput {
  std::filesystem::path file;  // resolved against the scene's folder
  Transform transform;         // after the asset's own node transforms
  std::map<std::string, GltfMaterialOverride> materials;
  std::string name;  // the objects' prefix ("<name>: nodes[2] meshes[0].primitives[1]"); empty: the file's name
};

// The asset's primitives as objects (and the media its transmissive materials need), each
// material overridden by name where the scene says; `where` is the scene's object.
void add_gltf_objects(SceneBuilder& b, const GltfObjectInput& in, const Source& where);

// The asset as a whole scene (bouguer render asset.glb): its objects, its first camera (or one
// framing its bounds), its lights, the path tracer; and the default studio, a uniform white
// background, where the asset has neither punctual lights nor emitting materials. `studio` (the
// command line's --studio) says on or off instead, over the asset's own extras.bouguer_studio.
void load_gltf_scene(const std::filesystem::path& path, SceneBuilder& b, std::optional<bool> studio = std::nullopt);

}  // namespace bouguer
