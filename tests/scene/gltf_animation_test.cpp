// glTF animations through the loader: animated nodes posed at LoadOptions::time,
// composed with their parents; cameras and lights move with their nodes; the rig's
// fps/frames clock; malformed samplers are errors.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "gltf_fixture.h"
#include "scene/loader.h"

namespace zz {
namespace {

using test::GltfBuilder;

// A SCALAR (times) or VECn (values) float accessor.
int accessor(GltfBuilder& b, const std::vector<float>& v, int components) {
  const int bv = b.view(v.data(), v.size() * sizeof(float));
  static const char* kType[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
  nlohmann::json acc = {{"bufferView", bv}, {"componentType", 5126}, {"count", v.size() / size_t(components)},
                        {"type", kType[components]}};
  if (components == 1) {
    acc["min"] = {*std::min_element(v.begin(), v.end())};
    acc["max"] = {*std::max_element(v.begin(), v.end())};
  }
  b.doc["accessors"].push_back(acc);
  return int(b.doc["accessors"].size() - 1);
}

void animate(GltfBuilder& b, int node, const std::string& path, const std::string& interpolation,
             const std::vector<float>& times, const std::vector<float>& values) {
  if (!b.doc.contains("animations")) b.doc["animations"] = {{{"channels", nlohmann::json::array()}, {"samplers", nlohmann::json::array()}}};
  auto& a = b.doc["animations"][0];
  const int components = path == "rotation" ? 4 : 3;
  a["samplers"].push_back({{"input", accessor(b, times, 1)}, {"output", accessor(b, values, components)},
                           {"interpolation", interpolation}});
  a["channels"].push_back({{"sampler", a["samplers"].size() - 1}, {"target", {{"node", node}, {"path", path}}}});
}

Scene load_at(const std::filesystem::path& p, double t) {
  LoadOptions o;
  o.quiet = true;
  o.time = t;
  return load_scene(p, o);
}

void expect_vec3(glm::vec3 got, glm::vec3 want, float tol = 1e-5f) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

const float kH = std::sqrt(0.5f);  // quaternion component of a 90° rotation

TEST(GltfAnimation, AnimatedParentComposesWithChild) {
  GltfBuilder b;
  const int child = b.node({{"mesh", b.mesh("tri", test::kTriPos)}, {"translation", {1, 0, 0}}}, false);
  // Parent: 90° about z (static), translation animated (0,0,0) -> (2,0,0) over 1 s.
  const int parent = b.node({{"children", {child}}, {"rotation", {0, 0, kH, kH}}});
  animate(b, parent, "translation", "LINEAR", {0, 1}, {0, 0, 0, 2, 0, 0});
  const auto path = b.write(test::temp_dir("m"));
  const Scene s = load_at(path, 0.5);
  ASSERT_EQ(s.triangle_count(), 1u);
  EXPECT_TRUE(s.animated);
  EXPECT_EQ(s.animation_end, 1.0f);
  // world = T(1,0,0) * Rz(90) * T(1,0,0): vertex (0,0,0) -> (1,1,0), (1,0,0) -> (1,2,0).
  expect_vec3(s.positions[0], {1, 1, 0});
  expect_vec3(s.positions[1], {1, 2, 0});
  expect_vec3(s.positions[2], {0, 1, 0});
  expect_vec3(load_at(path, 5.0).positions[0], {2, 1, 0});  // clamped after the last key
}

TEST(GltfAnimation, CameraAndLightFollowTheirNodes) {
  GltfBuilder b;
  b.doc["cameras"] = {{{"type", "perspective"}, {"name", "cam"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 1.0}}}}}}};
  b.node({{"mesh", b.mesh("tri", test::kTriPos)}});
  const int cam = b.node({{"camera", 0}}, false);
  animate(b, cam, "translation", "STEP", {0, 1}, {0, 0, 5, 0, 0, 10});
  // The camera's parent turns 0 -> 90° about y over 2 s (slerp).
  const int pivot = b.node({{"children", {cam}}});
  animate(b, pivot, "rotation", "LINEAR", {0, 2}, {0, 0, 0, 1, 0, kH, 0, kH});
  const int light = b.node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  animate(b, light, "translation", "LINEAR", {0, 2}, {0, 4, 0, 8, 4, 0});
  const auto path = b.write(test::temp_dir("m"));

  const Scene s0 = load_at(path, 0.0);
  ASSERT_EQ(s0.cameras.size(), 1u);
  expect_vec3(s0.cameras[0].position, {0, 0, 5});
  expect_vec3(s0.cameras[0].forward, {0, 0, -1});
  // t = 2: step holds (0,0,10); the pivot's 90° about y maps it to (10,0,0), -z to -x.
  const Scene s2 = load_at(path, 2.0);
  expect_vec3(s2.cameras[0].position, {10, 0, 0});
  expect_vec3(s2.cameras[0].forward, {-1, 0, 0});
  // t = 1: step switched to 10, the pivot is at 45°.
  const Scene s1 = load_at(path, 1.0);
  expect_vec3(s1.cameras[0].position, {10 * kH, 0, 10 * kH});
  ASSERT_EQ(s1.lights.size(), 1u);
  expect_vec3(s1.lights[0].position, {4, 4, 0});
}

TEST(GltfAnimation, RigClockAndFrameRange) {
  GltfBuilder b;
  const int n = b.node({{"mesh", b.mesh("tri", test::kTriPos)}});
  animate(b, n, "translation", "LINEAR", {0, 1.5f}, {0, 0, 0, 3, 0, 0});
  const auto dir = test::temp_dir("rig");
  b.write(dir);
  test::write_text(dir / "plain.json", R"({"model": "model.gltf"})");
  test::write_text(dir / "rig.json", R"({"model": "model.gltf", "fps": 10, "frames": [2, 9]})");
  LoadOptions o;
  o.quiet = true;
  Scene plain = load_scene(dir / "plain.json", o);
  EXPECT_EQ(plain.fps, 24.0);
  EXPECT_EQ(plain.first_frame, 0);
  EXPECT_EQ(plain.last_frame, 36);  // ceil(1.5 s * 24)
  EXPECT_EQ(plain.frame, 0);
  Scene rig = load_scene(dir / "rig.json", o);  // default frame: the range's first
  EXPECT_EQ(rig.fps, 10.0);
  EXPECT_EQ(rig.first_frame, 2);
  EXPECT_EQ(rig.last_frame, 9);
  EXPECT_EQ(rig.frame, 2);
  expect_vec3(rig.positions[0], {0.4f, 0, 0});  // t = 2 / 10 s
  o.frame = 5;
  o.fps = 5.0;  // overrides the rig: t = 1 s
  rig = load_scene(dir / "rig.json", o);
  EXPECT_DOUBLE_EQ(rig.time, 1.0);
  expect_vec3(rig.positions[0], {2, 0, 0});
  o.time = 0.25;  // a time wins over the frame
  rig = load_scene(dir / "rig.json", o);
  EXPECT_EQ(rig.frame, -1);
  expect_vec3(rig.positions[0], {0.5f, 0, 0});
  // A static model: one frame.
  GltfBuilder still;
  still.node({{"mesh", still.mesh("tri", test::kTriPos)}});
  const Scene s = load_scene(still.write(test::temp_dir("still")), LoadOptions{});
  EXPECT_FALSE(s.animated);
  EXPECT_EQ(s.last_frame, 0);
}

TEST(GltfAnimation, BadRigClockKeysAreErrors) {
  GltfBuilder b;
  b.node({{"mesh", b.mesh("tri", test::kTriPos)}});
  const auto dir = test::temp_dir("bad");
  b.write(dir);
  for (const char* rig : {R"({"model": "model.gltf", "fps": 0})", R"({"model": "model.gltf", "fps": "24"})",
                          R"({"model": "model.gltf", "frames": [5, 2]})", R"({"model": "model.gltf", "frames": [1]})",
                          R"({"model": "model.gltf", "frames": [-1, 3]})", R"({"model": "model.gltf", "frames": [0.5, 3]})"}) {
    test::write_text(dir / "rig.json", rig);
    EXPECT_THROW(load_scene(dir / "rig.json", LoadOptions{}), Error) << rig;
  }
}

TEST(GltfAnimation, MalformedSamplersAreErrors) {
  struct Case {
    std::vector<float> times, values;
    const char* interpolation;
    const char* message;
  };
  const std::vector<Case> cases = {
      {{0, 1}, {0, 0, 0}, "LINEAR", "output values"},
      {{0, 1}, {0, 0, 0, 1, 1, 1}, "CUBICSPLINE", "output values"},
      {{1, 0}, {0, 0, 0, 1, 1, 1}, "LINEAR", "increasing"},
      {{0, NAN}, {0, 0, 0, 1, 1, 1}, "LINEAR", "finite"},
      {{0, 1}, {0, 0, 0, 1, 1, 1}, "QUADRATIC", "interpolation"},
  };
  for (const Case& c : cases) {
    GltfBuilder b;
    const int n = b.node({{"mesh", b.mesh("tri", test::kTriPos)}});
    animate(b, n, "translation", c.interpolation, c.times, c.values);
    const auto path = b.write(test::temp_dir("m"));
    try {
      load_scene(path, LoadOptions{});
      ADD_FAILURE() << c.message;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
  }
}

// glTF 2.0, animation.sampler.input (§5.8): key times are seconds with time[0] >= 0; a
// sampler whose output holds NaN or Inf is refused too, even where the loaded time does not
// sample that key (it would at another --frame).
TEST(GltfAnimation, NegativeKeyTimesAndNonFiniteOutputsAreErrors) {
  struct Case {
    std::vector<float> times, values;
    const char* message;
  };
  const std::vector<Case> cases = {
      {{-1, 1}, {0, 0, 0, 1, 1, 1}, "non-negative"},
      {{0, 1}, {0, 0, 0, 1, NAN, 1}, "NaN/Inf"},
      {{0, 1}, {0, 0, 0, INFINITY, 1, 1}, "NaN/Inf"},
  };
  for (const Case& c : cases) {
    GltfBuilder b;
    const int n = b.node({{"mesh", b.mesh("tri", test::kTriPos)}});
    animate(b, n, "translation", "LINEAR", c.times, c.values);
    const auto path = b.write(test::temp_dir("m"));
    try {
      load_at(path, 0.0);
      ADD_FAILURE() << c.message << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
  }
}

// A channel must target one of the file's nodes (glTF 2.0, animation.channel.target.node,
// §5.7): one past the last is an error, not an animation of nothing.
TEST(GltfAnimation, AChannelTargetingANodePastTheLastIsAnError) {
  GltfBuilder b;
  const int n = b.node({{"mesh", b.mesh("tri", test::kTriPos)}});
  animate(b, n, "translation", "LINEAR", {0, 1}, {0, 0, 0, 1, 0, 0});
  b.doc["animations"][0]["channels"][0]["target"]["node"] = b.doc["nodes"].size();
  const auto path = b.write(test::temp_dir("m"));
  try {
    load_at(path, 0.0);
    ADD_FAILURE() << "a channel of node " << b.doc["nodes"].size() << " accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
}

// An animated node keeps its static properties as a static node has them: a rotation that
// is not unit length (glTF 2.0 node.rotation is a unit quaternion; files do not always comply)
// is normalised, not applied as a rotation with a scale of |q|^2.
TEST(GltfAnimation, AnAnimatedNodesRestRotationIsNormalisedAsAStaticNodes) {
  GltfBuilder b;
  // 90 degrees about z, stored at twice unit length; its translation is animated.
  const int n = b.node({{"mesh", b.mesh("tri", test::kTriPos)}, {"rotation", {0, 0, 2 * kH, 2 * kH}}});
  animate(b, n, "translation", "LINEAR", {0, 1}, {0, 0, 0, 2, 0, 0});
  const Scene s = load_at(b.write(test::temp_dir("m")), 0.5);
  ASSERT_EQ(s.triangle_count(), 1u);
  // T(1,0,0) * Rz(90): (0,0,0) -> (1,0,0), (1,0,0) -> (1,1,0), (0,1,0) -> (0,0,0).
  expect_vec3(s.positions[0], {1, 0, 0});
  expect_vec3(s.positions[1], {1, 1, 0});
  expect_vec3(s.positions[2], {0, 0, 0});
}

// A channel of a path the loader does not animate (glTF 2.0 animation.channel.target.path
// "weights": morph targets) is skipped with a warning; the file loads and its other
// channels play (an exporter's morph animation must not refuse the whole model).
TEST(GltfAnimation, AMorphWeightsChannelIsSkippedAndTheRestPlays) {
  GltfBuilder b;
  const int n = b.node({{"mesh", b.mesh("tri", test::kTriPos)}});
  animate(b, n, "translation", "LINEAR", {0, 1}, {0, 0, 0, 2, 0, 0});
  auto& a = b.doc["animations"][0];
  // One morph target: a SCALAR weight per key.
  a["samplers"].push_back({{"input", accessor(b, {0, 1}, 1)}, {"output", accessor(b, {0, 1}, 1)}});
  a["channels"].push_back({{"sampler", a["samplers"].size() - 1}, {"target", {{"node", n}, {"path", "weights"}}}});
  const Scene s = load_at(b.write(test::temp_dir("m")), 0.5);
  ASSERT_EQ(s.triangle_count(), 1u);
  expect_vec3(s.positions[0], {1, 0, 0});
  expect_vec3(s.positions[1], {2, 0, 0});
}

}  // namespace
}  // namespace zz
