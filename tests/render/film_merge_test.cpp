// EXR films with AOV channels: written and read back exactly (through OpenImageIO, by
// channel name), and merged from region parts only when every part has the same channels.
#include "render/film_merge.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <OpenImageIO/imageio.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <filesystem>
#include <limits>

#include "core/error.h"
#include "../scratch_dir.h"

namespace zz {
namespace {

namespace fs = std::filesystem;

struct FilmMergeTest : test::ScratchDirTest {
  // An EXR that zigzag did not write: `spec`'s size, channels and attributes, every value 0.5.
  fs::path foreign_exr(const std::string& name, const OIIO::ImageSpec& spec) const {
    std::vector<float> pixels(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels), 0.5f);
    const fs::path p = dir / name;
    auto out = OIIO::ImageOutput::create(p.string());
    EXPECT_TRUE(out && out->open(p.string(), spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    out->close();
    return p;
  }
};

// A film of `window` in a 7 x 5 frame whose values are a function of the frame position,
// so the parts of one frame agree with the whole.
Film frame_film(const TileRect& window, bool with_depth = true) {
  Film f(7, 5, window);
  f.channels.push_back({"rays", std::vector<float>(f.radiance.size())});
  if (with_depth) f.channels.push_back({"depth", std::vector<float>(f.radiance.size())});
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const int fx = f.x0 + x, fy = f.y0 + y;
      const size_t i = size_t(y) * f.width + x;
      f.radiance[i] = glm::vec3(0.1f * fx, 0.01f * fy, 1.0f / 3.0f);
      f.channels[0].values[i] = float(1 + fx + fy);
      if (with_depth) f.channels[1].values[i] = fx == 3 ? std::numeric_limits<float>::infinity() : 0.7f * fx + fy;
    }
  return f;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST_F(FilmMergeTest, ChannelsRoundTripByNameAndValue) {
  const Film film = frame_film({0, 0, 7, 5});
  write_film(dir / "f.exr", film, ToneMap{});
  auto in = OIIO::ImageInput::open((dir / "f.exr").string());
  ASSERT_TRUE(in);
  std::vector<std::string> names = in->spec().channelnames;
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"B", "G", "R", "depth", "rays"}));
  in->close();
  const FilmFile back = read_film(dir / "f.exr");
  ASSERT_EQ(back.film.channels.size(), 2u);
  for (const FilmChannel& c : back.film.channels) {
    const FilmChannel& orig = c.name == "rays" ? film.channels[0] : film.channels[1];
    EXPECT_TRUE(same_bits(c.values, orig.values)) << c.name;
  }
  EXPECT_EQ(std::memcmp(back.film.radiance.data(), film.radiance.data(), film.radiance.size() * sizeof(glm::vec3)), 0);
}

// Display images are sRGB-encoded and say so (PNG: sRGB/gAMA/cHRM chunks), so a
// colour-managed viewer shows them as written.
TEST_F(FilmMergeTest, DisplayImagesAreTaggedSrgb) {
  Film film(7, 5);
  write_film(dir / "f.png", film, ToneMap{});
  auto in = OIIO::ImageInput::open((dir / "f.png").string());
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("oiio:ColorSpace"), "sRGB");
  in->close();
  std::ifstream file(dir / "f.png", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  EXPECT_NE(bytes.find("sRGB"), std::string::npos);
  EXPECT_NE(bytes.find("gAMA"), std::string::npos);
}

TEST_F(FilmMergeTest, PartsMergeIntoTheWholeChannelsIncluded) {
  const Film whole = frame_film({0, 0, 7, 5});
  std::vector<FilmPart> parts;
  for (const TileRect& r : {TileRect{0, 0, 4, 2}, TileRect{4, 0, 7, 2}, TileRect{0, 2, 7, 5}}) {
    const fs::path p = dir / ("part" + std::to_string(parts.size()) + ".exr");
    write_film(p, frame_film(r), ToneMap{});
    parts.push_back({p.string(), read_film(p)});
  }
  const FilmFile merged = merge_films(parts);
  ASSERT_EQ(merged.film.channels.size(), 2u);
  const FilmFile full = [&] {
    write_film(dir / "whole.exr", whole, ToneMap{});
    return read_film(dir / "whole.exr");
  }();
  // The radiance too, pixel for pixel where it belongs (review: only the channels were
  // compared, so a radiance pasted at its source index passed).
  ASSERT_EQ(merged.film.radiance.size(), full.film.radiance.size());
  EXPECT_EQ(std::memcmp(merged.film.radiance.data(), full.film.radiance.data(), full.film.radiance.size() * sizeof(glm::vec3)), 0);
  for (size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(merged.film.channels[c].name, full.film.channels[c].name);
    EXPECT_TRUE(same_bits(merged.film.channels[c].values, full.film.channels[c].values)) << c;
  }
}

// `zigzag merge` checks the parts from their headers before it reads a pixel, then pastes
// them one at a time: the same checks, the same frame.
TEST_F(FilmMergeTest, PartsAreCheckedFromTheirHeadersAndPastedOneByOne) {
  std::vector<FilmPart> headers, whole;
  for (const TileRect& r : {TileRect{0, 0, 7, 3}, TileRect{0, 3, 7, 5}}) {
    const fs::path p = dir / ("h" + std::to_string(headers.size()) + ".exr");
    write_film(p, frame_film(r), ToneMap{}, {{"camera", "0"}});
    headers.push_back({p.string(), read_film_header(p)});
    whole.push_back({p.string(), read_film(p)});
    EXPECT_TRUE(headers.back().file.film.radiance.empty());
    EXPECT_EQ(headers.back().file.film.window(), r);
    EXPECT_TRUE(same_film_header(headers.back().file, whole.back().file));
  }
  ASSERT_EQ(headers[0].file.film.channels.size(), 2u);
  EXPECT_EQ(headers[0].file.film.channels[0].name, "depth");
  EXPECT_TRUE(headers[0].file.film.channels[0].values.empty());
  check_film_parts(headers);
  FilmFile frame = empty_frame(headers[0].file);
  for (const FilmPart& p : whole) paste_part(frame, p.file.film);
  // Against the whole frame written in one piece, not merge_films (which is these calls).
  write_film(dir / "whole.exr", frame_film({0, 0, 7, 5}), ToneMap{}, {{"camera", "0"}});
  const FilmFile full = read_film(dir / "whole.exr");
  ASSERT_EQ(frame.film.radiance.size(), full.film.radiance.size());
  EXPECT_EQ(std::memcmp(frame.film.radiance.data(), full.film.radiance.data(), full.film.radiance.size() * sizeof(glm::vec3)), 0);
  for (size_t c = 0; c < 2; ++c) EXPECT_TRUE(same_bits(frame.film.channels[c].values, full.film.channels[c].values));
  // A part of another camera: its attribute is a plain value, named with both values.
  write_film(dir / "h1.exr", frame_film({0, 3, 7, 5}), ToneMap{}, {{"camera", "1"}});
  headers[1] = {"h1.exr", read_film_header(dir / "h1.exr")};
  EXPECT_FALSE(same_film_header(headers[1].file, whole[1].file));
  try {
    check_film_parts(headers);
    FAIL() << "merged parts of two cameras";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("zigzag:camera differs: 1 in h1.exr, 0 in "), std::string::npos) << e.what();
  }
}

// Parts whose maps came from different Vulkan devices (a farm of GPU and lavapipe workers)
// merge: the device is named, not compared; any other attribute still must agree.
TEST_F(FilmMergeTest, PartsOfDifferentDevicesMergeAndAreNamed) {
  write_film(dir / "gpu.exr", frame_film({0, 0, 7, 2}), ToneMap{}, {{"camera", "0"}, {kDeviceAttribute, "a GPU"}});
  write_film(dir / "cpu.exr", frame_film({0, 2, 7, 5}), ToneMap{}, {{"camera", "0"}, {kDeviceAttribute, "llvmpipe"}});
  write_film(dir / "nomap.exr", frame_film({0, 2, 7, 5}), ToneMap{}, {{"camera", "0"}});
  std::vector<FilmPart> parts = {{"gpu.exr", read_film(dir / "gpu.exr")}, {"cpu.exr", read_film(dir / "cpu.exr")}};
  EXPECT_NO_THROW(check_film_parts(parts));
  EXPECT_EQ(devices_of(parts), (std::vector<std::string>{"a GPU", "llvmpipe"}));
  parts[1] = {"nomap.exr", read_film(dir / "nomap.exr")};
  EXPECT_NO_THROW(check_film_parts(parts));
  EXPECT_EQ(devices_of(parts), (std::vector<std::string>{"a GPU", "none"}));
  write_film(dir / "other.exr", frame_film({0, 2, 7, 5}), ToneMap{}, {{"camera", "1"}, {kDeviceAttribute, "a GPU"}});
  parts[1] = {"other.exr", read_film(dir / "other.exr")};
  EXPECT_THROW(check_film_parts(parts), Error);
}

// Parts of two scenes differ in the scene and its files' fingerprint: the scene is named,
// not "different versions of the scene's files", which the fingerprint alone means
// (exploratory testing: room and glass parts were said to be two versions of one scene).
TEST_F(FilmMergeTest, PartsOfTwoScenesAreSaidToBeOfTwoScenes) {
  write_film(dir / "room.exr", frame_film({0, 0, 7, 2}), ToneMap{},
             {{"camera", "0"}, {"scene", "room"}, {kSceneFilesAttribute, "70f2adb290acbb32"}});
  write_film(dir / "glass.exr", frame_film({0, 2, 7, 5}), ToneMap{},
             {{"camera", "0"}, {"scene", "glass"}, {kSceneFilesAttribute, "0123456789abcdef"}});
  write_film(dir / "edited.exr", frame_film({0, 2, 7, 5}), ToneMap{},
             {{"camera", "0"}, {"scene", "room"}, {kSceneFilesAttribute, "0123456789abcdef"}});
  const auto message = [&](const char* second) {
    try {
      check_film_parts({{"room.exr", read_film(dir / "room.exr")}, {second, read_film(dir / second)}});
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("merged");
  };
  EXPECT_EQ(message("glass.exr"),
            "merge: glass.exr and room.exr come from different renders (zigzag:scene differs: 'glass' in glass.exr, "
            "'room' in room.exr)");
  EXPECT_NE(message("edited.exr").find("were rendered from different versions of the scene's files"), std::string::npos)
      << message("edited.exr");
}

// Display bytes are round(T(v) * 255) for every channel, whatever the film's pixel count
// mod 4: the SSE body takes 4 pixels at a time and the tail its last 0..3 (mutation testing:
// the tail's + 0.5 dropped failed only a viewer test whose film happened to have one).
TEST_F(FilmMergeTest, DisplayBytesRoundEveryChannelWhateverTheTail) {
  const ToneMap tonemap{};
  for (const int pixels : {1, 2, 3, 4, 5, 6, 7}) {
    Film film(pixels, 1);
    for (int p = 0; p < pixels; ++p)
      film.radiance[size_t(p)] = glm::vec3(0.013f * float(p + 1), 0.31f + 0.07f * float(p), 0.9f / float(p + 1));
    const std::vector<uint8_t> bytes = display_bytes(film, tonemap);
    ASSERT_EQ(bytes.size(), size_t(3 * pixels));
    for (int p = 0; p < pixels; ++p)
      for (int c = 0; c < 3; ++c) {
        const float t = tonemap.apply(film.radiance[size_t(p)][c]) * 255.0f;
        EXPECT_EQ(int(bytes[size_t(3 * p + c)]), int(std::clamp(t + 0.5f, 0.0f, 255.0f)))
            << pixels << " pixels, pixel " << p << " channel " << c << " (" << t << ")";
      }
  }
}

TEST_F(FilmMergeTest, PartsWithDifferentChannelsAreRefused) {
  write_film(dir / "a.exr", frame_film({0, 0, 7, 2}), ToneMap{});
  write_film(dir / "b.exr", frame_film({0, 2, 7, 5}, false), ToneMap{});
  std::vector<FilmPart> parts = {{"a.exr", read_film(dir / "a.exr")}, {"b.exr", read_film(dir / "b.exr")}};
  try {
    merge_films(parts);
    FAIL() << "merged parts with different channels";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("b.exr has the AOV channels rays but a.exr depth, rays"), std::string::npos)
        << e.what();
  }
}

// Parts must have the very same channels: a part whose channels are only the first part's
// first few (rays of rays, depth) is refused too, not only one whose names differ.
TEST(FilmMerge, APartWithFewerOfTheSameChannelsIsRefused) {
  FilmFile a, b;
  a.film = frame_film({0, 0, 7, 2});
  b.film = frame_film({0, 2, 7, 5});
  b.film.channels.pop_back();  // rays only
  EXPECT_THROW(check_film_parts({{"a.exr", a}, {"b.exr", b}}), Error);
}

// Parts that overlap are refused, also where the later one starts below the earlier one's
// top (rows 0-2 and 2-3 overlap on row 2; their areas still add up to the frame's).
TEST(FilmMerge, PartsOverlappingAcrossTheirTopEdgesAreRefused) {
  FilmFile a, b;
  a.film = frame_film({0, 0, 7, 3});
  b.film = frame_film({0, 2, 7, 4});
  try {
    check_film_parts({{"a.exr", a}, {"b.exr", b}});
    FAIL() << "merged overlapping parts";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("overlap"), std::string::npos) << e.what();
  }
}

// The overlap scan visits the parts by their top edge: a part starting lower but further
// left (q, rows 3-4) does not hide the overlap of the first (p, rows 0-1) with one that
// starts on p's second row (r).
TEST(FilmMerge, AnOverlapBehindALowerPartFurtherLeftIsFound) {
  FilmFile p, q, r;
  p.film = frame_film({0, 0, 3, 2});
  q.film = frame_film({1, 3, 7, 5});
  r.film = frame_film({2, 1, 7, 3});  // column 2 of row 1 is p's too
  try {
    check_film_parts({{"p.exr", p}, {"q.exr", q}, {"r.exr", r}});
    FAIL() << "merged overlapping parts";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("p.exr (0,0,3,2) and r.exr (2,1,7,3) overlap"), std::string::npos) << e.what();
  }
}

// Parts of frames of another height are refused, even where their regions would tile
// the first part's frame.
TEST(FilmMerge, PartsOfFramesOfAnotherHeightAreRefused) {
  FilmFile a, b;
  a.film = frame_film({0, 0, 7, 2});
  b.film = Film(7, 6, TileRect{0, 2, 7, 5});
  for (const FilmChannel& c : a.film.channels) b.film.channels.push_back({c.name, std::vector<float>(b.film.radiance.size())});
  try {
    check_film_parts({{"a.exr", a}, {"b.exr", b}});
    FAIL() << "merged parts of a 7x5 and a 7x6 frame";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("b.exr is part of a 7x6 frame but a.exr of a 7x5 frame"), std::string::npos)
        << e.what();
  }
}

// Parts that leave a region of the frame uncovered are refused.
TEST(FilmMerge, PartsThatLeaveARegionUncoveredAreRefused) {
  FilmFile a;
  a.film = frame_film({0, 0, 7, 2});
  try {
    check_film_parts({{"a.exr", a}});
    FAIL() << "merged a part that covers 14 of 35 pixels";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("a region is missing"), std::string::npos) << e.what();
  }
}

// A part converted to half floats (oiiotool -d half) no longer holds the render's values:
// refused by name before anything merges.
TEST_F(FilmMergeTest, PartsNotInFloatAreRefused) {
  const fs::path p = dir / "p.exr";
  write_film(p, frame_film({0, 0, 7, 5}), ToneMap{}, {{"camera", "0"}});
  const FilmFile f = read_film(p);
  OIIO::ImageSpec spec(7, 5, 5, OIIO::TypeDesc::HALF);
  spec.channelnames = {"R", "G", "B", "rays", "depth"};
  spec.attribute("zigzag:exposure", 1.0f);
  const fs::path half = foreign_exr("half.exr", spec);
  for (auto read : {&read_film, &read_film_header}) {
    try {
      (void)read(half);
      ADD_FAILURE() << "a half part was read as a film";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("channel R is half, not the float"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(f.film.channels.size(), 2u);  // the float part reads
}

// An exposure attribute that is there but unusable (NaN, a string) is named as such, not
// as missing.
TEST_F(FilmMergeTest, AnUnusableExposureIsNamedNotCalledMissing) {
  for (const bool as_text : {false, true}) {
    OIIO::ImageSpec spec(4, 3, 3, OIIO::TypeDesc::FLOAT);
    if (as_text) spec.attribute("zigzag:exposure", "bright");
    else spec.attribute("zigzag:exposure", std::nanf(""));
    try {
      (void)read_film_header(foreign_exr("exposure.exr", spec));
      ADD_FAILURE() << "read";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("its zigzag:exposure attribute is not a positive float"), std::string::npos)
          << e.what();
    }
  }
}

// The EXR writer's other names (.sxr, .mxr) get the radiance, as .exr does, and its layers;
// Radiance's .rgbe gets radiance too. They took the 8-bit display image.
TEST_F(FilmMergeTest, EveryNameOfAnHdrWriterGetsRadiance) {
  EXPECT_TRUE(writes_radiance("a.sxr"));
  EXPECT_TRUE(writes_radiance("a.MXR"));
  EXPECT_TRUE(writes_radiance("a.rgbe"));
  EXPECT_TRUE(holds_extra_channels("a.sxr"));
  EXPECT_FALSE(holds_extra_channels("a.hdr"));
  EXPECT_FALSE(writes_radiance("a.png"));
  EXPECT_FALSE(writes_radiance("a.tif"));
  EXPECT_FALSE(writes_radiance("a"));
  const Film film = frame_film({0, 0, 7, 5});
  write_film(dir / "f.sxr", film, ToneMap{});
  const FilmFile back = read_film(dir / "f.sxr");
  EXPECT_EQ(back.film.radiance[8], film.radiance[8]);  // 0.1, 0.01, 1/3: not display values
  EXPECT_EQ(back.film.channels.size(), 2u);
}

TEST_F(FilmMergeTest, OnlyAnExrHoldsChannels) {
  EXPECT_THROW(write_film(dir / "f.png", frame_film({0, 0, 7, 5}), ToneMap{}), Error);
  EXPECT_THROW(write_film(dir / "f.hdr", frame_film({0, 0, 7, 5}), ToneMap{}), Error);
  EXPECT_FALSE(fs::exists(dir / "f.png"));
}

}  // namespace
}  // namespace zz
