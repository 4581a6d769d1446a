// Measures what the flag thresholds see on real scenes, to choose their defaults:
//  1. a histogram of the angle between camera-facing geometric normals over all pairs of
//     adjacent supersamples on different triangles (smooth tessellation vs real creases);
//  2. the flagged-pixel share (geo_fraction) as each threshold varies.
// Usage: survey_thresholds [--size N] [--dump DIR] [scene files...]
//   --dump writes DIR/<scene>.pgm, the flag map with the default thresholds.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "gpu/device.h"
#include "gpu/visibility.h"

using namespace zz;

namespace {

double geo_fraction(const GeoMap& m) {
  size_t n = 0;
  for (uint8_t f : m.flags) n += f != 0;
  return double(n) / double(m.flags.size());
}

void angle_histogram(VisibilityPass& pass, const Scene& scene, const Camera& cam, int w, int h) {
  VisibilitySettings s;
  std::vector<uint32_t> ids = pass.render_ids(cam, w, h, s);
  std::vector<glm::vec4> normals = geometric_normals(scene);
  gpu::FlagPush p = make_flag_push(cam, w, h, s);
  int sw = w * 4 + 2, sh = h * 4 + 2;
  const double edges[] = {0.5, 1, 2, 3, 5, 7.5, 10, 15, 20, 25, 30, 40, 60, 90, 181};
  size_t counts[15] = {};
  size_t total = 0;
  auto dir = [&](int gx, int gy) { return glm::vec3(p.dir00) + float(gx) * glm::vec3(p.du) + float(gy) * glm::vec3(p.dv); };
  auto pair = [&](int u0, int v0, int u1, int v1) {
    uint32_t a = ids[size_t(v0) * sw + u0], b = ids[size_t(v1) * sw + u1];
    if (a == b || a == 0 || b == 0) return;
    glm::vec3 na(normals[a - 1]), nb(normals[b - 1]);
    float sa = glm::dot(na, dir(u0 - 1, v0 - 1)), sb = glm::dot(nb, dir(u1 - 1, v1 - 1));
    double c = glm::dot(na, nb) * ((sa < 0) != (sb < 0) ? -1.0 : 1.0);
    double deg = std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
    int k = 0;
    while (deg >= edges[k]) ++k;
    ++counts[k];
    ++total;
  };
  for (int v = 0; v < sh; ++v)
    for (int u = 0; u < sw; ++u) {
      if (u + 1 < sw) pair(u, v, u + 1, v);
      if (v + 1 < sh) pair(u, v, u, v + 1);
    }
  std::printf("  triangle-change pairs: %zu; cumulative share with normal angle below:\n   ", total);
  size_t acc = 0;
  for (int k = 0; k < 14; ++k) {
    acc += counts[k];
    std::printf(" <%g:%.1f%%", edges[k], total ? 100.0 * acc / total : 0.0);
  }
  std::printf("\n");
}

void write_pgm(const std::string& path, const GeoMap& m) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n" << m.width << " " << m.height << "\n255\n";
  for (uint8_t f : m.flags) out.put(f ? char(255) : char(0));
}

void survey(VulkanContext& context, const Scene& scene, int size, const std::string& dump) {
  const Camera& cam = scene.cameras.front();
  float aspect = cam.aspect > 0 ? cam.aspect : float(scene.default_width) / float(scene.default_height);
  int w = size, h = std::max(1, int(std::lround(size / aspect)));
  VisibilityPass pass(context, scene);
  std::printf("%s: %zu triangles, %dx%d, S=4\n", scene.name.c_str(), scene.triangle_count(), w, h);
  angle_histogram(pass, scene, cam, w, h);
  std::printf("  geo_fraction vs normal angle (depth_rel 1e9 = off):");
  for (float a : {2.f, 5.f, 10.f, 15.f, 20.f, 25.f, 30.f, 45.f, 60.f, 89.f}) {
    VisibilitySettings s;
    s.normal_angle_deg = a;
    s.depth_rel = 1e9f;
    std::printf(" %g:%.4f", a, geo_fraction(pass.run(cam, w, h, s)));
  }
  std::printf("\n  geo_fraction vs depth_rel (normal angle 179 = off):");
  for (float r : {0.0003f, 0.001f, 0.003f, 0.01f, 0.03f, 0.1f, 0.3f, 1e9f}) {
    VisibilitySettings s;
    s.normal_angle_deg = 179.0f;
    s.depth_rel = r;
    std::printf(" %g:%.4f", r, geo_fraction(pass.run(cam, w, h, s)));
  }
  VisibilitySettings def;
  GeoMap map = pass.run(cam, w, h, def);
  std::printf("\n  defaults (%.0f deg, %g): geo_fraction %.4f\n", def.normal_angle_deg, def.depth_rel,
              geo_fraction(map));
  if (!dump.empty()) write_pgm(dump + "/" + scene.name + ".pgm", map);
}

}  // namespace

int main(int argc, char** argv) {
  int size = 512;
  std::string dump;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--size") && i + 1 < argc) size = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--dump") && i + 1 < argc) dump = argv[++i];
    else files.push_back(argv[i]);
  }
  try {
    auto context = VulkanContext::create({});
    std::printf("device: %s\n", context->device_name().c_str());
    for (int slices : {32, 64, 128, 256}) survey(*context, bench::sphere_scene(slices), size, dump);
    for (const auto& f : files) {
      size_t slash = f.find_last_of('/');
      survey(*context, bench::scene_or_fallback(f, f.substr(slash == std::string::npos ? 0 : slash + 1)), size, dump);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "survey_thresholds: %s\n", e.what());
    return 1;
  }
}
