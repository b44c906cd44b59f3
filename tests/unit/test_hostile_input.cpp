// Files made to break the readers (found by hand and by fuzzing, tests/fuzz): each is refused with
// one line naming the file and what is wrong, within a small memory budget, and never read past
// its end. The limits are those of docs/limits.md (core/limits.h).
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "bouguer/core/error.h"
#include "bouguer/geometry/mesh.h"
#include "bouguer/geometry/shapes.h"
#include "bouguer/core/csv.h"
#include "bouguer/io/image_io.h"
#include "bouguer/core/limits.h"
#include "bouguer/spectra/spectrum_csv.h"
#include "bouguer/lights/environment.h"
#include "bouguer/scene/loader.h"
#include "bouguer/scene/material_file.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

constexpr std::size_t kBudget = std::size_t{64} << 20;  // far below what the counts in these files claim

std::string error_of(const std::function<void()>& read) {
  try {
    read();
  } catch (const Error& e) {
    return e.what();
  }
  return "accepted";
}

testing::AssertionResult has(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return testing::AssertionSuccess();
  return testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

std::string mesh_error(const fs::path& path) {
  return error_of([&] { make_shape(MeshShape{path}, "object 'probe'"); });
}

std::string ply_ascii(const std::string& vertices, int vertex_count, const std::string& faces, int face_count) {
  return "ply\nformat ascii 1.0\nelement vertex " + std::to_string(vertex_count) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(face_count) +
         "\nproperty list uchar int vertex_indices\nend_header\n" + vertices + faces;
}

template <typename T>
std::string bytes_of(T v) {
  std::string s(sizeof v, '\0');
  std::memcpy(s.data(), &v, sizeof v);
  return s;
}

TEST(HostileInput, PfmWhoseHeaderEndsAtTheEndOfTheFile) {
  const fs::path dir = test::scratch_dir("hostile_pfm");
  test::write_file(dir / "eof.pfm", "PF\n1 1\n-1.000");
  EXPECT_TRUE(has(error_of([&] { read_pfm(dir / "eof.pfm"); }), "eof.pfm: PFM file ends after its header"));
  test::write_file(dir / "short.pfm", "Pf\n2 2\n-1.0\n" + std::string(15, '\0'));
  EXPECT_TRUE(has(error_of([&] { read_pfm(dir / "short.pfm"); }), "truncated (15 bytes of pixels, 16 expected)"));
  test::write_file(dir / "wide.pfm", "PF\n70000 1\n-1.0\n");
  EXPECT_TRUE(has(error_of([&] { read_pfm(dir / "wide.pfm"); }), "PFM size 70000 × 1 is outside"));
  test::write_file(dir / "nan.pfm", "Pf\n1 1\n-1.0\n" + bytes_of(std::numeric_limits<float>::quiet_NaN()));
  EXPECT_TRUE(has(error_of([&] { read_pfm(dir / "nan.pfm"); }), "pixel (0, 0) holds nan, not a finite number"));
  // A header that claims 65536² pixels is refused before anything is allocated for them.
  test::write_file(dir / "huge.pfm", "PF\n65536 2048\n-1.0\n" + std::string(64, '\0'));
  EXPECT_TRUE(has(test::run_with_memory_budget([&] { read_pfm(dir / "huge.pfm"); }, kBudget), "error: "));
}

TEST(HostileInput, PlyIndicesAndCountsAreWholeNumbersInRange) {
  const fs::path dir = test::scratch_dir("hostile_ply_numbers");
  const std::string v = "0 0 0\n1 0 0\n0 1 0\n";
  test::write_file(dir / "index.ply", ply_ascii(v, 3, "3 0 1 10000000000\n", 1));
  EXPECT_TRUE(has(mesh_error(dir / "index.ply"),
                  "index.ply: face 0: vertex index 10000000000 is not a whole number from 0 to 4294967295"));
  test::write_file(dir / "half.ply", ply_ascii(v, 3, "3 0 1 1.5\n", 1));
  EXPECT_TRUE(has(mesh_error(dir / "half.ply"), "vertex index 1.5 is not a whole number"));
  test::write_file(dir / "count.ply", ply_ascii(v, 3, "1000000000000 0 1 2\n", 1));
  EXPECT_TRUE(has(mesh_error(dir / "count.ply"),
                  "object 'probe': " + (dir / "count.ply").string() + ": face 0: list count 1000000000000 is not"));
  test::write_file(dir / "missing.ply", ply_ascii(v, 3, "3 0 1 3\n", 1));
  EXPECT_TRUE(has(mesh_error(dir / "missing.ply"), "a face refers to vertex 3 of 3"));
  test::write_file(dir / "float_count.ply", "ply\nformat ascii 1.0\nelement face 1\n"
                                            "property list float int vertex_indices\nend_header\n3 0 1 2\n");
  EXPECT_TRUE(has(mesh_error(dir / "float_count.ply"), "a list count must have an integer type"));
}

TEST(HostileInput, PlyAndObjVerticesAreFiniteAndInRange) {
  const fs::path dir = test::scratch_dir("hostile_vertices");
  const std::string f = "3 0 1 2\n";
  test::write_file(dir / "nan.ply", ply_ascii("0 0 0\n1 nan 0\n0 1 0\n", 3, f, 1));
  EXPECT_TRUE(has(mesh_error(dir / "nan.ply"), "nan.ply: vertex 1: y is nan, not a finite number"));
  test::write_file(dir / "inf.ply", ply_ascii("0 0 0\n1 0 0\n0 1 -inf\n", 3, f, 1));
  EXPECT_TRUE(has(mesh_error(dir / "inf.ply"), "vertex 2: z is -inf, not a finite number"));
  test::write_file(dir / "far.ply", ply_ascii("0 0 0\n1e10 0 0\n0 1 0\n", 3, f, 1));
  EXPECT_TRUE(has(mesh_error(dir / "far.ply"), "vertex 1: x = 10000000000 is beyond ±1000000000"));
  const std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 1\n"
                             "property list uchar int vertex_indices\nend_header\n";
  std::string data;
  for (float c : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, std::numeric_limits<float>::quiet_NaN(), 0.f}) data += bytes_of(c);
  data += bytes_of(std::uint8_t{3}) + bytes_of(0) + bytes_of(1) + bytes_of(2);
  test::write_file(dir / "nan_binary.ply", binary + data);
  EXPECT_TRUE(has(mesh_error(dir / "nan_binary.ply"), "vertex 2: y is nan, not a finite number"));
  // tinyobjloader reads 0e999 as NaN and 1e999 as infinity.
  test::write_file(dir / "nan.obj", "v 0 0 0\nv 1 0 0\nv 0e999 1 0\nf 1 2 3\n");
  EXPECT_TRUE(has(mesh_error(dir / "nan.obj"), "nan.obj': vertex 3: x is "));
  EXPECT_TRUE(has(mesh_error(dir / "nan.obj"), "nan, not a finite number"));
  test::write_file(dir / "inf.obj", "v 0 0 0\nv 1 1e999 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_TRUE(has(mesh_error(dir / "inf.obj"), "inf.obj', line 2: '1e999' is not a finite number"));
  // ... and "nan", "inf" or any other word as 0: the raw text is checked first, by line.
  test::write_file(dir / "word.obj", "v 0 0 0\nv 1 0 0\n\n  v nan 1 0\nf 1 2 3\n");
  EXPECT_TRUE(has(mesh_error(dir / "word.obj"), "word.obj', line 4: 'nan' is not a finite number"));
  test::write_file(dir / "uv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 inf\nf 1/1 2/1 3/1\n");
  EXPECT_TRUE(has(mesh_error(dir / "uv.obj"), "uv.obj', line 4: 'inf' is not a finite number"));
}

// The welder hashes coordinates into grid cells: huge and NaN coordinates must not overflow.
TEST(HostileInput, WelderKeepsFarAndNanVerticesApart) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1e300, 0, 0}, {-1e300, 0, 0}, {std::nan(""), 0, 0}};
  m.triangles = {{0, 1, 2}, {0, 1, 3}};
  EXPECT_EQ(welded(m, 1e-12).positions.size(), 4u);
}

// The 220-byte PLY whose face claims 4·10⁹ indices: refused from its size before any allocation.
TEST(HostileInput, PlyCountsAreCheckedAgainstTheBytesThatFollow) {
  const fs::path dir = test::scratch_dir("hostile_ply_counts");
  std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
                    "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                    "property list uint uint vertex_indices\nend_header\n";
  for (int i = 0; i < 9; ++i) ply += bytes_of(0.5f * static_cast<float>(i % 4));
  ply += bytes_of(std::uint32_t{4000000000u});
  ply.resize(220, '\0');
  test::write_file(dir / "claims.ply", ply);
  const std::string outcome = test::run_with_memory_budget([&] { make_shape(MeshShape{dir / "claims.ply"}, "t"); },
                                                           kBudget);
  EXPECT_TRUE(has(outcome, "error: t: " + (dir / "claims.ply").string() + ": face 0: a list of 4000000000 entries"));
  // Element counts in the header: 3·10⁷ vertices cannot fit in the 9 bytes after it.
  test::write_file(dir / "vertices.ply", ply_ascii("0 0 0\n", 30000000, "3 0 0 0\n", 1));
  EXPECT_TRUE(has(test::run_with_memory_budget([&] { make_shape(MeshShape{dir / "vertices.ply"}, "t"); }, kBudget),
                  "declares elements of at least 180000001 bytes, but only 14 bytes follow it"));
  test::write_file(dir / "too_many.ply", ply_ascii("", 40000000, "", 0));
  EXPECT_TRUE(has(mesh_error(dir / "too_many.ply"), "more than 33554432 elements (docs/limits.md)"));
}

TEST(HostileInput, FoldersDevicesAndFifosAreRefusedAtOnce) {
  const fs::path dir = test::scratch_dir("hostile_kinds");
  fs::create_directories(dir / "x.obj");
  fs::create_directories(dir / "x.ply");
  EXPECT_TRUE(has(mesh_error(dir / "x.obj"), "x.obj: is a folder, not a file"));
  EXPECT_TRUE(has(mesh_error(dir / "x.ply"), "x.ply: is a folder, not a file"));
  EXPECT_TRUE(has(error_of([] { load_spectrum_csv("/dev/zero"); }),
                  "/dev/zero: is not a regular file (a device, FIFO or socket)"));
  EXPECT_TRUE(has(error_of([] { load_scene("/dev/zero"); }), "/dev/zero: is not a regular file"));
  ASSERT_EQ(::mkfifo((dir / "pipe.csv").c_str(), 0600), 0);  // nobody writes: reading it would wait forever
  EXPECT_TRUE(has(error_of([&] { read_csv_file(dir / "pipe.csv"); }), "pipe.csv: is not a regular file"));
  EXPECT_TRUE(has(error_of([&] { read_exr(dir / "pipe.csv"); }), "pipe.csv: is not a regular file"));
  // An OBJ's mtllib is a file name from the file: it gets the same checks.
  test::write_file(dir / "m.obj", "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_TRUE(has(mesh_error(dir / "m.obj"), "mtllib '/dev/zero': /dev/zero: is not a regular file"));
  test::write_file(dir / "big.csv", "wavelength_nm,v\n");
  EXPECT_TRUE(has(error_of([&] { read_text_file(dir / "big.csv", 10); }),
                  "big.csv: the file has 16 bytes, more than the 10 bytes this kind of file may have (docs/limits.md)"));
}

TEST(HostileInput, CommandLineRefusesDevicesWithAMessage) {
  const auto color = test::run_bouguer({"color", "/dev/zero"});
  EXPECT_EQ(color.exit_code, 1);
  EXPECT_TRUE(has(color.err, "bouguer: error: /dev/zero: is not a regular file"));
  const auto render = test::run_bouguer({"render", "/dev/zero", "-o", "never.png"});
  EXPECT_EQ(render.exit_code, 1);
  EXPECT_TRUE(has(render.err, "/dev/zero: is not a regular file"));
}

TEST(HostileInput, ByteOrderMarksAreSkipped) {
  const fs::path dir = test::scratch_dir("hostile_bom");
  const std::string bom = "\xEF\xBB\xBF";
  test::write_file(dir / "s.csv", bom + "wavelength_nm,transmittance\n400,0.5\n700,0.9\n");
  EXPECT_EQ(load_spectrum_csv(dir / "s.csv").value, (std::vector<double>{0.5, 0.9}));
  test::write_file(dir / "m.csv", bom + "# unit: attenuation_per_m\nwavelength_nm,value\n350,1\n850,2\n");
  EXPECT_EQ(load_material_csv(dir / "m.csv").unit, AbsorptionUnit::attenuation_per_m);
  const fs::path scene = fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "examples" / "issue3.json";
  test::write_file(dir / "scene.json", bom + test::read_file(scene));
  EXPECT_EQ(load_scene(dir / "scene.json").objects.size(), load_scene(scene).objects.size());
}

TEST(HostileInput, LongContentIsQuotedShortInMessages) {
  const fs::path dir = test::scratch_dir("hostile_long");
  test::write_file(dir / "line.csv", "wavelength_nm,v\n400," + std::string(30'000'000, 'x') + "\n");
  const std::string e = error_of([&] { load_spectrum_csv(dir / "line.csv"); });
  EXPECT_TRUE(has(e, "line.csv, line 2: column 'v': 'xxxxxxxxxx"));
  EXPECT_TRUE(has(e, "… (30000000 bytes)' is not a number"));
  EXPECT_LT(e.size(), 300u);
  test::write_file(dir / "m.csv", "# unit: " + std::string(100000, 'q') + "\nwavelength_nm,value\n400,1\n");
  EXPECT_LT(error_of([&] { load_material_csv(dir / "m.csv"); }).size(), 400u);
  test::write_file(dir / "t.csv", "# unit: internal_transmittance\n# thickness: " + std::string(100000, '5') +
                                      " mm\nwavelength_nm,value\n400,0.5\n");
  EXPECT_LT(error_of([&] { load_material_csv(dir / "t.csv"); }).size(), 400u);
}

TEST(HostileInput, TableValuesAreFiniteAndInRange) {
  const fs::path dir = test::scratch_dir("hostile_tables");
  test::write_file(dir / "big.csv", "wavelength_nm,v\n400,1\n500,1e300\n");
  EXPECT_TRUE(has(error_of([&] { load_spectrum_csv(dir / "big.csv"); }),
                  "big.csv, line 3: v is 1e+300, beyond the ±1000000000000 a table value may have"));
  test::write_file(dir / "far.csv", "wavelength_nm,v\n400,1\n1e6,1\n");
  EXPECT_TRUE(has(error_of([&] { load_spectrum_csv(dir / "far.csv"); }),
                  "far.csv, line 3: wavelength_nm must be a positive number of nanometres from 1 to 100000 (found 1000000)"));
  // A product that overflows where it is formed: T = 10⁻³⁰⁰ over 10⁻³⁰⁷ m is σ_a = ∞.
  test::write_file(dir / "thin.csv",
                   "# unit: internal_transmittance\n# thickness: 1e-307 m\nwavelength_nm,value\n350,1e-300\n850,1\n");
  EXPECT_TRUE(has(error_of([&] { resolve_material((dir / "thin.csv").string(), std::nullopt); }),
                  "the value at 350 nm gives σ_a = inf per metre, not a finite number"));
}

TEST(HostileInput, EnvironmentTexelsAreBoundedWithTheirScale) {
  const fs::path dir = test::scratch_dir("hostile_environment");
  Film film(2, 2);
  for (float& v : film.rgb) v = 0.5f;
  film.set_rgb(1, 0, {3e38f, 0.5f, 0.5f});
  write_pfm(dir / "bright.pfm", film);
  EXPECT_TRUE(has(error_of([&] { load_environment({dir / "bright.pfm", 1.0, 0.0}); }),
                  "bright.pfm: pixel (1, 0) channel R: 3.0000000054977558e+38 × scale 1 is beyond the ±1000000000000"));
  film.set_rgb(1, 0, {1.0f, 0.5f, 0.5f});
  write_pfm(dir / "plain.pfm", film);
  EXPECT_NO_THROW(load_environment({dir / "plain.pfm", 1e6, 0.0}));
  EXPECT_TRUE(has(error_of([&] { load_environment({dir / "plain.pfm", 1e30, 0.0}); }), "× scale 1e+30 is beyond"));
}

// An uncompressed EXR whose data window is patched to 40000² pixels after it was written.
TEST(HostileInput, ExrHeadersAreCheckedAgainstTheFileSize) {
  const fs::path dir = test::scratch_dir("hostile_exr");
  {
    Imf::Header header(4, 4);
    header.compression() = Imf::NO_COMPRESSION;
    for (const char* c : {"R", "G", "B"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    std::vector<float> pixels(3 * 16, 0.25f);
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; ++c)
      fb.insert(std::string(1, "RGB"[c]), Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(pixels.data() + c), 12, 48));
    Imf::OutputFile out((dir / "small.exr").c_str(), header);
    out.setFrameBuffer(fb);
    out.writePixels(4);
  }
  EXPECT_EQ(read_exr(dir / "small.exr").width, 4);
  std::string bytes = test::read_file(dir / "small.exr");
  const std::string tag = std::string("dataWindow") + '\0' + "box2i" + '\0';
  const auto at = bytes.find(tag);
  ASSERT_NE(at, std::string::npos);
  const std::size_t box = at + tag.size() + 4;  // after the attribute size: xMin, yMin, xMax, yMax
  std::memcpy(bytes.data() + box + 8, bytes_of(std::int32_t{39999}).data(), 4);
  std::memcpy(bytes.data() + box + 12, bytes_of(std::int32_t{39999}).data(), 4);
  test::write_file(dir / "claims.exr", bytes);
  const std::string outcome = test::run_with_memory_budget([&] { read_exr(dir / "claims.exr"); }, kBudget);
  EXPECT_TRUE(has(outcome, "error: " + (dir / "claims.exr").string())) << outcome;

  // OpenEXR allocates an attribute's stated size before reading it (found by fuzzing).
  test::write_file(dir / "attribute.exr", std::string("\x76\x2f\x31\x01\x02\0\0\0comment\0opaque\0", 23) +
                                              bytes_of(std::int32_t{1634231040}) + "xyz");
  EXPECT_TRUE(has(test::run_with_memory_budget([&] { read_exr(dir / "attribute.exr"); }, kBudget),
                  "attribute.exr: EXR attribute 'comment' claims 1634231040 bytes, but only 3 follow"));

  // A value shorter than its stated size: OpenEXR reads a channel list up to its end and takes
  // the bytes after it for the next attribute, here one of 1.9·10⁹ bytes.
  const std::string chlist = std::string("R\0", 2) + bytes_of(std::int32_t{2}) + std::string(4, '\0') +
                             bytes_of(std::int32_t{1}) + bytes_of(std::int32_t{1}) + std::string(1, '\0');
  const std::string inner = chlist + std::string("n\0t\0", 4) + bytes_of(std::int32_t{1886220131});
  test::write_file(dir / "chlist.exr", std::string("\x76\x2f\x31\x01\x02\0\0\0channels\0chlist\0", 24) +
                                           bytes_of(static_cast<std::int32_t>(inner.size())) + inner + '\0');
  EXPECT_TRUE(has(test::run_with_memory_budget([&] { read_exr(dir / "chlist.exr"); }, kBudget),
                  "chlist.exr: EXR attribute 'channels' of type 'chlist' does not fill its 27 bytes"));

  Film nan(2, 1);
  nan.set_rgb(1, 0, {0.0f, std::numeric_limits<float>::infinity(), 0.0f});
  write_exr(dir / "inf.exr", nan);
  EXPECT_TRUE(has(error_of([&] { read_exr(dir / "inf.exr"); }), "pixel (1, 0) channel G is inf, not a finite number"));
}

}  // namespace
}  // namespace bouguer
