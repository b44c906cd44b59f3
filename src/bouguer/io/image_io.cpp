#include "bouguer/io/image_io.h"

#include <algorithm>
#include <cctype>

#include "bouguer/core/error.h"

namespace bouguer {
namespace {
std::string extension_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}
}  // namespace

void write_image(const std::filesystem::path& path, const Film& film) {
  const std::string ext = extension_of(path);
  if (ext == ".png") return write_png(path, film);
  if (ext == ".exr") return write_exr(path, film);
  if (ext == ".pfm") return write_pfm(path, film);
  fail("{}: unknown image type '{}' (use .png, .exr or .pfm)", path.string(), ext);
}

void write_image(const std::filesystem::path& path, const Film& film, const DisplayTransform& t) {
  // Each branch passes the film itself when nothing changes: a copy of a spectral film is large.
  if (extension_of(path) == ".png") {
    if (t.leaves_png()) return write_png(path, film);
    return write_png(path, displayed(film, t));
  }
  if (t.leaves_floats()) return write_image(path, film);
  return write_image(path, exposed(film, t));
}

Film read_image(const std::filesystem::path& path) {
  const std::string ext = extension_of(path);
  if (ext == ".exr") return read_exr(path);
  if (ext == ".pfm") return read_pfm(path);
  fail("{}: cannot read '{}' images (use .exr or .pfm renders)", path.string(), ext);
}

}  // namespace bouguer
