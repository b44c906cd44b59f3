// Texture images through the OpenImageIO module (io/texture_module.h), loaded on first use.
#include "bouguer/io/texture_image.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string_view>

#include "bouguer/core/csv.h"
#include "bouguer/core/error.h"
#include "bouguer/core/limits.h"
#include "bouguer/core/module.h"
#include "bouguer/io/image_io.h"
#include "bouguer/io/texture_module.h"

namespace bouguer {
namespace {

// The module, loaded once: from where the build put it, else beside the program.
const texture_module::Api& module_api() {
  std::string problem;
  const auto* api = module_api_once<texture_module::Api>(BOUGUER_TEXTURE_MODULE, "bouguer_texture_module_api", false,
                                                         problem);
  if (!api) fail("texture images cannot be read: {}", problem);
  return *api;
}

TextureImage image_from(const texture_module::Result& r, texture_module::Image&& image) {
  if (!r.ok) fail("{}", r.message);
  return {image.width, image.height, std::move(image.rgb), image.srgb};
}

texture_module::Limits limits() {
  return {static_cast<std::int64_t>(kMaxTextureDimension), static_cast<std::int64_t>(kMaxTexturePixels)};
}

}  // namespace

// OpenEXR allocates what an EXR header states before it reads on (fuzz_texture found a 1.6 GB
// attribute): such files get the EXR reader's own header checks first.
constexpr std::string_view kExrMagic = "\x76\x2f\x31\x01";

TextureImage read_texture_image(const std::filesystem::path& file) {
  const std::string name = file.string();
  require_regular_file(file, kMaxImageFileBytes);
  {
    std::ifstream in(file, std::ios::binary);
    char magic[4] = {};
    in.read(magic, 4);
    if (std::string_view(magic, 4) == kExrMagic) check_exr_before_opening(read_file_bytes(file, kMaxImageFileBytes), name);
  }
  texture_module::Image image;
  const texture_module::Result r = module_api().read_file(name, limits(), image);
  return image_from(r, std::move(image));
}

TextureImage read_texture_image(std::span<const unsigned char> bytes, const std::string& name) {
  const std::string_view view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (view.starts_with(kExrMagic)) check_exr_before_opening(view, name);
  texture_module::Image image;
  const texture_module::Result r = module_api().read_memory(bytes.data(), bytes.size(), name, limits(), image);
  return image_from(r, std::move(image));
}

float srgb_to_linear(float encoded) {
  const float c = std::clamp(encoded, 0.0f, 1.0f);
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace bouguer
