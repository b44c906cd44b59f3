#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string_view>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/io/atomic_file.h"
#include "bouguer/core/csv.h"
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

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// The header's next whitespace-separated word; empty at the end of the bytes.
std::string_view next_word(std::string_view bytes, std::size_t& pos) {
  while (pos < bytes.size() && is_space(bytes[pos])) ++pos;
  const std::size_t start = pos;
  while (pos < bytes.size() && !is_space(bytes[pos])) ++pos;
  return bytes.substr(start, pos - start);
}

template <typename T>
bool parse_whole(std::string_view word, T& out) {
  const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), out);
  return !word.empty() && ec == std::errc() && ptr == word.data() + word.size();
}

}  // namespace

Film read_pfm(const std::filesystem::path& path) {
  const std::string name = path.string();
  const std::string bytes = read_file_bytes(path, kMaxImageFileBytes);
  std::size_t pos = 0;
  const std::string_view magic = next_word(bytes, pos);
  if (magic != "PF" && magic != "Pf") fail("{}: not a PFM file (expected 'PF' or 'Pf' header)", name);
  long long width = 0, height = 0;
  double scale = 0.0;
  const std::string_view w = next_word(bytes, pos), h = next_word(bytes, pos), sc = next_word(bytes, pos);
  if (!parse_whole(w, width) || !parse_whole(h, height) || !parse_whole(sc, scale))
    fail("{}: PFM header '{} {} {}' is not 'width height scale'", name, excerpt(w), excerpt(h), excerpt(sc));
  if (width <= 0 || height <= 0 || width > kMaxImageDimension || height > kMaxImageDimension ||
      static_cast<std::size_t>(width * height) > kMaxImagePixels)
    fail("{}: PFM size {} × {} is outside 1 × 1 .. {} × {} pixels and {} pixels in all (docs/limits.md)", name, width,
         height, kMaxImageDimension, kMaxImageDimension, kMaxImagePixels);
  if (scale == 0.0 || !std::isfinite(scale)) fail("{}: PFM scale '{}' must be a non-zero number", name, excerpt(sc));
  // The header ends with a single whitespace character; the pixels follow it.
  if (pos >= bytes.size()) fail("{}: PFM file ends after its header (no pixels)", name);
  const std::size_t offset = pos + 1;
  const int channels = magic == "PF" ? 3 : 1;
  const std::size_t count = static_cast<std::size_t>(width * height) * channels;
  if (bytes.size() - offset < count * sizeof(float))
    fail("{}: PFM file is truncated ({} bytes of pixels, {} expected)", name, bytes.size() - offset,
         count * sizeof(float));
  const bool file_little = scale < 0.0;
  const bool swap = file_little != (std::endian::native == std::endian::little);
  Film film(static_cast<int>(width), static_cast<int>(height));
  for (int row = 0; row < film.height; ++row) {
    const int y = film.height - 1 - row;
    for (int x = 0; x < film.width; ++x) {
      float v[3];
      const std::size_t at = offset + (static_cast<std::size_t>(row) * film.width + x) * channels * sizeof(float);
      std::memcpy(v, bytes.data() + at, channels * sizeof(float));
      for (int c = 0; c < channels; ++c) {
        v[c] = swap ? byteswap(v[c]) : v[c];
        if (!std::isfinite(v[c]))
          fail("{}: pixel ({}, {}) holds {}, not a finite number", name, x, y, static_cast<double>(v[c]));
      }
      film.set_rgb(x, y, channels == 3 ? Vec3f{v[0], v[1], v[2]} : Vec3f{v[0], v[0], v[0]});
    }
  }
  return film;
}

}  // namespace bouguer
