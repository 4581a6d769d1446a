// What the loader reads from a glTF's JSON beside tinygltf (scene/gltf_json.h).
#include "scene/gltf_json.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace zz::gltf {
namespace {

TEST(GltfJson, Base64SizeCountsStrictPaddedPayloadsOnly) {
  EXPECT_EQ(base64_decoded_size(""), 0u);
  EXPECT_EQ(base64_decoded_size("QUJD"), 3u);      // "ABC"
  EXPECT_EQ(base64_decoded_size("QUI="), 2u);
  EXPECT_EQ(base64_decoded_size("QQ=="), 1u);
  EXPECT_EQ(base64_decoded_size("a+/9QUJD"), 6u);
  EXPECT_FALSE(base64_decoded_size("QUJ"));        // not padded to 4: tinygltf decides
  EXPECT_FALSE(base64_decoded_size("Q*JD"));       // outside the alphabet
  EXPECT_FALSE(base64_decoded_size("Q=JD"));       // '=' only at the end
  EXPECT_FALSE(base64_decoded_size("Q==="));       // at most two of them
}

TEST(GltfJson, EmbeddedBufferOfAnotherLengthThanItsByteLengthIsRefused) {
  const auto doc = parse_json(R"({"buffers": [{"uri": "data:application/octet-stream;base64,QUJD", "byteLength": 3},
                                              {"uri": "data:application/gltf-buffer;base64,QUI=", "byteLength": 3}]})");
  try {
    check_embedded_buffers(doc, "f.gltf");
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "f.gltf: buffer 1: its data: URI holds 2 bytes, but its byteLength says 3");
  }
  EXPECT_NO_THROW(check_embedded_buffers(parse_json(R"({"buffers": [{"uri": "x.bin", "byteLength": 3}]})"), "f"));
  EXPECT_NO_THROW(check_embedded_buffers(parse_json("[[[["), "f"));  // not JSON: tinygltf says so
}

TEST(GltfJson, DataUrisInMessagesAreCutShort) {
  const std::string uri = "data:image/png;base64," + std::string(100, 'A');
  EXPECT_EQ(elide_data_uris("cannot decode " + uri + " in image"),
            "cannot decode " + uri.substr(0, 48) + "... (122 characters) in image");
  EXPECT_EQ(elide_data_uris("short data:,abc stays"), "short data:,abc stays");
}

TEST(GltfJson, ImageReadWarningsAreLeftToTheImageLoader) {
  EXPECT_EQ(without_image_read_warnings("File not found : a.png\nFailed to load external 'uri' for image[0] name = []\n"
                                        "Unknown extension X\n"),
            "Unknown extension X\n");
  // A missing .bin's "File not found" is not an image's and stays.
  EXPECT_EQ(without_image_read_warnings("File not found : a.bin\n"), "File not found : a.bin\n");
}

TEST(GltfJson, ExternalFilesAndBufferLengthsFromTheDocument) {
  const auto doc = parse_json(R"({"buffers": [{"uri": "a.bin", "byteLength": 8}, {"uri": "data:,x", "byteLength": 1},
                                              {"uri": "b.bin", "byteLength": -1}],
                                  "images": [{"uri": "t.png"}, {"bufferView": 0}]})");
  EXPECT_EQ(external_uris(doc), (std::vector<std::string>{"a.bin", "b.bin", "t.png"}));
  EXPECT_EQ(external_buffer_lengths(doc), (std::vector<std::pair<std::string, uint64_t>>{{"a.bin", 8}}));
  EXPECT_TRUE(external_uris(parse_json("not json")).empty());
}

}  // namespace
}  // namespace zz::gltf
