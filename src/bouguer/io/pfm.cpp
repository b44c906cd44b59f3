#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "bouguer/core/error.h"
#include "bouguer/io/atomic_file.h"
#include "bouguer/io/csv.h"
#include "bouguer/io/image_io.h"

namespace bouguer {
namespace {

float byteswap(float f) {
  std::uint32_t u = std::bit_cast<std::uint32_t>(f);
  u = (u >> 24) | ((u >> 8) & 0xff00u) | ((u << 8) & 0xff0000u) | (u << 24);
  return std::bit_cast<float>(u);
}

}  // namespace

// PFM: "PF" (colour) or "Pf" (grey), width height, scale (negative: little-endian), then rows
// from the bottom of the image to the top.
void write_pfm(const std::filesystem::path& path, const Film& film) {
  write_atomically(path, [&](const std::filesystem::path& temp) {
    std::ofstream out(temp, std::ios::binary);
    out << "PF\n" << film.width << ' ' << film.height << "\n-1.0\n";
    const bool swap = std::endian::native == std::endian::big;
    for (int y = film.height - 1; y >= 0; --y) {
      for (int x = 0; x < film.width; ++x) {
        const Vec3f c = film.rgb_at(x, y);
        const float v[3] = {swap ? byteswap(c.x) : c.x, swap ? byteswap(c.y) : c.y, swap ? byteswap(c.z) : c.z};
        out.write(reinterpret_cast<const char*>(v), sizeof v);
      }
    }
    out.close();
    if (!out) fail("{}: PFM write failed", path.string());
  });
}

Film read_pfm(const std::filesystem::path& path) {
  const std::string bytes = read_text_file(path);
  std::istringstream in(bytes);
  std::string magic;
  int width = 0, height = 0;
  double scale = 0.0;
  in >> magic >> width >> height >> scale;
  if (!in || (magic != "PF" && magic != "Pf")) fail("{}: not a PFM file (expected 'PF' or 'Pf' header)", path.string());
  if (width <= 0 || height <= 0 || width > 1 << 16 || height > 1 << 16 || scale == 0.0 || !std::isfinite(scale))
    fail("{}: PFM header has an invalid size or scale", path.string());
  in.get();  // the single whitespace character that ends the header
  const int channels = magic == "PF" ? 3 : 1;
  const auto offset = static_cast<std::size_t>(in.tellg());
  const std::size_t count = static_cast<std::size_t>(width) * height * channels;
  if (bytes.size() < offset + count * sizeof(float))
    fail("{}: PFM file is truncated ({} bytes of pixels, {} expected)", path.string(), bytes.size() - offset,
         count * sizeof(float));
  const bool file_little = scale < 0.0;
  const bool swap = file_little != (std::endian::native == std::endian::little);
  Film film(width, height);
  for (int row = 0; row < height; ++row) {
    const int y = height - 1 - row;
    for (int x = 0; x < width; ++x) {
      float v[3];
      const std::size_t at = offset + (static_cast<std::size_t>(row) * width + x) * channels * sizeof(float);
      std::memcpy(v, bytes.data() + at, channels * sizeof(float));
      for (int c = 0; c < channels; ++c) v[c] = swap ? byteswap(v[c]) : v[c];
      film.set_rgb(x, y, channels == 3 ? Vec3f{v[0], v[1], v[2]} : Vec3f{v[0], v[0], v[0]});
    }
  }
  return film;
}

}  // namespace bouguer
