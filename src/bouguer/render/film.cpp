#include "bouguer/render/film.h"

#include <cassert>
#include <cmath>
#include <cstring>

#include "bouguer/core/error.h"
#include "bouguer/core/limits.h"

namespace bouguer {

FilmBuffer::FilmBuffer(int width_px, int height_px, std::vector<double> spectrum_wavelengths_nm)
    : width_(width_px), height_(height_px), wavelengths_nm_(std::move(spectrum_wavelengths_nm)) {
  const auto pixels = static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px);
  rgb_sum_.assign(3 * pixels, 0.0);
  weight_sum_.assign(pixels, 0.0);
  splat_rgb_.assign(3 * pixels, 0);
  spectral_sum_.assign(wavelengths_nm_.size() * pixels, 0.0);
  splat_spectral_.assign(wavelengths_nm_.size() * pixels, 0);
}

FilmBuffer::FilmBuffer(FilmBuffer&& other) noexcept
    : width_(other.width_),
      height_(other.height_),
      wavelengths_nm_(std::move(other.wavelengths_nm_)),
      rgb_sum_(std::move(other.rgb_sum_)),
      weight_sum_(std::move(other.weight_sum_)),
      spectral_sum_(std::move(other.spectral_sum_)),
      odd_rgb_sum_(std::move(other.odd_rgb_sum_)),
      odd_weight_sum_(std::move(other.odd_weight_sum_)),
      splat_rgb_(std::move(other.splat_rgb_)),
      splat_spectral_(std::move(other.splat_spectral_)),
      saturated_(other.saturated_.load()) {}

void FilmBuffer::keep_halves() {
  if (keeps_halves()) return;
  odd_rgb_sum_.assign(rgb_sum_.size(), 0.0);
  odd_weight_sum_.assign(weight_sum_.size(), 0.0);
}

std::array<Vec3, 2> FilmBuffer::half_means(int x, int y) const {
  const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
  std::array<Vec3, 2> out{};
  if (!keeps_halves()) return out;
  const double odd = odd_weight_sum_[p], even = weight_sum_[p] - odd;
  for (std::size_t c = 0; c < 3; ++c) {
    const double odd_sum = odd_rgb_sum_[3 * p + c];
    if (even > 0.0) out[0][c] = (rgb_sum_[3 * p + c] - odd_sum) / even;
    if (odd > 0.0) out[1][c] = odd_sum / odd;
  }
  return out;
}

std::uint64_t FilmBuffer::bytes_needed(int width_px, int height_px, std::size_t spectrum_wavelengths) {
  const auto pixels = static_cast<std::uint64_t>(width_px) * static_cast<std::uint64_t>(height_px);
  const std::uint64_t n = spectrum_wavelengths;
  const std::uint64_t buffer = 7 * sizeof(double) + n * (sizeof(double) + sizeof(std::int64_t));
  const std::uint64_t film = 3 * sizeof(float) + n * sizeof(float);
  const std::uint64_t writers = 3 * sizeof(float) + n * sizeof(float);  // one converted copy at a time
  return pixels * (buffer + film + writers);
}

void FilmBuffer::add_fixed(std::int64_t& cell, double value) {
  const double units = value / kSplatUnit;
  if (!(std::abs(units) < 9.0e15)) {  // NaN, or beyond what one cell can hold exactly
    saturated_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  std::atomic_ref<std::int64_t>(cell).fetch_add(std::llround(units), std::memory_order_relaxed);
}

void FilmBuffer::add_splat(double film_x, double film_y, const Vec3& rgb, std::span<const float> spectrum) {
  const int x = static_cast<int>(film_x), y = static_cast<int>(film_y);
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
  for (std::size_t c = 0; c < 3; ++c) add_fixed(splat_rgb_[3 * p + c], rgb[c]);
  const std::size_t n = wavelengths_nm_.size();
  for (std::size_t i = 0; i < n && i < spectrum.size(); ++i) add_fixed(splat_spectral_[n * p + i], spectrum[i]);
}

Film FilmBuffer::resolve(double splat_scale) const {
  Film film(width_, height_, wavelengths_nm_);
  const std::size_t n = wavelengths_nm_.size();
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const std::size_t p = film.pixel_index(x, y);
      const double w = weight_sum_[p];
      auto value = [&](double sum, std::int64_t splat) {
        return static_cast<float>((w > 0.0 ? sum / w : 0.0) + static_cast<double>(splat) * kSplatUnit * splat_scale);
      };
      film.set_rgb(x, y, {value(rgb_sum_[3 * p], splat_rgb_[3 * p]), value(rgb_sum_[3 * p + 1], splat_rgb_[3 * p + 1]),
                          value(rgb_sum_[3 * p + 2], splat_rgb_[3 * p + 2])});
      auto spectrum = film.spectrum_at(x, y);
      for (std::size_t i = 0; i < n; ++i) spectrum[i] = value(spectral_sum_[n * p + i], splat_spectral_[n * p + i]);
    }
  return film;
}

}  // namespace bouguer

namespace bouguer {
namespace {

// The serialised header: magic, version, byte-order mark, width, height, wavelengths, saturated
// splats; then the wavelengths and the arrays in the order of FilmBuffer's members.
constexpr char kMagic[8] = {'B', 'O', 'U', 'G', 'F', 'I', 'L', 'M'};
constexpr std::uint32_t kVersion = 1, kByteOrder = 0x01020304;
constexpr std::size_t kHeaderBytes = 40;

std::uint64_t payload_bytes(std::uint64_t pixels, std::uint64_t n) { return 8 * (n + pixels * (7 + 2 * n)); }

class Writer {
 public:
  explicit Writer(std::vector<std::byte>& out) : out_(out) {}
  template <typename T>
  void put(const T& value) { put_array(std::span<const T>(&value, 1)); }
  template <typename T>
  void put_array(std::span<const T> values) {
    const std::size_t at = out_.size();
    out_.resize(at + values.size_bytes());
    if (!values.empty()) std::memcpy(out_.data() + at, values.data(), values.size_bytes());
  }

 private:
  std::vector<std::byte>& out_;
};

class Reader {
 public:
  explicit Reader(std::span<const std::byte> in) : in_(in) {}
  template <typename T>
  T get() {
    T value;
    get_array(std::span<T>(&value, 1));
    return value;
  }
  template <typename T>
  void get_array(std::span<T> values) {  // the caller checked the size
    assert(at_ + values.size_bytes() <= in_.size());
    if (!values.empty()) std::memcpy(values.data(), in_.data() + at_, values.size_bytes());
    at_ += values.size_bytes();
  }

 private:
  std::span<const std::byte> in_;
  std::size_t at_ = 0;
};

}  // namespace

std::uint64_t FilmBuffer::serialised_bytes() const {
  const auto pixels = static_cast<std::uint64_t>(width_) * static_cast<std::uint64_t>(height_);
  return kHeaderBytes + payload_bytes(pixels, wavelengths_nm_.size());
}

std::vector<std::byte> FilmBuffer::serialise() const {
  std::vector<std::byte> out;
  out.reserve(serialised_bytes());
  Writer w(out);
  w.put_array(std::span<const char>(kMagic));
  w.put(kVersion);
  w.put(kByteOrder);
  w.put(width_);
  w.put(height_);
  w.put(static_cast<std::uint64_t>(wavelengths_nm_.size()));
  w.put(saturated_.load());
  for (const auto* v : {&wavelengths_nm_, &rgb_sum_, &weight_sum_, &spectral_sum_}) w.put_array(std::span<const double>(*v));
  for (const auto* v : {&splat_rgb_, &splat_spectral_}) w.put_array(std::span<const std::int64_t>(*v));
  assert(out.size() == serialised_bytes());
  return out;
}

FilmBuffer FilmBuffer::deserialise(std::span<const std::byte> bytes, std::string_view source) {
  if (bytes.size() < kHeaderBytes) fail("{}: a film of {} bytes is shorter than its header", source, bytes.size());
  Reader r(bytes);
  char magic[8];
  r.get_array(std::span<char>(magic));
  if (std::memcmp(magic, kMagic, sizeof magic) != 0) fail("{}: not a Bouguer film (its magic number differs)", source);
  if (const auto version = r.get<std::uint32_t>(); version != kVersion)
    fail("{}: film version {}, this build reads version {}", source, version, kVersion);
  if (r.get<std::uint32_t>() != kByteOrder) fail("{}: the film was written in another byte order", source);
  const int width = r.get<int>(), height = r.get<int>();
  const auto n = r.get<std::uint64_t>();
  const auto saturated = r.get<std::uint64_t>();
  if (width < 0 || height < 0 || width > kMaxImageDimension || height > kMaxImageDimension)
    fail("{}: a film of {}x{} pixels (each side at most {})", source, width, height, kMaxImageDimension);
  const auto pixels = static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
  if (pixels > kMaxImagePixels || n > kMaxSpectrumWavelengths || pixels * n > kMaxImageValues)
    fail("{}: a film of {}x{} pixels with {} wavelengths is beyond the limits (docs/limits.md)", source, width, height,
         n);
  if (bytes.size() - kHeaderBytes != payload_bytes(pixels, n))
    fail("{}: a {}x{} film with {} wavelengths takes {} bytes, the buffer has {}", source, width, height, n,
         kHeaderBytes + payload_bytes(pixels, n), bytes.size());
  std::vector<double> wavelengths(n);
  r.get_array(std::span<double>(wavelengths));
  for (const double nm : wavelengths)
    if (!(nm >= kMinWavelengthNm && nm <= kMaxWavelengthNm))
      fail("{}: a film wavelength of {} nm (expected {} to {})", source, nm, kMinWavelengthNm, kMaxWavelengthNm);
  FilmBuffer film(width, height, std::move(wavelengths));
  for (auto* v : {&film.rgb_sum_, &film.weight_sum_, &film.spectral_sum_}) r.get_array(std::span<double>(*v));
  for (auto* v : {&film.splat_rgb_, &film.splat_spectral_}) r.get_array(std::span<std::int64_t>(*v));
  film.saturated_ = saturated;
  return film;
}

void FilmBuffer::merge(const FilmBuffer& other) {
  if (other.width_ != width_ || other.height_ != height_ || other.wavelengths_nm_ != wavelengths_nm_)
    fail("films of {}x{} pixels with {} wavelengths and {}x{} with {} cannot be merged", width_, height_,
         wavelengths_nm_.size(), other.width_, other.height_, other.wavelengths_nm_.size());
  const std::size_t pixels = weight_sum_.size(), n = wavelengths_nm_.size();
  for (std::size_t p = 0; p < pixels; ++p)
    if (weight_sum_[p] != 0.0 && other.weight_sum_[p] != 0.0)
      fail("pixel ({}, {}) has camera samples in both films: their sum would depend on the order of the merge",
           p % static_cast<std::size_t>(width_), p / static_cast<std::size_t>(width_));
  for (std::size_t p = 0; p < pixels; ++p) {
    if (other.weight_sum_[p] == 0.0) continue;
    weight_sum_[p] = other.weight_sum_[p];
    for (std::size_t c = 0; c < 3; ++c) rgb_sum_[3 * p + c] = other.rgb_sum_[3 * p + c];
    for (std::size_t i = 0; i < n; ++i) spectral_sum_[n * p + i] = other.spectral_sum_[n * p + i];
  }
  // Two's complement wrapping, as the atomic adds of one process wrap: the same sum in any order.
  auto add = [](std::vector<std::int64_t>& to, const std::vector<std::int64_t>& from) {
    for (std::size_t i = 0; i < to.size(); ++i)
      to[i] = static_cast<std::int64_t>(static_cast<std::uint64_t>(to[i]) + static_cast<std::uint64_t>(from[i]));
  };
  add(splat_rgb_, other.splat_rgb_);
  add(splat_spectral_, other.splat_spectral_);
  saturated_ += other.saturated_.load();
}

}  // namespace bouguer
