#pragma once
// Image files. Every writer goes through write_atomically (io/atomic_file.h); every reader and
// writer reports problems as one-line Errors naming the file.
//   PNG  8-bit sRGB-encoded, clamped to [0, 1]
//   EXR  32-bit float linear Rec.709 with a chromaticities attribute (Rec.709 primaries, D65)
//   PFM  32-bit float linear Rec.709 (no colour metadata in the format)
//   spectral EXR: Fichet, Pacanowski, Wilkie, "An OpenEXR Layout for Spectral Images", JCGT 10(3),
//        2021: one channel per wavelength named S0.<nm with comma decimal>nm plus R, G, B preview.
#include <array>
#include <filesystem>
#include <string>
#include <string_view>

#include "bouguer/io/display.h"
#include "bouguer/io/image.h"

namespace bouguer {

void write_png(const std::filesystem::path& path, const Film& film);
void write_exr(const std::filesystem::path& path, const Film& film);
void write_pfm(const std::filesystem::path& path, const Film& film);
void write_spectral_exr(const std::filesystem::path& path, const Film& film);  // film must keep spectra

// The PNG file's bytes (8-bit sRGB), for embedding.
std::string encode_png(const Film& film);

// Chooses the writer by extension (.png, .exr, .pfm); an unknown extension is an Error.
inline constexpr std::array<std::string_view, 3> kImageExtensions = {".png", ".exr", ".pfm"};
void write_image(const std::filesystem::path& path, const Film& film);
// The same through a display transform (io/display.h): a PNG gets displayed(film, t), EXR and PFM
// exposed(film, t); the identity transform writes exactly what write_image(path, film) writes.
void write_image(const std::filesystem::path& path, const Film& film, const DisplayTransform& t);

// EXR reading keeps spectral channels (S0.*nm) when the file has them, and converts RGB in other
// primaries (the chromaticities attribute: ACEScg, Rec.2020, ...) to linear Rec.709. Both readers
// check sizes against docs/limits.md and the file's bytes before allocating, and accept finite
// pixel values only.
Film read_exr(const std::filesystem::path& path);
Film read_pfm(const std::filesystem::path& path);
Film read_image(const std::filesystem::path& path);  // by extension: .exr or .pfm

// The checks read_exr makes of an EXR file's header before OpenEXR sees it (every size OpenEXR
// would allocate from, against the limits and the bytes the file holds), for other readers of EXR
// files (io/texture_image.cpp, before the OpenImageIO module reads them with OpenEXR).
void check_exr_before_opening(std::string_view bytes, const std::string& name);

// Channel name of one wavelength in the spectral layout, e.g. 550 -> "S0.550,000000nm".
std::string spectral_channel_name(double wavelength_nm);

}  // namespace bouguer
