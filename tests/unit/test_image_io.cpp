#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <gtest/gtest.h>
#include <png.h>

#include <array>
#include <cstring>
#include <optional>

#include "bouguer/core/error.h"
#include "bouguer/io/atomic_file.h"
#include "bouguer/io/image_io.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

// A small film whose every value is distinct, so a transposed or flipped read shows.
Film gradient_film(int w, int h, std::vector<double> wavelengths = {}) {
  Film film(w, h, std::move(wavelengths));
  for (std::size_t i = 0; i < film.rgb.size(); ++i) film.rgb[i] = 0.001f * static_cast<float>(i) + 0.25f;
  for (std::size_t i = 0; i < film.spectral.size(); ++i) film.spectral[i] = 1.0f / (1.0f + static_cast<float>(i));
  return film;
}

TEST(ImageIo, SpectralChannelNamesFollowTheJcgtLayout) {
  EXPECT_EQ(spectral_channel_name(550.0), "S0.550,000000nm");
  EXPECT_EQ(spectral_channel_name(412.5), "S0.412,500000nm");
}

TEST(ImageIo, SpectralExrRoundTripIsIdentical) {
  const fs::path dir = test::scratch_dir("spectral_exr");
  const Film film = gradient_film(7, 5, {365.0, 412.5, 550.0, 700.25, 825.0});
  write_spectral_exr(dir / "s.exr", film);
  const Film back = read_exr(dir / "s.exr");
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.wavelengths_nm, film.wavelengths_nm);
  EXPECT_EQ(back.spectral, film.spectral);
  EXPECT_EQ(back.rgb, film.rgb);

  Imf::InputFile file((dir / "s.exr").c_str());
  EXPECT_NE(file.header().findTypedAttribute<Imf::StringAttribute>("spectralLayoutVersion"), nullptr);
  EXPECT_NE(file.header().channels().findChannel("S0.412,500000nm"), nullptr);
}

TEST(ImageIo, RgbExrRoundTripAndChromaticities) {
  const fs::path dir = test::scratch_dir("rgb_exr");
  const Film film = gradient_film(6, 4);
  write_exr(dir / "a.exr", film);
  const Film back = read_exr(dir / "a.exr");
  EXPECT_EQ(back.rgb, film.rgb);
  EXPECT_FALSE(back.has_spectra());
  Imf::InputFile file((dir / "a.exr").c_str());
  ASSERT_TRUE(Imf::hasChromaticities(file.header()));
  const Imf::Chromaticities c = Imf::chromaticities(file.header());
  EXPECT_FLOAT_EQ(c.red.x, 0.64f);
  EXPECT_FLOAT_EQ(c.white.x, 0.3127f);
}

// One-pixel RGB EXR written with OpenEXR directly, with the given chromaticities (none: no attribute).
void write_one_pixel_exr(const fs::path& path, const std::array<float, 3>& rgb,
                         const std::optional<Imf::Chromaticities>& chromaticities) {
  Imf::Header header(1, 1);
  if (chromaticities) Imf::addChromaticities(header, *chromaticities);
  Imf::FrameBuffer fb;
  std::array<float, 3> px = rgb;
  for (int c = 0; c < 3; ++c) {
    header.channels().insert(std::string(1, "RGB"[c]), Imf::Channel(Imf::FLOAT));
    fb.insert(std::string(1, "RGB"[c]),
              Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(&px[c]), sizeof(px), sizeof(px)));
  }
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(fb);
  file.writePixels(1);
}

// An EXR in other primaries is read into linear Rec.709. Reference: the Rec.709 -> ACEScg matrix with
// Bradford adaptation D65 -> ACES white, as published with OpenColorIO's ACES config (6 digits).
TEST(ImageIo, ExrInOtherPrimariesIsConvertedToRec709) {
  const fs::path dir = test::scratch_dir("exr_chromaticities");
  const double m[3][3] = {
      {0.613097, 0.339523, 0.047379}, {0.070194, 0.916354, 0.013452}, {0.020616, 0.109570, 0.869815}};
  const double c709[3] = {0.8, 0.3, 0.1};
  std::array<float, 3> acescg{};
  for (int r = 0; r < 3; ++r) acescg[r] = static_cast<float>(m[r][0] * c709[0] + m[r][1] * c709[1] + m[r][2] * c709[2]);
  const Imf::Chromaticities ap1({0.713f, 0.293f}, {0.165f, 0.830f}, {0.128f, 0.044f}, {0.32168f, 0.33767f});
  write_one_pixel_exr(dir / "acescg.exr", acescg, ap1);
  const Film back = read_exr(dir / "acescg.exr");
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(back.rgb[c], c709[c], 2e-5) << c;

  // Without the attribute, or with Rec.709's, the values are taken as they are.
  write_one_pixel_exr(dir / "plain.exr", acescg, std::nullopt);
  write_one_pixel_exr(dir / "rec709.exr", acescg, Imf::Chromaticities());
  for (const char* name : {"plain.exr", "rec709.exr"}) {
    const Film same = read_exr(dir / name);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(same.rgb[c], acescg[c]) << name;
  }
}

TEST(ImageIo, PfmRoundTripAndBottomUpRows) {
  const fs::path dir = test::scratch_dir("pfm");
  const Film film = gradient_film(3, 2);
  write_pfm(dir / "a.pfm", film);
  EXPECT_EQ(read_pfm(dir / "a.pfm").rgb, film.rgb);
  // The first pixel stored in a PFM is the bottom-left one.
  const std::string bytes = test::read_file(dir / "a.pfm");
  const std::size_t header = std::string("PF\n3 2\n-1.0\n").size();
  float first = 0.0f;
  std::memcpy(&first, bytes.data() + header, sizeof first);
  EXPECT_EQ(first, film.rgb_at(0, 1).x);
}

TEST(ImageIo, PngEncodesHalfGreyAs188) {
  const fs::path dir = test::scratch_dir("png");
  Film film(2, 1);
  film.set_rgb(0, 0, {0.5f, 0.5f, 0.5f});
  film.set_rgb(1, 0, {2.0f, -1.0f, 1.0f});
  write_png(dir / "g.png", film);
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  ASSERT_TRUE(png_image_begin_read_from_file(&image, (dir / "g.png").c_str()));
  image.format = PNG_FORMAT_RGB;
  std::vector<unsigned char> px(PNG_IMAGE_SIZE(image));
  ASSERT_TRUE(png_image_finish_read(&image, nullptr, px.data(), 0, nullptr));
  EXPECT_EQ(px, (std::vector<unsigned char>{188, 188, 188, 255, 0, 255}));
}

TEST(ImageIo, WriteImageChoosesByExtensionAndRejectsUnknown) {
  const fs::path dir = test::scratch_dir("dispatch");
  const Film film = gradient_film(2, 2);
  write_image(dir / "a.PFM", film);
  EXPECT_EQ(read_image(dir / "a.PFM").rgb, film.rgb);
  EXPECT_THROW(write_image(dir / "a.tiff", film), Error);
  EXPECT_THROW(read_image(dir / "a.png"), Error);
}

TEST(ImageIo, FailedWriteLeavesTheEarlierFileIntactAndNoTemporaries) {
  const fs::path dir = test::scratch_dir("atomic");
  test::write_file(dir / "out.exr", "earlier image");
  EXPECT_THROW(write_atomically(dir / "out.exr",
                                [](const fs::path& temp) {
                                  test::write_file(temp, "half of a new ima");
                                  throw Error("simulated failure half-way");
                                }),
               Error);
  EXPECT_EQ(test::read_file(dir / "out.exr"), "earlier image");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(ImageIo, MissingFolderAndBadFilesAreErrorsNotCrashes) {
  const fs::path dir = test::scratch_dir("bad_files");
  EXPECT_THROW(write_png(dir / "missing" / "a.png", gradient_film(1, 1)), Error);
  EXPECT_THROW(write_spectral_exr(dir / "no_spectra.exr", gradient_film(1, 1)), Error);
  test::write_file(dir / "text.exr", "this is not an EXR file");
  EXPECT_THROW(read_exr(dir / "text.exr"), Error);
  test::write_file(dir / "short.pfm", "PF\n4 4\n-1.0\nabc");
  EXPECT_THROW(read_pfm(dir / "short.pfm"), Error);
  test::write_file(dir / "header.pfm", "P6\n4 4\n255\n");
  EXPECT_THROW(read_pfm(dir / "header.pfm"), Error);
  EXPECT_THROW(read_exr(dir / "absent.exr"), Error);
}

}  // namespace
}  // namespace bouguer
