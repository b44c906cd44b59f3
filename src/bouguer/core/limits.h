#pragma once
// The most the readers accept (docs/limits.md explains each). Every count a file states is checked
// against these and against the bytes that can follow it before anything is allocated for it.
#include <cstddef>
#include <cstdint>

namespace bouguer {

// File sizes. Anything but a regular file (a folder, FIFO, device, socket) is refused at once.
inline constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t{64} << 20;  // scenes, CSV, MTL
inline constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t{2} << 30;   // OBJ, PLY
inline constexpr std::uintmax_t kMaxImageFileBytes = std::uintmax_t{2} << 30;  // EXR, PFM
inline constexpr std::uintmax_t kMaxVdbFileBytes = std::uintmax_t{2} << 30;    // OpenVDB grids

// Meshes (one file): vertices, triangles after fan triangulation, |x|, |y|, |z| in the file's units.
inline constexpr std::size_t kMaxMeshVertices = std::size_t{1} << 25;   // 33 554 432
inline constexpr std::size_t kMaxMeshTriangles = std::size_t{1} << 25;  // 33 554 432
inline constexpr double kMaxMeshCoordinate = 1e9;

// Scenes: lengths anywhere (positions, sizes, radii; and every vertex after its transform), the
// smallest positive size, all triangles together, emitted radiance or intensity (luminance units),
// absorption and scattering coefficients.
inline constexpr double kMaxSceneCoordinateM = 1e7;
inline constexpr double kMinSceneLengthM = 1e-9;
inline constexpr std::uint64_t kMaxSceneTriangles = std::uint64_t{1} << 28;  // 268 435 456
inline constexpr double kMaxEmission = 1e12;
inline constexpr double kMaxCoefficientPerM = 1e12;
inline constexpr std::size_t kMaxLayers = 256;  // in a layers concentration field
// A grid concentration field: nodes of its dense copy (the active voxels' bounding box plus a
// border of one), in all and along each axis; 1 GiB as floats.
inline constexpr std::uint64_t kMaxGridNodes = std::uint64_t{1} << 28;  // 268 435 456, e.g. 645³
inline constexpr std::int64_t kMaxGridNodesPerAxis = std::int64_t{1} << 20;

// Images (EXR, PFM, environment maps): each side, all pixels, all values in all channels read.
inline constexpr int kMaxImageDimension = 65536;
inline constexpr std::size_t kMaxImagePixels = std::size_t{1} << 27;  // 134 217 728, e.g. 16384 × 8192
inline constexpr std::size_t kMaxImageValues = std::size_t{1} << 30;  // 4 GiB as floats
// Texture images (io/texture_image.h): each side, and all pixels (8192 × 4096; read, kept by the
// description, and made a MIP pyramid with per-texel spectra, about 60 bytes a pixel at the peak).
inline constexpr int kMaxTextureDimension = 32768;
inline constexpr std::size_t kMaxTexturePixels = std::size_t{1} << 25;  // 33 554 432
// A compressed EXR may decode to at most this many bytes of pixels per byte of file (zlib's
// limit is 1032:1; an uncompressed file must hold every byte of its pixels).
inline constexpr double kMaxExrExpansion = 4096.0;

// Numbers in tables (spectrum and material CSVs, spectral EXR channels) and environment maps.
inline constexpr double kMinWavelengthNm = 1.0;
inline constexpr double kMaxWavelengthNm = 1e5;
inline constexpr double kMaxTableValue = 1e12;        // |value| of any tabulated quantity
inline constexpr double kMaxEnvironmentRadiance = 1e12;  // |texel × scale| of an environment map

}  // namespace bouguer
