// The only file that includes OpenImageIO.
#include "bouguer/io/texture_image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <string_view>

#include "bouguer/core/error.h"
#include "bouguer/core/csv.h"
#include "bouguer/io/image_io.h"
#include "bouguer/core/limits.h"

namespace bouguer {
namespace {

// OpenImageIO's own message, first line only (it may hold several).
std::string first_line(std::string message) {
  const auto end = message.find('\n');
  if (end != std::string::npos) message.resize(end);
  return message.empty() ? "not an image OpenImageIO can read" : message;
}

bool declared_srgb(const OIIO::ImageSpec& spec) {
  const std::string space = spec.get_string_attribute("oiio:ColorSpace");
  if (!space.empty()) return OIIO::Strutil::iequals(space, "sRGB");
  return spec.format == OIIO::TypeDesc::UINT8 || spec.format == OIIO::TypeDesc::UINT16;
}

void check_declared_size(const OIIO::ImageSpec& spec, const std::string& name) {
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.depth > 1)
    fail("{}: not a two-dimensional image ({} × {} × {}, {} channels)", name, spec.width, spec.height, spec.depth,
         spec.nchannels);
  if (spec.width > kMaxTextureDimension || spec.height > kMaxTextureDimension ||
      static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) > kMaxTexturePixels)
    fail("{}: a texture of {} × {} pixels is larger than the limit of {} pixels (docs/limits.md)", name, spec.width,
         spec.height, kMaxTexturePixels);
}

TextureImage read_open(OIIO::ImageInput& in, const std::string& name) {
  const OIIO::ImageSpec& spec = in.spec();
  check_declared_size(spec, name);
  const int channels = std::min(spec.nchannels, spec.nchannels >= 3 ? 3 : 1);
  const auto pixels = static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height);
  std::vector<float> values(pixels * static_cast<std::size_t>(channels));
  if (!in.read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, values.data()))
    fail("{}: {}", name, first_line(in.geterror()));
  TextureImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.srgb = declared_srgb(spec);
  image.rgb.resize(pixels * 3);
  for (std::size_t p = 0; p < pixels; ++p)
    for (std::size_t c = 0; c < 3; ++c) {
      const float v = values[p * static_cast<std::size_t>(channels) + (channels == 3 ? c : 0)];
      if (!std::isfinite(v)) fail("{}: pixel {} is not a finite number", name, p);
      image.rgb[p * 3 + c] = v;
    }
  return image;
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
  auto in = OIIO::ImageInput::open(name);
  if (!in) fail("{}: {}", name, first_line(OIIO::geterror()));
  return read_open(*in, name);
}

TextureImage read_texture_image(std::span<const unsigned char> bytes, const std::string& name) {
  const std::string_view view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (view.starts_with(kExrMagic)) check_exr_before_opening(view, name);
  OIIO::Filesystem::IOMemReader reader(bytes.data(), bytes.size());
  auto in = OIIO::ImageInput::open(name, nullptr, &reader);
  if (!in) fail("{}: {}", name, first_line(OIIO::geterror()));
  return read_open(*in, name);
}

float srgb_to_linear(float encoded) {
  const float c = std::clamp(encoded, 0.0f, 1.0f);
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace bouguer
