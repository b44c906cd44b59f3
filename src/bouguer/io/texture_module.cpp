// The OpenImageIO module (io/texture_module.h): a texture image's pixels as floats. Built as
// libbouguer_texture.so and loaded on first use; it reports problems as messages, never as
// exceptions of the library's types (it shares no code with it).
#include "bouguer/io/texture_module.h"

#include <fmt/format.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <new>

namespace {

using bouguer::texture_module::Image;
using bouguer::texture_module::Limits;
using bouguer::texture_module::Result;

// Thrown inside the module only, caught at its edge.
struct Problem {
  std::string message;
};

template <typename... Args>
[[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) {
  throw Problem{fmt::format(f, std::forward<Args>(args)...)};
}

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

void check_declared_size(const OIIO::ImageSpec& spec, const std::string& name, const Limits& limits) {
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 || spec.depth > 1)
    fail("{}: not a two-dimensional image ({} × {} × {}, {} channels)", name, spec.width, spec.height, spec.depth,
         spec.nchannels);
  if (spec.width > limits.max_dimension || spec.height > limits.max_dimension ||
      static_cast<std::int64_t>(spec.width) * static_cast<std::int64_t>(spec.height) > limits.max_pixels)
    fail("{}: a texture of {} × {} pixels is larger than the limit of {} pixels (docs/limits.md)", name, spec.width,
         spec.height, limits.max_pixels);
}

void read_open(OIIO::ImageInput& in, const std::string& name, const Limits& limits, Image& image) {
  const OIIO::ImageSpec& spec = in.spec();
  check_declared_size(spec, name, limits);
  const int channels = std::min(spec.nchannels, spec.nchannels >= 3 ? 3 : 1);
  const auto pixels = static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height);
  std::vector<float> values(pixels * static_cast<std::size_t>(channels));
  if (!in.read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, values.data()))
    fail("{}: {}", name, first_line(in.geterror()));
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
}

// Runs `body`, turning what it throws into a problem naming the image.
template <typename Body>
Result guarded(const std::string& name, Body body) {
  try {
    body();
    return {};
  } catch (const Problem& p) {
    return {false, p.message};
  } catch (const std::bad_alloc&) {
    return {false, fmt::format("{}: OpenImageIO ran out of memory reading it (is the file damaged?)", name)};
  } catch (const std::exception& e) {
    return {false, fmt::format("{}: OpenImageIO cannot read it: {}", name, e.what())};
  }
}

Result read_file(const std::string& name, const Limits& limits, Image& out) {
  return guarded(name, [&] {
    auto in = OIIO::ImageInput::open(name);
    if (!in) fail("{}: {}", name, first_line(OIIO::geterror()));
    read_open(*in, name, limits, out);
  });
}

Result read_memory(const unsigned char* bytes, std::size_t size, const std::string& name, const Limits& limits,
                   Image& out) {
  return guarded(name, [&] {
    OIIO::Filesystem::IOMemReader reader(bytes, size);
    auto in = OIIO::ImageInput::open(name, nullptr, &reader);
    if (!in) fail("{}: {}", name, first_line(OIIO::geterror()));
    read_open(*in, name, limits, out);
  });
}

const bouguer::texture_module::Api kApi{1, read_file, read_memory};

}  // namespace

extern "C" const bouguer::texture_module::Api* bouguer_texture_module_api() {
  return &kApi;
}
