#pragma once
// Texture images (PNG, JPEG, OpenEXR, TIFF, Radiance HDR, ...) read through OpenImageIO, in a module
// loaded on first use (io/texture_module.h) that no other file includes. The declared size is
// checked against core/limits.h (kMaxTextureDimension, kMaxTexturePixels) before anything is
// allocated; every failure is one Error naming the file.
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace bouguer {

// Pixels as read, rows from the top: three values per pixel (a grey image repeats its one channel,
// a grey-alpha image drops the alpha, RGBA drops the alpha), not yet decoded from sRGB.
struct TextureImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  // Whether the values are sRGB-encoded: the file says so (OpenImageIO's oiio:ColorSpace), or it
  // says nothing and holds 8- or 16-bit integers (PNG, JPEG, TIFF). Float formats are linear.
  bool srgb = false;
};

TextureImage read_texture_image(const std::filesystem::path& file);

// From bytes in memory (a glTF asset's embedded image); `name` names it in messages, and its
// extension (".png", ".jpg") tells OpenImageIO the format to try first.
TextureImage read_texture_image(std::span<const unsigned char> bytes, const std::string& name);

// The sRGB transfer function's inverse (IEC 61966-2-1): an encoded value in [0, 1] to linear.
float srgb_to_linear(float encoded);

}  // namespace bouguer
