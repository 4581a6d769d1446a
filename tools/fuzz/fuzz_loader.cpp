#include "fuzz_loader.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <system_error>

#include "accel/bvh.h"
#include "core/error.h"
#include "render/scene_source.h"
#include "render/shader.h"
#include "scene/loader.h"

#ifndef ZZ_SOURCE_DIR
#error "ZZ_SOURCE_DIR must point at the repository (scenes/ and tools/fuzz/ are read from it)"
#endif

namespace zz::fuzz {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void bug(const std::string& what) {
  std::fprintf(stderr, "fuzz_loader: BUG: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

bool finite3(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// What load_scene promises about a scene it returns (scene/scene.h, scene/loader.h).
void check_invariants(const Scene& s) {
  const size_t n = s.triangle_count();
  if (s.positions.size() != 3 * n || s.normals.size() != 3 * n || s.uvs.size() != 3 * n)
    bug("per-vertex arrays do not hold 3 entries per triangle");
  if ((!s.uvs1.empty() && s.uvs1.size() != 3 * n) || (!s.tangents.empty() && s.tangents.size() != 3 * n))
    bug("optional per-vertex arrays (TEXCOORD_1, tangents) do not hold 3 entries per triangle");
  if (s.whitted.size() != s.materials.size()) bug("whitted materials not finalized");
  for (uint32_t m : s.material_of)
    if (m >= s.materials.size()) bug("material index out of range");
  for (const glm::vec3& p : s.positions)
    if (!finite3(p)) bug("non-finite position");
  for (const glm::vec3& nv : s.normals)
    if (!finite3(nv)) bug("non-finite normal");
  for (const Material& m : s.materials) {
    for (const TextureRef* r : {&m.base_color_texture, &m.metallic_roughness_texture, &m.emissive_texture,
                                &m.normal_texture, &m.transmission_texture})
      if (r->index >= int(s.textures.size()) || r->texcoord < 0 || r->texcoord > 1) bug("texture slot out of range");
  }
  for (const Texture& t : s.textures)
    if (t.width <= 0 || t.height <= 0 || t.texel_count() != size_t(t.width) * size_t(t.height))
      bug("texture size does not match its texels");
  if (s.cameras.empty()) bug("no camera");
  for (const Camera& c : s.cameras)
    if (!finite3(c.position) || !finite3(c.forward) || !finite3(c.right) || !finite3(c.up) || !std::isfinite(c.yfov))
      bug("non-finite camera");
  for (const Light& l : s.lights)
    if (!finite3(l.position) || !finite3(l.intensity)) bug("non-finite light");
  if (s.max_depth < 0 || s.default_width < 1 || s.default_height < 1) bug("bad render settings");
}

// A 4x4 grid of camera packets through the scene: radiance must be finite and >= 0.
void trace_a_little(const Scene& s) {
  const Bvh bvh = Bvh::build(s.positions);
  const Shader shader(s, bvh);
  const CameraRays rays(s.cameras[0], 8, 8);
  SceneSource source(shader, rays);
  for (int y = 0; y < 8; y += 2)
    for (int x = 0; x < 8; x += 2) {
      const Rgb4 c = source.sample4(float4(x + 0.5f, x + 1.5f, x + 0.5f, x + 1.5f),
                                    float4(y + 0.5f, y + 0.5f, y + 1.5f, y + 1.5f));
      for (int i = 0; i < 4; ++i)
        for (float v : {c.r[i], c.g[i], c.b[i]})
          if (!std::isfinite(v) || v < 0.0f) bug("radiance " + std::to_string(v));
    }
}

void link_into(const fs::path& dir, const fs::path& target) {
  std::error_code ec;
  fs::create_symlink(target, dir / target.filename(), ec);
}

struct WorkDir {
  fs::path path;
  WorkDir() {
    path = fs::temp_directory_path() / ("zz_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(path);
    // Models and buffers the seeds reference: the repository's small scenes and the
    // tiny models written by make_corpus.py.
    const fs::path src(ZZ_SOURCE_DIR);
    for (const auto& e : fs::directory_iterator(src / "scenes"))
      if (e.path().extension() == ".gltf" || e.path().extension() == ".bin") link_into(path, e.path());
    link_into(path, src / "tools" / "fuzz" / "tiny.gltf");
    link_into(path, src / "tools" / "fuzz" / "tiny.glb");
  }
  ~WorkDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

const fs::path& work_dir() {
  static WorkDir dir;
  return dir.path;
}

int load_input(const uint8_t* data, size_t size, const std::string& ext) {
  const fs::path file = work_dir() / ("input." + ext);
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    if (!out) bug("cannot write " + file.string());
  }
  LoadOptions options;
  options.quiet = true;
  options.assets_dir = work_dir() / "no_assets";  // "assets:" references fail fast
  Scene scene;
  try {
    scene = load_scene(file, options);
  } catch (const Error&) {
    return 0;  // rejected with a message: the contract
  }
  // Any other exception propagates: std::terminate -> libFuzzer reports a crash.
  check_invariants(scene);
  // ZZ_FUZZ_NO_TRACE=1: the loader alone (when the renderer is being changed under you).
  static const bool trace = [] {
    const char* e = std::getenv("ZZ_FUZZ_NO_TRACE");
    return !(e && *e == '1');
  }();
  if (trace) trace_a_little(scene);
  return 0;
}

}  // namespace zz::fuzz
