#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <limits>

#include "core/error.h"
#include "gltf_fixture.h"
#include "scene/gltf_file.h"
#include "scene/loader.h"

namespace zz {
namespace {

using test::GltfBuilder;
using test::kTriNrm;
using test::kTriPos;

const LoadOptions kQuiet{{}, true};

void expect_vec(glm::vec3 a, glm::vec3 b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

glm::vec3 geometric_normal(const Scene& s, size_t t) {
  return glm::normalize(glm::cross(s.positions[3 * t + 1] - s.positions[3 * t], s.positions[3 * t + 2] - s.positions[3 * t]));
}

// The loader's expected-failure contract: a zz::Error whose message contains `needle`.
template <typename F>
void expect_error(F&& f, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "no error; expected one containing '" << needle << "'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "message must be one line";
  }
}

TEST(GltfLoader, TranslatedRotatedScaledNode) {
  GltfBuilder b;
  int m = b.mesh("tri", kTriPos, kTriNrm);
  // M = T * R * S: scale 2, then 90 degrees about +z, then translate (1, 2, 3).
  const float h = std::sqrt(0.5f);
  b.node({{"mesh", m}, {"translation", {1, 2, 3}}, {"rotation", {0, 0, h, h}}, {"scale", {2, 2, 2}}});
  Scene s = load_scene(b.write(test::temp_dir("trs")), kQuiet);
  ASSERT_EQ(s.triangle_count(), 1u);
  expect_vec(s.positions[0], {1, 2, 3});
  expect_vec(s.positions[1], {1, 4, 3});   // (1,0,0) -> (2,0,0) -> (0,2,0) -> +T
  expect_vec(s.positions[2], {-1, 2, 3});  // (0,1,0) -> (0,2,0) -> (-2,0,0) -> +T
  expect_vec(s.normals[0], {0, 0, 1});
  expect_vec(geometric_normal(s, 0), {0, 0, 1});
}

TEST(GltfLoader, MatrixNodeAndHierarchyCompose) {
  GltfBuilder b;
  int m = b.mesh("tri", kTriPos, kTriNrm);
  int child = b.node({{"mesh", m}, {"translation", {0, 0, 5}}}, false);
  // Column-major matrix: uniform scale 3 and translation (10, 0, 0).
  b.node({{"matrix", {3, 0, 0, 0, 0, 3, 0, 0, 0, 0, 3, 0, 10, 0, 0, 1}}, {"children", {child}}});
  Scene s = load_scene(b.write(test::temp_dir("matrix")), kQuiet);
  ASSERT_EQ(s.triangle_count(), 1u);
  expect_vec(s.positions[0], {10, 0, 15});  // parent * child: 3 * (0,0,5) + (10,0,0)
  expect_vec(s.positions[1], {13, 0, 15});
}

// glTF 3.5.3: nodes form disjoint strict trees. A chain deeper than any recursion would
// take loads, in the order of the hierarchy; a node with two parents (17 kB of such nodes
// instanced millions of triangles) or a root that is also a child is an error naming it.
TEST(GltfLoader, NodesFormDisjointTreesOfAnyDepth) {
  auto dir = test::temp_dir("trees");
  {
    GltfBuilder b;
    const int m = b.mesh("tri", kTriPos, kTriNrm);
    int below = b.node({{"mesh", m}, {"translation", {0, 0, 1}}}, false);
    for (int level = 0; level < 5000; ++level) below = b.node({{"children", {below}}, {"translation", {0, 0, 1}}}, false);
    b.doc["scenes"][0]["nodes"] = {below};
    b.node({{"mesh", m}, {"translation", {7, 0, 0}}});  // a second root, after the chain
    const Scene s = load_scene(b.write(dir, "chain"), kQuiet);
    ASSERT_EQ(s.triangle_count(), 2u);
    expect_vec(s.positions[0], {0, 0, 5001});  // the chain first (the scene's first root), each level +1 in z
    expect_vec(s.positions[3], {7, 0, 0});
  }
  auto refused = [&](auto edit, const std::string& needle) {
    GltfBuilder b;
    const int m = b.mesh("tri", kTriPos, kTriNrm);
    const int leaf = b.node({{"mesh", m}, {"name", "shared"}}, false);
    b.node({{"children", {leaf}}});
    edit(b, leaf);
    const auto path = b.write(dir, "shared");
    expect_error([&] { load_scene(path, kQuiet); }, needle);
  };
  refused([](GltfBuilder& b, int leaf) { b.node({{"children", {leaf}}}); }, "node 0 'shared' is reached twice");
  refused([](GltfBuilder& b, int leaf) { b.doc["nodes"][1]["children"] = {leaf, leaf}; }, "reached twice");
  refused([](GltfBuilder& b, int leaf) { b.doc["scenes"][0]["nodes"].push_back(leaf); }, "reached twice");
}

TEST(GltfLoader, NormalsUseInverseTranspose) {
  GltfBuilder b;
  const float k = 1.0f / std::sqrt(3.0f);
  int m = b.mesh("slanted", {1, 0, 0, 0, 1, 0, 0, 0, 1}, {k, k, k, k, k, k, k, k, k});
  b.node({{"mesh", m}, {"scale", {2, 1, 1}}});
  Scene s = load_scene(b.write(test::temp_dir("it")), kQuiet);
  ASSERT_EQ(s.triangle_count(), 1u);
  // Non-uniform scale: the transformed plane's normal is (1,2,2)/3, not M * n.
  expect_vec(s.normals[0], glm::vec3(1, 2, 2) / 3.0f);
  expect_vec(geometric_normal(s, 0), glm::vec3(1, 2, 2) / 3.0f);
}

TEST(GltfLoader, NegativeScaleFlipsWinding) {
  GltfBuilder b;
  int m = b.mesh("tri", kTriPos, kTriNrm);
  b.node({{"mesh", m}, {"scale", {-1, 1, 1}}});
  Scene s = load_scene(b.write(test::temp_dir("neg")), kQuiet);
  ASSERT_EQ(s.triangle_count(), 1u);
  expect_vec(s.normals[0], {0, 0, 1});
  // Without the flip the mirrored triangle would wind clockwise (geometric normal -z).
  expect_vec(geometric_normal(s, 0), {0, 0, 1});
  EXPECT_LE(s.positions[1].x + s.positions[2].x, -0.99f);
}

// A triangle wound against its vertex normals is rewound so its front is the normals'
// side (the shader turns shading normals to the front: flat shading otherwise), also
// under a mirroring node; a triangle that agrees keeps its order.
TEST(GltfLoader, TrianglesWoundAgainstTheirNormalsAreRewound) {
  for (const float mirror : {1.0f, -1.0f}) {
    GltfBuilder b;
    const int against = b.mesh("against", kTriPos, {0, 0, -1, 0.1f, 0, -1, 0, 0.1f, -1});
    const int along = b.mesh("along", kTriPos, kTriNrm);
    b.node({{"mesh", against}, {"scale", {mirror, 1, 1}}});
    b.node({{"mesh", along}, {"scale", {mirror, 1, 1}}});
    Scene s = load_scene(b.write(test::temp_dir("rewound")), kQuiet);
    ASSERT_EQ(s.triangle_count(), 2u);
    expect_vec(geometric_normal(s, 0), {0, 0, -1});
    expect_vec(geometric_normal(s, 1), {0, 0, 1});
    // Vertex attributes follow their positions: vertex (±1,0,0) keeps its normal's x tilt.
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(s.normals[size_t(k)].x * mirror > 0.01f, s.positions[size_t(k)].x * mirror > 0.5f) << mirror << " " << k;
    EXPECT_EQ(s.positions[3], glm::vec3(0.0f));
    EXPECT_EQ(s.positions[4].x * mirror > 0.5f, mirror > 0.0f);  // (1,0,0) second unless mirrored
  }
  // On a crease smoothed across, some normals may point away: that is not a rewind.
  GltfBuilder b;
  const int crease = b.mesh("crease", kTriPos, {0.9f, 0, 0.2f, 0, 0.6f, -0.8f, 0, 0.6f, -0.8f});
  b.node({{"mesh", crease}});
  Scene s = load_scene(b.write(test::temp_dir("crease")), kQuiet);
  expect_vec(geometric_normal(s, 0), {0, 0, 1});
}

TEST(GltfLoader, IndexedAndNonIndexedGiveSameTriangles) {
  const std::vector<float> quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
  std::vector<float> flat;
  for (uint16_t i : idx) flat.insert(flat.end(), quad.begin() + 3 * i, quad.begin() + 3 * i + 3);
  GltfBuilder a, b;
  a.node({{"mesh", a.mesh("q", quad, {}, idx)}});
  b.node({{"mesh", b.mesh("q", flat)}});
  Scene sa = load_scene(a.write(test::temp_dir("a")), kQuiet);
  Scene sb = load_scene(b.write(test::temp_dir("b")), kQuiet);
  ASSERT_EQ(sa.triangle_count(), 2u);
  ASSERT_EQ(sa.positions.size(), sb.positions.size());
  for (size_t i = 0; i < sa.positions.size(); ++i) {
    EXPECT_EQ(sa.positions[i], sb.positions[i]) << i;
    EXPECT_EQ(sa.normals[i], sb.normals[i]) << i;  // flat normals, generated
  }
  expect_vec(sa.normals[0], {0, 0, 1});
}

TEST(GltfLoader, StripsAndFansBecomeConsistentlyWoundTriangles) {
  const std::vector<float> strip = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0};
  const std::vector<float> fan = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 0.5f, 0};
  GltfBuilder b;
  b.node({{"mesh", b.mesh("strip", strip, {}, {}, 5)}});
  b.node({{"mesh", b.mesh("fan", fan, {}, {}, 6)}});
  Scene s = load_scene(b.write(test::temp_dir("strip")), kQuiet);
  ASSERT_EQ(s.triangle_count(), 6u);  // 3 from the strip, 3 from the fan
  for (size_t t = 0; t < s.triangle_count(); ++t) expect_vec(geometric_normal(s, t), {0, 0, 1});
}

TEST(GltfLoader, PointsAndLinesAreSkipped) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("lines", kTriPos, {}, {}, 1)}});
  b.node({{"mesh", b.mesh("points", kTriPos, {}, {}, 0)}});
  b.node({{"mesh", b.mesh("tri", kTriPos)}});
  Scene s = load_scene(b.write(test::temp_dir("lines")), kQuiet);
  EXPECT_EQ(s.triangle_count(), 1u);
}

TEST(GltfLoader, DegenerateTrianglesAreDroppedAndCounted) {
  GltfBuilder b;
  // Second triangle repeats a vertex, third is collinear.
  b.node({{"mesh", b.mesh("mixed", {0, 0, 0, 1, 0, 0, 0, 1, 0,  0, 0, 0, 1, 0, 0, 1, 0, 0,  0, 0, 0, 1, 1, 1, 2, 2, 2})}});
  testing::internal::CaptureStderr();
  Scene s = load_scene(b.write(test::temp_dir("degen")), LoadOptions{{}, false});
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_EQ(s.triangle_count(), 1u);
  EXPECT_EQ(s.dropped_degenerate, 2u);
  EXPECT_NE(warned.find("2 degenerate triangle(s) dropped"), std::string::npos) << warned;  // not in --stats alone
}

// A shading normal of any finite length but zero is the direction it gives: 1e30 or 1e-25
// long, its square overflowed or underflowed, and the flat normal replaced it.
TEST(GltfLoader, ShadingNormalsOfAnyLengthKeepTheirDirection) {
  for (const float length : {1e30f, 1e-25f, 2.0f}) {
    SCOPED_TRACE(length);
    const float c = 0.6f * length, d = 0.8f * length;
    GltfBuilder b;
    b.node({{"mesh", b.mesh("tri", kTriPos, {0, c, d, 0, c, d, 0, c, d})}});
    const Scene s = load_scene(b.write(test::temp_dir("nlen")), kQuiet);
    ASSERT_EQ(s.normals.size(), 3u);
    for (const glm::vec3& n : s.normals) expect_vec(n, {0.0f, 0.6f, 0.8f}, 1e-6f);
  }
}

TEST(GltfLoader, NanVertexIsAnErrorNamingTheMesh) {
  GltfBuilder b;
  std::vector<float> pos = kTriPos;
  pos[4] = std::numeric_limits<float>::quiet_NaN();
  b.node({{"mesh", b.mesh("broken_wing", pos)}});
  auto path = b.write(test::temp_dir("nan"));
  expect_error([&] { load_scene(path, kQuiet); }, "broken_wing");
  GltfBuilder c;
  std::vector<float> nrm = kTriNrm;
  nrm[0] = std::numeric_limits<float>::infinity();
  c.node({{"mesh", c.mesh("inf_normal", kTriPos, nrm)}});
  auto path2 = c.write(test::temp_dir("inf"));
  expect_error([&] { load_scene(path2, kQuiet); }, "inf_normal");
}

// glTF 2.0 section 3.12: a loader must refuse a file that requires an extension it does
// not support (the data may only make sense through it, e.g. Draco-compressed meshes).
TEST(GltfLoader, ARequiredExtensionItDoesNotSupportIsAnError) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos)}});
  b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression", "KHR_texture_transform"};
  b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  const auto dir = test::temp_dir("required");
  expect_error([&] { load_scene(b.write(dir), kQuiet); }, "requires the glTF extension KHR_draco_mesh_compression");
  b.doc["extensionsRequired"] = {"KHR_texture_transform"};  // read by the loader: loads
  EXPECT_EQ(load_scene(b.write(dir), kQuiet).triangle_count(), 1u);
}

// Section 3.7.2.1: POSITION is float (integers only with KHR_mesh_quantization); read as
// floats regardless, unsigned bytes gave a silent stray triangle.
TEST(GltfLoader, AttributeComponentTypesFollowTheSpec) {
  GltfBuilder b;
  const uint8_t corners[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0};  // one triangle, padded to 4 bytes
  const int bv = b.view(corners, sizeof corners);
  b.doc["accessors"].push_back({{"bufferView", bv}, {"componentType", 5121}, {"count", 3}, {"type", "VEC3"}});
  b.doc["meshes"].push_back(
      {{"name", "bytes"}, {"primitives", {{{"attributes", {{"POSITION", int(b.doc["accessors"].size()) - 1}}}}}}});
  b.node({{"mesh", 0}});
  const auto dir = test::temp_dir("component");
  expect_error([&] { load_scene(b.write(dir), kQuiet); }, "not allow for POSITION without KHR_mesh_quantization");
  b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
  b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  const Scene s = load_scene(b.write(dir), kQuiet);
  ASSERT_EQ(s.triangle_count(), 1u);
  expect_vec(s.positions[1] - s.positions[0], {1, 0, 0});  // unnormalized bytes: their integer values
  expect_vec(s.positions[2] - s.positions[0], {0, 1, 0});
}

// The other attributes' rules, each on a float triangle: TEXCOORD takes normalized
// unsigned integers in core glTF, any byte or short with quantization; NORMAL only signed
// normalized ones, and only with quantization.
TEST(GltfLoader, NormalAndTexcoordComponentTypesFollowTheSpec) {
  struct Case {
    const char* attribute;
    int component_type;
    bool normalized, quantized, allowed;
  };
  const auto dir = test::temp_dir("attributes");
  for (const Case& c : {Case{"TEXCOORD_0", 5121, true, false, true}, Case{"TEXCOORD_0", 5121, false, false, false},
                        Case{"TEXCOORD_0", 5121, false, true, true}, Case{"TEXCOORD_0", 5125, true, true, false},
                        Case{"NORMAL", 5120, true, false, false}, Case{"NORMAL", 5120, true, true, true},
                        Case{"NORMAL", 5120, false, true, false}, Case{"NORMAL", 5121, true, true, false}}) {
    SCOPED_TRACE(std::string(c.attribute) + " " + std::to_string(c.component_type) + (c.normalized ? " n" : "") +
                 (c.quantized ? " q" : ""));
    GltfBuilder b;
    b.node({{"mesh", b.mesh("tri", kTriPos)}});
    const bool normal = std::string(c.attribute) == "NORMAL";
    const int size = c.component_type == 5125 ? 4 : 1;  // unsigned int, else (unsigned) byte
    std::vector<uint8_t> data(size_t(3 * (normal ? 3 : 2) * size), 0);
    if (normal)
      for (int v = 0; v < 3; ++v) data[size_t(3 * v + 2)] = 127;  // +z, normalized
    const int bv = b.view(data.data(), data.size());
    b.doc["accessors"].push_back({{"bufferView", bv}, {"componentType", c.component_type}, {"count", 3},
                                  {"type", normal ? "VEC3" : "VEC2"}, {"normalized", c.normalized}});
    b.doc["meshes"][0]["primitives"][0]["attributes"][c.attribute] = int(b.doc["accessors"].size()) - 1;
    if (c.quantized) b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    const auto path = b.write(dir);
    if (c.allowed) {
      const Scene s = load_scene(path, kQuiet);
      if (normal) expect_vec(s.normals[0], {0, 0, 1});
    } else {
      expect_error([&] { load_scene(path, kQuiet); }, std::string("does not allow for ") + c.attribute);
    }
  }
}

TEST(GltfLoader, MissingAndTruncatedFilesAreErrorsNamingTheFile) {
  auto dir = test::temp_dir("trunc");
  expect_error([&] { load_scene(dir / "nope.gltf", kQuiet); }, "nope.gltf");

  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm)}});
  auto path = b.write(dir, "whole");
  const std::string text = test::read_text(path);
  test::write_text(dir / "half.gltf", text.substr(0, text.size() / 2));
  std::filesystem::copy_file(dir / "whole.bin", dir / "half.bin");
  expect_error([&] { load_scene(dir / "half.gltf", kQuiet); }, "half.gltf");

  // Buffer shorter than its declared byteLength.
  const std::string bin = test::read_text(dir / "whole.bin");
  test::write_text(dir / "whole.bin", bin.substr(0, bin.size() - 8));
  expect_error([&] { load_scene(path, kQuiet); }, "whole.gltf");

  // Missing buffer file.
  std::filesystem::remove(dir / "whole.bin");
  expect_error([&] { load_scene(path, kQuiet); }, "whole.gltf");
}

// glTF 1.0 (a different format) is refused, not read as 2.0 without a word: by its asset
// version in a .gltf, by the container's version in a .glb.
TEST(GltfLoader, OnlyGltf2IsRead) {
  auto dir = test::temp_dir("version");
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm)}});
  b.doc["asset"]["version"] = "1.0";
  expect_error([&] { load_scene(b.write(dir), kQuiet); }, "glTF version '1.0'; only glTF 2.0");
  b.doc["asset"]["version"] = "2.0";
  const auto glb = b.write_glb(dir);
  EXPECT_EQ(load_scene(glb, kQuiet).triangle_count(), 1u);
  std::string bytes = test::read_text(glb);
  bytes[4] = 1;  // glTF 1.0's binary header: version 1, then the content's length and format 0
  bytes.replace(16, 4, std::string(4, '\0'));
  test::write_text(glb, bytes);
  expect_error([&] { load_scene(glb, kQuiet); }, "GLB container version 1");
  b.doc["asset"] = {{"version", "2.1"}};  // a later 2.x minor version loads...
  EXPECT_EQ(load_scene(b.write(dir), kQuiet).triangle_count(), 1u);
  b.doc["asset"]["minVersion"] = "2.1";  // ...unless it requires more than 2.0
  expect_error([&] { load_scene(b.write(dir), kQuiet); }, "minVersion '2.1'");
}

// A device or a folder where a file belongs is named as such, never read (a scene linked to
// /dev/zero read until memory ran out; a buffer folder gave std::bad_alloc).
TEST(GltfLoader, DevicesAndFoldersAreNotReadAsFiles) {
  auto dir = test::temp_dir("device");
  for (const char* name : {"zero.gltf", "zero.glb", "zero.json"}) {
    std::filesystem::create_symlink("/dev/zero", dir / name);
    expect_error([&] { load_scene(dir / name, kQuiet); }, std::string(name) + ": not a regular file");
  }
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm)}});
  const auto path = b.write(dir, "folder");
  std::filesystem::remove(dir / "folder.bin");
  std::filesystem::create_directory(dir / "folder.bin");
  expect_error([&] { load_scene(path, kQuiet); }, "folder.bin : not a regular file");
}

TEST(GltfLoader, OutOfRangeReferencesAreErrors) {
  auto dir = test::temp_dir("range");
  auto broken = [&](auto edit, const std::string& needle) {
    GltfBuilder b;
    b.node({{"mesh", b.mesh("victim", kTriPos, kTriNrm, {0, 1, 2})}});
    edit(b.doc);
    auto path = b.write(dir);
    expect_error([&] { load_scene(path, kQuiet); }, needle);
  };
  broken([](auto& d) { d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 99; }, "victim");
  broken([](auto& d) { d["accessors"][0]["count"] = 1000; }, "victim");
  broken([](auto& d) { d["accessors"][0]["byteOffset"] = 4096; }, "model.gltf");
  broken([](auto& d) { d["accessors"][2]["bufferView"] = 42; }, "model.gltf");
  broken([](auto& d) { d["bufferViews"][0]["byteLength"] = 1 << 20; }, "model.gltf");
  broken([](auto& d) { d["nodes"][0]["mesh"] = 7; }, "model.gltf");
  broken([](auto& d) { d["scenes"][0]["nodes"] = {5}; }, "model.gltf");
  broken([](auto& d) { d["nodes"][0]["children"] = {0}; }, "cyclic");
  // tinygltf hands an image's bufferView to the image callback unchecked: 100 MB past a
  // buffer of a few bytes was read (a crash, or garbage as a texture).
  broken(
      [](auto& d) {
        d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 100000000}});
        d["images"] = {{{"bufferView", d["bufferViews"].size() - 1}, {"mimeType", "image/png"}}};
      },
      "exceeds its buffer");
  broken(
      [](auto& d) {
        d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 4000000000u}, {"byteLength", 4}});
        d["images"] = {{{"bufferView", d["bufferViews"].size() - 1}, {"mimeType", "image/png"}}};
      },
      "exceeds its buffer");
}

TEST(GltfLoader, OutOfRangeIndexIsAnError) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("bad_index", kTriPos, {}, {0, 1, 7})}});
  auto path = b.write(test::temp_dir("idx"));
  expect_error([&] { load_scene(path, kQuiet); }, "bad_index");
}

// Every truncation of a valid file throws zz::Error (never crashes, never loads): the GLB
// header states the file's length and the chunks theirs, so a cut file is always short of
// something. Measured: all 824 prefixes of this 824-byte file fail.
TEST(GltfLoader, TruncationsNeverCrash) {
  auto dir = test::temp_dir("fuzz");
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm, {0, 1, 2}, 4, -1, {0, 0, 1, 0, 0, 1})}});
  auto glb = b.write_glb(dir);
  const std::string bytes = test::read_text(glb);
  ASSERT_GT(bytes.size(), 100u);
  int loaded = 0, errors = 0;
  for (size_t n = 0; n < bytes.size(); ++n) {
    test::write_text(dir / "cut.glb", bytes.substr(0, n));
    try {
      load_scene(dir / "cut.glb", kQuiet);
      ++loaded;
      ADD_FAILURE() << "a GLB cut to " << n << " of " << bytes.size() << " bytes loaded";
    } catch (const Error&) {
      ++errors;
    }
  }
  EXPECT_EQ(loaded, 0);
  EXPECT_EQ(size_t(errors), bytes.size());
  test::write_text(dir / "full.glb", bytes);
  EXPECT_EQ(load_scene(dir / "full.glb", kQuiet).triangle_count(), 1u);
}

// Deterministic mutation fuzzing of the JSON: digits replaced (indices, counts, offsets,
// strides go out of range) and bytes overwritten. Each variant loads or throws zz::Error.
TEST(GltfLoader, MutatedFilesNeverCrash) {
  auto dir = test::temp_dir("mutate");
  GltfBuilder b;
  b.doc["materials"] = {{{"name", "m"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}}}}};
  b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
  int child = b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm, {0, 1, 2}, 4, 0, {0, 0, 1, 0, 0, 1})}}, false);
  b.node({{"children", {child}}, {"camera", 0}, {"scale", {1, 2, 3}}});
  b.node({{"mesh", b.mesh("strip", kTriPos, {}, {}, 5)}});
  const std::string text = test::read_text(b.write(dir, "base"));
  std::filesystem::copy_file(dir / "base.bin", dir / "mut.bin");
  uint32_t state = 12345u;
  auto next = [&] { state = state * 1664525u + 1013904223u; return state >> 8; };
  int loaded = 0, errors = 0;
  for (int iter = 0; iter < 300; ++iter) {
    std::string m = text;
    for (int k = 0; k < 1 + int(next() % 3); ++k) {
      size_t at = next() % m.size();
      if (iter % 3 == 0) m[at] = char(next() & 0xFF);
      else if (m[at] >= '0' && m[at] <= '9') m[at] = char('0' + next() % 10);
      else if (iter % 3 == 1) m.insert(at, std::to_string(next() % 100000));
    }
    test::write_text(dir / "mut.gltf", m);
    try {
      load_scene(dir / "mut.gltf", kQuiet);
      ++loaded;
    } catch (const Error&) {
      ++errors;
    }
  }
  EXPECT_GT(loaded, 0);
  EXPECT_GT(errors, 0);
}

// tinygltf converts extras and extensions by recursion: 20 000 nested arrays overflowed
// the stack (SIGSEGV) before the depth check; sanitized builds, with larger frames, at fewer.
TEST(GltfLoader, DeeplyNestedJsonIsAnErrorNotAStackOverflow) {
  auto dir = test::temp_dir("deep");
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm)}});
  auto nested = [](int depth) { return "\"extras\": " + std::string(size_t(depth), '[') + std::string(size_t(depth), ']') + ", "; };
  b.raw_members = nested(20000);
  expect_error([&] { load_scene(b.write(dir, "deep"), kQuiet); }, "nested deeper than 512");
  expect_error([&] { load_scene(b.write_glb(dir, "deep"), kQuiet); }, "nested deeper than 512");
  // What a scene may hold, and brackets inside strings, are no nesting.
  b.raw_members = nested(gltf::kMaxJsonDepth - 1) + "\"extensionsUsed\": [], \"extensionsRequired\": [], ";
  b.doc["asset"]["generator"] = std::string(1000, '[') + "\"{";
  EXPECT_EQ(load_scene(b.write(dir, "ok"), kQuiet).triangle_count(), 1u);
  EXPECT_EQ(load_scene(b.write_glb(dir, "ok"), kQuiet).triangle_count(), 1u);
}

// A .bin longer than its buffer's byteLength is valid glTF (Khronos's SimpleMaterial pads
// its .bin); tinygltf 2.7 refused it as a "File size mismatch". A shorter one stays an error.
TEST(GltfLoader, ExternalBufferLongerThanItsByteLengthLoads) {
  const auto dir = test::temp_dir("longbin");
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm)}});
  const auto gltf = b.write(dir);
  std::ofstream(dir / "model.bin", std::ios::binary | std::ios::app).write("padding!", 8);
  const Scene s = load_scene(gltf, kQuiet);
  EXPECT_EQ(s.triangle_count(), 1u);
  expect_vec(s.positions[1], {1, 0, 0});
  std::filesystem::resize_file(dir / "model.bin", b.bin.size() - 4);
  expect_error([&] { load_scene(gltf, kQuiet); }, "model.bin");
}

// An embedded buffer whose data: URI decodes to another length than its byteLength is
// refused in one short line; tinygltf quoted the whole payload (1.4 MB of text for 1 MB).
TEST(GltfLoader, EmbeddedBufferOfTheWrongLengthSaysSoBriefly) {
  const auto dir = test::temp_dir("embedlen");
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm)}});
  b.bin.resize(30000, 0);
  b.write(dir);
  nlohmann::json doc = nlohmann::json::parse(std::ifstream(dir / "model.gltf"));
  const std::string payload(40000, 'A');  // 30000 zero bytes in base64
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + payload;
  doc["buffers"][0]["byteLength"] = 30004;
  test::write_text(dir / "bad_length.gltf", doc.dump());
  expect_error([&] { load_scene(dir / "bad_length.gltf", kQuiet); },
               "buffer 0: its data: URI holds 30000 bytes, but its byteLength says 30004");
  // Not base64 at all: tinygltf's own message, its URI cut short.
  doc["buffers"][0]["uri"] = "data:application/octet-stream;base64,*" + payload.substr(1);
  doc["buffers"][0]["byteLength"] = 30000;
  test::write_text(dir / "bad_base64.gltf", doc.dump());
  expect_error([&] { load_scene(dir / "bad_base64.gltf", kQuiet); }, "base64,*AAAAAAAAAA... (40037 characters) in Buffer");
}

// The content decides between binary and JSON glTF, not the extension.
TEST(GltfLoader, BinaryGltfLoadsWhateverItsExtension) {
  const auto dir = test::temp_dir("misnamed");
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm)}});
  std::filesystem::rename(b.write_glb(dir), dir / "binary.gltf");
  EXPECT_EQ(load_scene(dir / "binary.gltf", kQuiet).triangle_count(), 1u);
  const auto json = b.write(dir, "text");
  std::filesystem::rename(json, dir / "text.glb");
  EXPECT_EQ(load_scene(dir / "text.glb", kQuiet).triangle_count(), 1u);
  EXPECT_EQ(gltf::external_files(dir / "text.glb"), std::vector<std::filesystem::path>{dir / "text.bin"});
}

// glTF 2.0: byteStride is for vertex attributes; an index view with one is named as such.
TEST(GltfLoader, IndexViewWithAByteStrideIsRefusedByName) {
  GltfBuilder b;
  const int m = b.mesh("tri", kTriPos, kTriNrm);
  const int indices = b.indices({0, 1, 2, 0});
  b.doc["accessors"][size_t(indices)]["count"] = 3;
  b.doc["bufferViews"][b.doc["accessors"][size_t(indices)]["bufferView"].get<size_t>()]["byteStride"] = 4;
  b.doc["meshes"][size_t(m)]["primitives"][0]["indices"] = indices;
  b.node({{"mesh", m}});
  expect_error([&] { load_scene(b.write(test::temp_dir("idxstride")), kQuiet); }, "which has a byteStride");
}

// Float's squares overflow for edges of 1e10 and underflow below 1e-10: a huge triangle
// was dropped as "zero area" from 1.2e13 on. Up to 1e18 it now loads with its normal; beyond
// that, and below 1e-10, the warning says why it goes.
TEST(GltfLoader, HugeTrianglesLoadAndOutOfRangeOnesAreDroppedWithTheReason) {
  for (const float scale : {1e14f, 1e17f}) {
    SCOPED_TRACE(scale);
    GltfBuilder b;
    b.node({{"mesh", b.mesh("tri", kTriPos)}, {"scale", {scale, scale, scale}}});  // flat normals
    const Scene s = load_scene(b.write(test::temp_dir("huge")), kQuiet);
    ASSERT_EQ(s.triangle_count(), 1u);
    EXPECT_EQ(s.dropped_degenerate, 0u);
    expect_vec(s.normals[0], {0, 0, 1});
    expect_vec(s.positions[1], {scale, 0, 0}, scale * 1e-6f);
  }
  for (const auto& [scale, why] : {std::pair{1e19f, "beyond +-1e18 units"}, std::pair{1e-12f, "edges below about 1e-10"}}) {
    SCOPED_TRACE(scale);
    GltfBuilder b;
    b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm)}, {"scale", {scale, scale, scale}}});
    b.node({{"mesh", b.mesh("kept", kTriPos, kTriNrm)}});
    testing::internal::CaptureStderr();
    const Scene s = load_scene(b.write(test::temp_dir("range")), LoadOptions{{}, false});
    const std::string warned = testing::internal::GetCapturedStderr();
    EXPECT_EQ(s.triangle_count(), 1u);
    EXPECT_EQ(s.dropped_degenerate, 1u);
    EXPECT_NE(warned.find(std::string("1 triangle(s) dropped: ") + (scale > 1.0f ? "a vertex lies " : "") + why),
              std::string::npos) << warned;
    EXPECT_EQ(warned.find("degenerate"), std::string::npos) << warned;
  }
}

// What the spec forbids but a file may still hold is loaded, with a warning: a matrix whose
// last row is not 0 0 0 1, a TRIANGLES count not a multiple of 3, a spot light whose inner
// cone is not inside its outer one.
TEST(GltfLoader, InvalidButUsableValuesAreWarnedAbout) {
  GltfBuilder b;
  const int m = b.mesh("tri", {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5});
  b.node({{"name", "plain"}, {"mesh", m}, {"matrix", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1}}});
  b.node({{"name", "projective"}, {"matrix", {1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}});
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"name", "cone"}, {"type", "spot"}, {"spot", {{"innerConeAngle", 0.6}, {"outerConeAngle", 0.5}}}}};
  b.node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  testing::internal::CaptureStderr();
  const Scene s = load_scene(b.write(test::temp_dir("invalid")), LoadOptions{{}, false});
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_EQ(s.triangle_count(), 1u);
  expect_vec(s.positions[1], {2, 0, 0});
  EXPECT_EQ(warned.find("node 0"), std::string::npos) << warned;  // an affine matrix is fine
  EXPECT_NE(warned.find("node 1 'projective''s matrix is not affine"), std::string::npos) << warned;
  EXPECT_NE(warned.find("4 vertices for TRIANGLES, not a multiple of 3: the last 1 ignored"), std::string::npos) << warned;
  EXPECT_NE(warned.find("spot light 'cone' has an inner cone angle of 0.6 rad, not below its outer 0.5 rad"),
            std::string::npos) << warned;
}

// KHR_lights_punctual requires a spot light's "spot" object; tinygltf's refusal named no
// light ("Spot light description not found.").
TEST(GltfLoader, ASpotLightWithoutItsSpotObjectIsNamed) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm)}});
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}},
                                                         {{"name", "lamp"}, {"type", "spot"}}};
  b.node({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  expect_error([&] { load_scene(b.write(test::temp_dir("spotless")), kQuiet); },
               "light 1 'lamp' is a spot light without its \"spot\" object");
}

TEST(GltfFile, NestingDepthCountsBracketsOutsideStrings) {
  EXPECT_EQ(gltf::json_nesting_depth(""), 0);
  EXPECT_EQ(gltf::json_nesting_depth("{\"a\": [1, {\"b\": []}], \"c\": {}}"), 4);
  EXPECT_EQ(gltf::json_nesting_depth("{\"a\": \"[[[{{{\"}"), 1);
  EXPECT_EQ(gltf::json_nesting_depth("{\"a\": \"\\\" [[[\"}"), 1);  // an escaped quote does not end the string
  EXPECT_EQ(gltf::json_nesting_depth("{\"a\": \"\\\\\", \"b\": [[]]}"), 3);  // an escaped backslash does
  EXPECT_EQ(gltf::json_nesting_depth("]]]}[[", 10), 2);  // stray closers do not go below zero
  EXPECT_EQ(gltf::json_nesting_depth(std::string(100000, '['), 10), 11);  // stops past the limit
}

TEST(GltfLoader, GlbMatchesGltf) {
  auto dir = test::temp_dir("glb");
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm)}, {"translation", {0, 1, 0}}});
  Scene a = load_scene(b.write(dir), kQuiet);
  Scene g = load_scene(b.write_glb(dir), kQuiet);
  ASSERT_EQ(g.triangle_count(), 1u);
  EXPECT_EQ(a.positions, g.positions);
}

TEST(GltfLoader, CamerasAndLightsFollowNodeTransforms) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos)}});
  b.doc["cameras"] = {{{"type", "perspective"}, {"name", "cam"},
                       {"perspective", {{"yfov", 0.5}, {"znear", 0.1}, {"zfar", 50}, {"aspectRatio", 1.5}}}}};
  // Rotated 90 degrees about +y: looks down -x instead of -z.
  const float h = std::sqrt(0.5f);
  b.node({{"camera", 0}, {"translation", {4, 0, 0}}, {"rotation", {0, h, 0, h}}});
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"] = {{"KHR_lights_punctual",
                          {{"lights", {{{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 8}},
                                       {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.4}}}},
                                       {{"type", "directional"}, {"intensity", 2}}}}}}};
  int parent = b.node({{"translation", {0, 10, 0}}});
  int point = b.node({{"translation", {1, 0, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}, false);
  b.doc["nodes"][parent]["children"] = {point};
  b.node({{"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});  // points down -y
  b.node({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  Scene s = load_scene(b.write(test::temp_dir("cam")), kQuiet);
  ASSERT_EQ(s.cameras.size(), 1u);
  const Camera& c = s.cameras[0];
  EXPECT_EQ(c.name, "cam");
  expect_vec(c.position, {4, 0, 0});
  expect_vec(c.forward, {-1, 0, 0});
  expect_vec(c.up, {0, 1, 0});
  expect_vec(c.right, {0, 0, -1});
  EXPECT_FLOAT_EQ(c.yfov, 0.5f);
  EXPECT_FLOAT_EQ(c.aspect, 1.5f);
  EXPECT_FLOAT_EQ(c.znear, 0.1f);
  EXPECT_FLOAT_EQ(c.zfar, 50.0f);
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].type, Light::Type::Point);
  expect_vec(s.lights[0].position, {1, 10, 0});
  expect_vec(s.lights[0].intensity, {8, 4, 2});
  EXPECT_EQ(s.lights[1].type, Light::Type::Spot);
  expect_vec(s.lights[1].direction, {0, -1, 0});
  EXPECT_FLOAT_EQ(s.lights[1].outer_cone, 0.4f);
  EXPECT_EQ(s.lights[2].type, Light::Type::Directional);
  expect_vec(s.lights[2].direction, {0, 0, -1});
}

// Percent-decoded next to the glTF (RFC 3986: '+' is itself, not a space).
TEST(GltfLoader, ExternalFilesAreNamedAsTheirUrisSay) {
  EXPECT_EQ(gltf::external_file("a/scene.gltf", "My%20Wood.png"), std::filesystem::path("a/My Wood.png"));
  EXPECT_EQ(gltf::external_file("a/scene.gltf", "tex/b+c%2fd.png"), std::filesystem::path("a/tex/b+c/d.png"));
  EXPECT_EQ(gltf::external_file("scene.gltf", "x%2"), std::filesystem::path("x%2"));  // too short to decode
  EXPECT_FALSE(gltf::external_file("a/scene.gltf", "data:image/png;base64,AAAA"));     // the bytes are in the URI
  EXPECT_FALSE(gltf::external_file("a/scene.gltf", ""));
  // The scene's file list names the decoded files (a farm hashes them to tell edits).
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos)}});
  const auto dir = test::temp_dir("encoded");
  const auto path = b.write(dir, "my model");
  auto doc = nlohmann::json::parse(test::read_text(path));
  ASSERT_EQ(doc["buffers"][0]["uri"], "my model.bin");
  doc["buffers"][0]["uri"] = "my%20model.bin";
  test::write_text(path, doc.dump());
  const Scene s = load_scene(path, kQuiet);
  ASSERT_EQ(s.source_files.size(), 2u);
  EXPECT_EQ(s.source_files[1], (dir / "my model.bin").string());
}

// A one-triangle glTF in `dir` whose buffer is `stem`.bin, named by that very URI; loads it
// and checks the buffer is the file read.
std::filesystem::path load_buffer_named(const std::filesystem::path& dir, const std::string& stem) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos)}});
  const auto path = b.write(dir, stem);
  EXPECT_EQ(nlohmann::json::parse(test::read_text(path))["buffers"][0]["uri"], stem + ".bin");
  const Scene s = load_scene(path, kQuiet);
  EXPECT_EQ(s.triangle_count(), 1u);
  EXPECT_EQ(s.source_files.size(), 2u);
  if (s.source_files.size() == 2) {
    EXPECT_EQ(s.source_files[1], (dir / (stem + ".bin")).string());
  }
  return path;
}

// tinygltf 2.7 reads "C++.bin" as "C  .bin": a file whose name holds a '+' was not found.
TEST(GltfLoader, APlusInAUriIsAPlus) {
  const auto dir = test::temp_dir("plus");
  const auto path = load_buffer_named(dir, "C++");
  // "C%2B%2B.bin" names the same file; "C  .bin" would be another, and is not there.
  auto doc = nlohmann::json::parse(test::read_text(path));
  doc["buffers"][0]["uri"] = "C%2B%2B.bin";
  test::write_text(path, doc.dump());
  EXPECT_EQ(load_scene(path, kQuiet).triangle_count(), 1u);
  std::filesystem::copy_file(dir / "C++.bin", dir / "C  .bin");
  std::filesystem::remove(dir / "C++.bin");
  doc["buffers"][0]["uri"] = "C++.bin";
  test::write_text(path, doc.dump());
  expect_error([&] { load_scene(path, kQuiet); }, "C++.bin");
}

// A '%' that starts no escape is itself: "grey_50%.png" was read as "grey_50\0ng" (a bad
// hex digit taken as 0), a file that is never there, whose NUL cut the error message short;
// "t%3x5" read as "t05". An escape of a NUL byte stays as written too.
TEST(GltfLoader, APercentThatStartsNoEscapeIsAPercent) {
  EXPECT_EQ(gltf::external_file("a/s.gltf", "grey_50%.png"), std::filesystem::path("a/grey_50%.png"));
  EXPECT_EQ(gltf::external_file("a/s.gltf", "t%3x5.png"), std::filesystem::path("a/t%3x5.png"));
  EXPECT_EQ(gltf::external_file("a/s.gltf", "a%2.png"), std::filesystem::path("a/a%2.png"));
  EXPECT_EQ(gltf::external_file("a/s.gltf", "n%00.png"), std::filesystem::path("a/n%00.png"));
  EXPECT_EQ(gltf::external_file("a/s.gltf", "%41%2541.png"), std::filesystem::path("a/A%41.png"));
  const auto dir = test::temp_dir("percent");
  const auto path = load_buffer_named(dir, "buf_100%");
  // Missing, it is named whole.
  std::filesystem::remove(dir / "buf_100%.bin");
  expect_error([&] { load_scene(path, kQuiet); }, "buf_100%.bin");
}

// Two URIs tinygltf would read as one name ("a+b" and "a%20b") cannot both be loaded
// through it; the load says so rather than reading one file for both.
TEST(GltfLoader, UrisTinygltfCannotTellApartAreAnError) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos)}});
  const auto dir = test::temp_dir("plusspace");
  const auto path = b.write(dir, "a+b");
  std::filesystem::copy_file(dir / "a+b.bin", dir / "a b.bin");
  auto doc = nlohmann::json::parse(test::read_text(path));
  doc["buffers"].push_back({{"uri", "a%20b.bin"}, {"byteLength", doc["buffers"][0]["byteLength"]}});
  test::write_text(path, doc.dump());
  expect_error([&] { load_scene(path, kQuiet); }, "cannot tell apart");
}

// tinygltf looks for a file the glTF names in the working directory too when it is not next
// to the glTF: the same scene rendered from another folder (or farm worker) was another
// scene. Only the glTF's folder counts.
TEST(GltfLoader, AFileMissingNextToTheGltfIsNotTakenFromTheWorkingDirectory) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos)}});
  const auto dir = test::temp_dir("cwdfallback");
  std::filesystem::create_directories(dir / "scene");
  std::filesystem::create_directories(dir / "cwd");
  const auto path = b.write(dir / "scene", "model");
  std::filesystem::rename(dir / "scene" / "model.bin", dir / "cwd" / "model.bin");
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(dir / "cwd");
  std::string error;
  try {
    load_scene(path, kQuiet);
  } catch (const Error& e) {
    error = e.what();
  }
  std::filesystem::current_path(before);
  EXPECT_NE(error.find("model.bin"), std::string::npos) << error;
}

// KHR_lights_punctual: range > 0 when given. A negative one was taken as no range.
TEST(GltfLoader, ANegativeLightRangeIsAnError) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos)}});
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"name", "far"}, {"range", -3}}}}}}};
  b.node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  expect_error([&] { load_scene(b.write(test::temp_dir("negrange")), kQuiet); }, "light 'far': negative range");
}

// What the loader does not apply changes the image, so it is said, once per feature and
// file: vertex colours, skins, morph weights, and several animations on one clock.
TEST(GltfLoader, UnappliedFeaturesAreWarnedOnce) {
  GltfBuilder b;
  for (int i = 0; i < 2; ++i) {
    const int mesh = b.mesh("coloured" + std::to_string(i), kTriPos);
    b.doc["meshes"][size_t(mesh)]["primitives"][0]["attributes"]["COLOR_0"] = b.floats({1, 0, 0, 1, 0, 0, 1, 0, 0}, 3);
    b.node({{"mesh", mesh}});
  }
  const int morphed = b.mesh("morphed", kTriPos);
  b.doc["meshes"][size_t(morphed)]["primitives"][0]["targets"] = {{{"POSITION", b.floats(kTriPos, 3)}}};
  b.doc["meshes"][size_t(morphed)]["weights"] = {0.5};
  b.node({{"mesh", morphed}});
  b.node({{"mesh", b.mesh("tri", kTriPos)}, {"skin", 0}});
  b.doc["skins"] = {{{"joints", {0}}}};
  const int times = b.floats({0, 1}, 1), moves = b.floats({0, 0, 0, 1, 0, 0}, 3);
  const nlohmann::json clip = {{"samplers", {{{"input", times}, {"output", moves}}}},
                               {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}};
  b.doc["animations"] = {clip, clip};
  testing::internal::CaptureStderr();
  const Scene s = load_scene(b.write(test::temp_dir("unapplied")), LoadOptions{{}, false});
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_EQ(s.triangle_count(), 4u);
  for (const char* said : {"vertex colours (COLOR_0)", "morph targets with non-zero weights", "is skinned",
                           "2 animations play together"}) {
    const size_t at = warned.find(said);
    EXPECT_NE(at, std::string::npos) << said << "\n" << warned;
    EXPECT_EQ(warned.find(said, at + 1), std::string::npos) << "said twice: " << said << "\n" << warned;
  }
}

TEST(GltfLoader, MaterialFactorsOutOfRangeAreClampedWithAWarning) {
  GltfBuilder b;
  b.doc["materials"] = {{{"name", "odd"}, {"pbrMetallicRoughness", {{"metallicFactor", -0.5}, {"roughnessFactor", 0.5}}}}};
  b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm, {}, 4, 0)}});
  testing::internal::CaptureStderr();
  const Scene s = load_scene(b.write(test::temp_dir("matrange")), LoadOptions{{}, false});
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_NE(warned.find("material 'odd': metallic -0.5 outside [0, 1], clamped"), std::string::npos) << warned;
  EXPECT_EQ(s.whitted[0].mirror, whitted_from_gltf(s.materials[0]).mirror);  // rendered as clamped
}

// Extension values beyond float's range are refused as the core factors are (an ior of
// 1e39 rendered as 1.5 without a word), and a negative thickness is named.
TEST(GltfLoader, ExtensionFactorsBeyondFloatAreErrorsAndNegativeThicknessIsNamed) {
  auto file = [](const nlohmann::json& extensions) {
    GltfBuilder b;
    b.doc["materials"] = {{{"name", "glass"}, {"extensions", extensions}}};
    b.node({{"mesh", b.mesh("tri", kTriPos, kTriNrm, {}, 4, 0)}});
    return b.write(test::temp_dir("matext"));
  };
  expect_error([&] { load_scene(file({{"KHR_materials_ior", {{"ior", 1e39}}}}), kQuiet); },
               "material 'glass' has non-finite parameters");
  expect_error([&] { load_scene(file({{"KHR_materials_volume", {{"thicknessFactor", 1e39}}}}), kQuiet); },
               "material 'glass' has non-finite parameters");
  testing::internal::CaptureStderr();
  load_scene(file({{"KHR_materials_volume", {{"thicknessFactor", -1}}}}), LoadOptions{{}, false});
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_NE(warned.find("material 'glass': thickness -1 below 0, thin-walled, as 0"), std::string::npos) << warned;
}

// A light node's direction is its -Z whatever its scale (KHR_lights_punctual): scaled by
// 1e20 it used to overflow to no direction and render black; scaled to nothing it is
// ignored with a warning, as a camera is. A light the extension forbids is an error.
TEST(GltfLoader, LightDirectionsIgnoreScaleAndForbiddenLightsAreErrors) {
  auto file = [](const nlohmann::json& light, double scale) {
    GltfBuilder b;
    b.node({{"mesh", b.mesh("tri", kTriPos)}});
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {light}}}}};
    b.node({{"scale", {scale, scale, scale}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    return b.write(test::temp_dir("lightdir"));
  };
  const nlohmann::json spot = {{"type", "spot"}, {"name", "flat"}, {"spot", {{"outerConeAngle", 0.5}}}};
  for (const nlohmann::json& light : {nlohmann::json{{"type", "directional"}}, spot})
    for (const double scale : {1e20, 1e-23, 1.0}) {
      SCOPED_TRACE(light.dump() + " " + std::to_string(scale));
      const Scene s = load_scene(file(light, scale), kQuiet);
      ASSERT_EQ(s.lights.size(), 1u);
      EXPECT_EQ(s.lights[0].direction, glm::vec3(0, 0, -1));
    }
  testing::internal::CaptureStderr();
  const Scene flat = load_scene(file(spot, 0.0), LoadOptions{{}, false});
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_NE(warned.find("light 'flat' has a degenerate transform"), std::string::npos) << warned;
  ASSERT_EQ(flat.lights.size(), 2u);  // the default pair: the file's one light was ignored
  EXPECT_EQ(flat.lights[0].name, "default headlight");
  EXPECT_EQ(load_scene(file({{"type", "point"}}, 0.0), kQuiet).lights.size(), 1u);  // a point needs no direction

  expect_error([&] { load_scene(file({{"type", "point"}, {"name", "neg"}, {"intensity", -50}}, 1.0), kQuiet); },
               "light 'neg': negative colour or intensity");
  expect_error([&] {
    load_scene(file({{"type", "spot"}, {"name", "shut"}, {"spot", {{"innerConeAngle", 0}, {"outerConeAngle", 0}}}}, 1.0),
               kQuiet);
  }, "light 'shut': spot cone closed");
  // Angles past KHR_lights_punctual's [0, pi/2] are refused, as the rig refuses them
  // (exploratory testing: an outer cone of 3 rad, lighting behind the spot, was taken).
  for (const auto& [inner, outer] : {std::pair(0.1, 3.0), std::pair(-1.0, 0.5)}) {
    SCOPED_TRACE(outer);
    expect_error([&] {
      load_scene(file({{"type", "spot"}, {"name", "wide"}, {"spot", {{"innerConeAngle", inner}, {"outerConeAngle", outer}}}},
                      1.0),
                 kQuiet);
    }, "light 'wide': spot cone angle outside [0, pi/2]");
  }
  EXPECT_NO_THROW(load_scene(file({{"type", "spot"}, {"spot", {{"innerConeAngle", 0}, {"outerConeAngle", 1.5707963267948966}}}}, 1.0),
                             kQuiet));  // 90 degrees itself
  testing::internal::CaptureStderr();
  load_scene(file({{"type", "point"}, {"intensity", 0}}, 1.0), LoadOptions{{}, false});
  const std::string black = testing::internal::GetCapturedStderr();
  EXPECT_NE(black.find("no light with an intensity above 0"), std::string::npos) << black;
}

// A field of view or aspect ratio the spec forbids is not replaced by a made-up one: the
// camera is ignored, with a warning, and the automatic camera frames the scene.
// The view is the inverse of the camera node's transform (glTF 2.0 §3.10.1): a local ray
// (a, b, -1) goes to m (a, b, -1). A mirrored root (a handedness conversion holding camera
// and meshes) came out mirrored, and a scaled one unscaled.
TEST(GltfLoader, ACameraSeesThroughItsNodesMirrorAndScale) {
  const auto camera_under = [](const nlohmann::json& scale, const char* name) {
    GltfBuilder b;
    b.node({{"mesh", b.mesh("tri", kTriPos)}});
    b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}}};
    const int cam = b.node({{"camera", 0}, {"translation", {0.5, -0.25, 3}}, {"rotation", {0.1, 0.2, 0, 0.9747}}}, false);
    b.node({{"scale", scale}, {"children", {cam}}});
    return load_scene(b.write(test::temp_dir(name)), kQuiet).cameras.at(0);
  };
  const Camera plain = camera_under({1, 1, 1}, "camplain");
  const CameraRays plain_rays(plain, 8, 4);
  for (const auto& [scale, name] : {std::pair{glm::vec3(1, 1, -1), "cammirz"}, std::pair{glm::vec3(-1, 1, 1), "cammirx"},
                                    std::pair{glm::vec3(2, 1, 1), "camwide"}, std::pair{glm::vec3(3, 3, 3), "camuniform"}}) {
    const Camera c = camera_under({scale.x, scale.y, scale.z}, name);
    const CameraRays rays(c, 8, 4);
    expect_vec(c.position, scale * plain.position);
    // znear is a depth in the node's frame: a world point at node depth z is at clip depth
    // znear * z / 0.1, whatever the node's mirror, scale or shear (its plane is the node's
    // z = -z plane, not one normal to the view).
    const glm::mat4 node = glm::scale(glm::mat4(1.0f), scale) * glm::translate(glm::mat4(1.0f), {0.5f, -0.25f, 3.0f}) *
                           glm::mat4_cast(glm::quat(0.9747f, 0.1f, 0.2f, 0.0f));
    for (const glm::vec3 local : {glm::vec3(0, 0, -1), glm::vec3(0.8f, -0.5f, -1), glm::vec3(-0.6f, 0.7f, -2.5f)}) {
      const glm::vec3 world = glm::vec3(node * glm::vec4(local, 1.0f));
      EXPECT_NEAR(rays.clip.depth(world) / c.znear, -local.z / 0.1f, 1e-3f * -local.z / 0.1f)
          << name << " local point " << local.x << "," << local.y << "," << local.z;
    }
    EXPECT_EQ(c.zfar, std::numeric_limits<float>::infinity()) << name << ": no zfar is an infinite projection";
    for (const glm::vec2 p : {glm::vec2(0.5f, 0.5f), glm::vec2(7.5f, 0.5f), glm::vec2(2.0f, 3.5f), glm::vec2(4, 2)}) {
      const glm::vec3 expected = glm::normalize(scale * plain_rays.direction(p.x, p.y));
      const glm::vec3 got = rays.direction(p.x, p.y);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], expected[k], 1e-5f) << name << " pixel " << p.x << "," << p.y;
    }
  }
}

// glTF orthographic cameras: half extents xmag, ymag (their ratio the intended frame's
// shape) and planes in the node's units, so a node scaled by 2 shows twice as much.
TEST(GltfLoader, OrthographicCamerasKeepTheirExtentsAndPlanes) {
  for (const float scale : {1.0f, 2.0f}) {
    GltfBuilder b;
    b.node({{"mesh", b.mesh("tri", kTriPos)}});
    b.doc["cameras"] = {{{"type", "orthographic"}, {"name", "plan"},
                         {"orthographic", {{"xmag", 3.0}, {"ymag", 1.5}, {"znear", 0.25}, {"zfar", 40}}}}};
    const float h = std::sqrt(0.5f);
    b.node({{"camera", 0}, {"translation", {4, 0, 0}}, {"rotation", {0, h, 0, h}}, {"scale", {scale, scale, scale}}});
    const Scene s = load_scene(b.write(test::temp_dir("ortho")), kQuiet);
    ASSERT_EQ(s.cameras.size(), 1u);
    const Camera& c = s.cameras[0];
    EXPECT_EQ(c.name, "plan");
    ASSERT_TRUE(c.orthographic());
    expect_vec(c.position, {4, 0, 0});
    expect_vec(c.forward, {-1, 0, 0});
    expect_vec(c.right, {0, 0, -1});
    EXPECT_FLOAT_EQ(c.ymag, 1.5f * scale);
    EXPECT_FLOAT_EQ(c.aspect, 2.0f);
    EXPECT_FLOAT_EQ(c.znear, 0.25f * scale);
    EXPECT_FLOAT_EQ(c.zfar, 40.0f * scale);
  }
}

// A field of view or orthographic extents the renderer cannot use leave the camera out,
// with a warning; the automatic camera (a perspective one) takes its place.
TEST(GltfLoader, ACameraWithAnImpossibleViewIsIgnored) {
  const std::vector<std::pair<const char*, nlohmann::json>> cameras = {
      {"perspective", {{"yfov", 0.0}, {"znear", 0.1}}},
      {"perspective", {{"yfov", 3.5}, {"znear", 0.1}}},
      {"perspective", {{"yfov", 0.5}, {"znear", 0.1}, {"aspectRatio", -1.5}}},
      {"orthographic", {{"xmag", 1.0}, {"ymag", 0.0}, {"znear", 0.0}, {"zfar", 10}}},
      {"orthographic", {{"xmag", 1.0}, {"ymag", -1.0}, {"znear", 0.0}, {"zfar", 10}}},
      {"orthographic", {{"xmag", 0.0}, {"ymag", 1.0}, {"znear", 0.0}, {"zfar", 10}}},
      {"orthographic", {{"xmag", 1.0}, {"ymag", 1e300}, {"znear", 0.0}, {"zfar", 10}}}};
  for (const auto& [type, view] : cameras) {
    SCOPED_TRACE(view.dump());
    GltfBuilder b;
    b.node({{"mesh", b.mesh("tri", kTriPos)}});
    b.doc["cameras"] = {{{"type", type}, {"name", "bad"}, {type, view}}};
    b.node({{"camera", 0}, {"translation", {0, 0, 5}}});
    const Scene s = load_scene(b.write(test::temp_dir("badcam")), kQuiet);
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_NE(s.cameras[0].name, "bad");
    EXPECT_FALSE(s.cameras[0].orthographic());
  }
}

// A clipping plane against the rules is left out with a warning, the camera kept (its
// index too): a negative znear without a zfar rendered black (the absent zfar became a far
// plane at 0), and a zfar <= znear was dropped without a word.
TEST(GltfLoader, AClippingPlaneAgainstTheRulesIsLeftOut) {
  struct Case {
    const char* type;
    nlohmann::json view;
    float znear, zfar;  // what the camera keeps
    const char* said;
  };
  constexpr float kNone = std::numeric_limits<float>::infinity();  // no far plane
  const std::vector<Case> cases = {
      {"perspective", {{"yfov", 0.5}, {"znear", -0.001}}, 0.0f, kNone, "has znear -0.001 (not >= 0): no near plane"},
      {"perspective", {{"yfov", 0.5}, {"znear", -1e-9}, {"zfar", 100}}, 0.0f, 100.0f, "has znear -1e-09 (not >= 0)"},
      {"perspective", {{"yfov", 0.5}, {"znear", 2.0}, {"zfar", 1.0}}, 2.0f, kNone,
       "has zfar 1 (not greater than znear 2): no far plane"},
      {"orthographic", {{"xmag", 1.0}, {"ymag", 1.0}, {"znear", -1.0}, {"zfar", 10}}, 0.0f, 10.0f, "has znear -1"},
      {"orthographic", {{"xmag", 1.0}, {"ymag", 1.0}, {"znear", 5.0}, {"zfar", 5.0}}, 5.0f, kNone, "has zfar 5"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.view.dump());
    GltfBuilder b;
    b.node({{"mesh", b.mesh("tri", kTriPos)}});
    b.doc["cameras"] = {{{"type", c.type}, {"name", "odd"}, {c.type, c.view}},
                        {{"type", "perspective"}, {"name", "next"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    b.node({{"camera", 0}, {"translation", {0, 0, 5}}});
    b.node({{"camera", 1}, {"translation", {0, 0, 6}}});
    testing::internal::CaptureStderr();
    const Scene s = load_scene(b.write(test::temp_dir("planes")), LoadOptions{{}, false});
    const std::string warned = testing::internal::GetCapturedStderr();
    EXPECT_NE(warned.find(std::string("camera 'odd' ") + c.said), std::string::npos) << warned;
    ASSERT_EQ(s.cameras.size(), 2u);
    EXPECT_EQ(s.cameras[0].name, "odd");
    EXPECT_EQ(s.cameras[1].name, "next");
    EXPECT_FLOAT_EQ(s.cameras[0].znear, c.znear);
    EXPECT_FLOAT_EQ(s.cameras[0].zfar, c.zfar);
  }
}

TEST(GltfLoader, AutoCameraFramesTheBoundsWhenTheFileHasNone) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos)}, {"translation", {100, 0, 0}}});
  Scene s = load_scene(b.write(test::temp_dir("auto")), kQuiet);
  ASSERT_EQ(s.cameras.size(), 1u);
  const Camera& c = s.cameras[0];
  const glm::vec3 centre(100.5f, 0.5f, 0.0f);
  // Looks at the centre of the bounds from outside the bounding sphere.
  expect_vec(glm::normalize(centre - c.position), c.forward, 1e-4f);
  EXPECT_GT(glm::length(centre - c.position), std::sqrt(0.5f));
  EXPECT_EQ(s.background, glm::vec3(0.0f));
  EXPECT_EQ(s.max_depth, 2);
  EXPECT_EQ(s.exposure, 1.0f);
  // No lights in the file: the documented default pair, headlight along the view.
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.lights[0].type, Light::Type::Directional);
  expect_vec(s.lights[0].direction, c.forward, 1e-6f);
}

// A small model fills the frame as a large one does: the camera stood at least 1e-6 from a
// centre-fitting distance, so a model 1e-7 across covered a seventh of the frame
// (exploratory testing: nearly black renders).
TEST(GltfLoader, AutoCameraFramesSmallModelsAsLargeOnes) {
  float unit_distance = 0.0f;
  for (const double scale : {1.0, 1e-4, 1e-7, 1e-9}) {
    SCOPED_TRACE(scale);
    GltfBuilder b;
    b.node({{"mesh", b.mesh("tri", kTriPos)}, {"scale", {scale, scale, scale}}});
    const Scene s = load_scene(b.write(test::temp_dir("auto_small")), kQuiet);
    ASSERT_EQ(s.cameras.size(), 1u);
    const glm::vec3 centre = 0.5f * glm::vec3(float(scale), float(scale), 0.0f);
    const float distance = glm::length(s.cameras[0].position - centre) / float(scale);
    if (scale == 1.0) unit_distance = distance;
    EXPECT_NEAR(distance, unit_distance, 1e-3f * unit_distance);
  }
}

TEST(GltfLoader, MaterialsAndExtensions) {
  GltfBuilder b;
  b.doc["materials"] = {
      {{"name", "glass"}, {"doubleSided", true},
       {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.6, 0.7, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0.1}}},
       {"emissiveFactor", {1, 0.5, 0}},
       {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 0.9}}},
                       {"KHR_materials_ior", {{"ior", 1.33}}},
                       {"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}},
                       {"KHR_materials_volume", {{"attenuationColor", {0.5, 0.25, 1}}, {"attenuationDistance", 2}}}}}},
      {{"name", "plain"}}};
  b.node({{"mesh", b.mesh("a", kTriPos, {}, {}, 4, 0)}});
  b.node({{"mesh", b.mesh("b", kTriPos, {}, {}, 4, 1)}, {"translation", {0, 0, 1}}});
  b.node({{"mesh", b.mesh("c", kTriPos)}, {"translation", {0, 0, 2}}});  // no material
  Scene s = load_scene(b.write(test::temp_dir("mat")), kQuiet);
  ASSERT_EQ(s.materials.size(), 3u);  // two + the default
  ASSERT_EQ(s.whitted.size(), 3u);
  const Material& g = s.materials[0];
  EXPECT_EQ(g.name, "glass");
  expect_vec(g.base_color, {0.5f, 0.6f, 0.7f});
  EXPECT_FLOAT_EQ(g.roughness, 0.1f);
  EXPECT_FLOAT_EQ(g.transmission, 0.9f);
  EXPECT_FLOAT_EQ(g.ior, 1.33f);
  expect_vec(g.emissive, {4, 2, 0});
  expect_vec(g.attenuation_color, {0.5f, 0.25f, 1.0f});
  EXPECT_FLOAT_EQ(g.attenuation_distance, 2.0f);
  EXPECT_TRUE(g.double_sided);
  // glTF defaults for an empty material: base 1, metallic 1, roughness 1.
  const Material& p = s.materials[1];
  expect_vec(p.base_color, {1, 1, 1});
  EXPECT_FLOAT_EQ(p.metallic, 1.0f);
  EXPECT_FALSE(p.double_sided);
  EXPECT_EQ(s.material_of, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(s.materials[2].name, "default");
}

TEST(GltfLoader, UvsAreCarriedPerVertex) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", kTriPos, {}, {}, 4, -1, {0.25f, 0.5f, 1, 0, 0, 1})}});
  Scene s = load_scene(b.write(test::temp_dir("uv")), kQuiet);
  ASSERT_EQ(s.uvs.size(), 3u);
  EXPECT_EQ(s.uvs[0], glm::vec2(0.25f, 0.5f));
  EXPECT_EQ(s.uvs[2], glm::vec2(0.0f, 1.0f));
}

TEST(GltfLoader, UnknownFileFormatIsAnError) {
  auto dir = test::temp_dir("ext");
  expect_error([&] { load_scene(dir / "model.obj", kQuiet); }, "model.obj");
}

// ---- the project's own scenes and the shared third-party ones -----------------------

struct SceneCase {
  const char* file;
  size_t triangles, lights, cameras;
  int depth;
};

TEST(ProjectScenes, LoadWithExpectedCounts) {
  const SceneCase cases[] = {{"room.json", 10196, 9, 1, 2}, {"glass.json", 12700, 3, 1, 2}, {"default.json", 1724, 2, 1, 2}};
  for (const SceneCase& c : cases) {
    Scene s = load_scene(std::filesystem::path(ZZ_SOURCE_DIR) / "scenes" / c.file, kQuiet);
    EXPECT_EQ(s.triangle_count(), c.triangles) << c.file;
    EXPECT_EQ(s.lights.size(), c.lights) << c.file;
    EXPECT_EQ(s.cameras.size(), c.cameras) << c.file;
    EXPECT_EQ(s.max_depth, c.depth) << c.file;
    EXPECT_EQ(s.dropped_degenerate, 0u) << c.file;
    EXPECT_EQ(s.positions.size(), 3 * s.triangle_count());
    EXPECT_EQ(s.normals.size(), 3 * s.triangle_count());
    EXPECT_EQ(s.uvs.size(), 3 * s.triangle_count());
    for (const glm::vec3& n : s.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f) << c.file;
  }
}

TEST(SharedScenes, LoadWhenPresent) {
  const auto root = test::shared_scenes();
  if (!std::filesystem::exists(root / "toycar"))
    GTEST_SKIP() << "shared third-party scenes not found at " << root << " (optional)";
  LoadOptions opt = kQuiet;
  opt.assets_dir = root;
  const SceneCase cases[] = {{"car.json", 108936, 2, 8, 3}, {"vase.json", 14036, 3, 1, 3}, {"lamp.json", 6000, 5, 1, 2}};
  for (const SceneCase& c : cases) {
    Scene s = load_scene(std::filesystem::path(ZZ_SOURCE_DIR) / "scenes" / c.file, opt);
    EXPECT_EQ(s.triangle_count(), c.triangles) << c.file;
    EXPECT_EQ(s.lights.size(), c.lights) << c.file;
    EXPECT_EQ(s.cameras.size(), c.cameras) << c.file;
    EXPECT_EQ(s.max_depth, c.depth) << c.file;
    EXPECT_FALSE(s.textures.empty()) << c.file;
  }
  // The raw glTF files load directly too (ToyCar's 8 cameras, the lamp's 5 lights).
  Scene car = load_scene(root / "toycar/glTF/ToyCar.gltf", kQuiet);
  EXPECT_EQ(car.cameras.size(), 8u);
  EXPECT_EQ(car.cameras[0].name, "Camera001");
  EXPECT_EQ(car.lights.size(), 2u);  // none in the file: the default headlight and key light
  Scene lamp = load_scene(root / "lightspunctuallamp/glTF/LightsPunctualLamp.gltf", kQuiet);
  EXPECT_EQ(lamp.lights.size(), 5u);
  EXPECT_EQ(lamp.cameras.size(), 1u);  // auto camera
  EXPECT_EQ(lamp.cameras[0].name, "auto");
}

}  // namespace
}  // namespace zz
