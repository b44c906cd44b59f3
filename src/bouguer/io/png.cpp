#include <png.h>

#include <cstdio>
#include <memory>
#include <vector>

#include "bouguer/core/error.h"
#include "bouguer/io/atomic_file.h"
#include "bouguer/io/image_io.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {

void write_png(const std::filesystem::path& path, const Film& film) {
  std::vector<unsigned char> bytes(film.rgb.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = srgb_encode_8bit(film.rgb[i]);
  write_atomically(path, [&](const std::filesystem::path& temp) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = static_cast<png_uint_32>(film.width);
    image.height = static_cast<png_uint_32>(film.height);
    image.format = PNG_FORMAT_RGB;
    if (!png_image_write_to_file(&image, temp.c_str(), 0, bytes.data(), 0, nullptr)) {
      const std::string reason = image.message;
      png_image_free(&image);
      fail("{}: PNG write failed: {}", path.string(), reason);
    }
  });
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
