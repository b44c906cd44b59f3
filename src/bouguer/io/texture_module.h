#pragma once
// The interface of the OpenImageIO module (libbouguer_texture.so, io/texture_module.cpp), the only
// code that links OpenImageIO. It is loaded with dlopen the first time a texture image is read
// (io/texture_image.cpp): linked into the program, OpenImageIO and the 260 libraries it needs
// (its image formats' codecs, OpenCV, DICOM, ...) cost every start of `bouguer`, every test
// process and every `import bouguer` about 0.25 s of dynamic relocation, which a scene without
// textures should not pay. Plain types only: the module shares no code with the library.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace bouguer::texture_module {

struct Result {
  bool ok = true;
  std::string message;  // names the image when not ok
};

// As io/texture_image.h's TextureImage.
struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;
  bool srgb = false;
};

// core/limits.h's, checked against the declared size before anything is allocated.
struct Limits {
  std::int64_t max_dimension = 0, max_pixels = 0;
};

struct Api {
  int version = 1;
  Result (*read_file)(const std::string& name, const Limits& limits, Image& out);
  // `name` names the bytes in messages; its extension tells OpenImageIO the format to try first.
  Result (*read_memory)(const unsigned char* bytes, std::size_t size, const std::string& name, const Limits& limits,
                        Image& out);
};

}  // namespace bouguer::texture_module

// The module's one exported symbol.
extern "C" const bouguer::texture_module::Api* bouguer_texture_module_api();
