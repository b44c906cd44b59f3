#include <png.h>

#include <vector>

#include "bouguer/core/error.h"
#include "bouguer/io/atomic_file.h"
#include "bouguer/io/image_io.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {

void write_png(const std::filesystem::path& path, const Film& film) {
  std::string bytes;
  try {
    bytes = encode_png(film);
  } catch (const Error& e) {
    fail("{}: {}", path.string(), e.what());
  }
  write_bytes_atomically(path, bytes);
}

std::string encode_png(const Film& film) {
  std::vector<unsigned char> pixels(film.rgb.size());
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = srgb_encode_8bit(film.rgb[i]);
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(film.width);
  image.height = static_cast<png_uint_32>(film.height);
  image.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&image, nullptr, &size, 0, pixels.data(), 0, nullptr))
    fail("PNG encoding failed: {}", image.message);
  std::string out(size, '\0');
  if (!png_image_write_to_memory(&image, out.data(), &size, 0, pixels.data(), 0, nullptr))
    fail("PNG encoding failed: {}", image.message);
  out.resize(size);
  return out;
}

}  // namespace bouguer
