#include "ray_sets.h"

#include <cmath>
#include <exception>
#include <filesystem>
#include <random>

#include "scene/camera.h"
#ifdef ZZ_BENCH_HAVE_LOADER
#include "scene/loader.h"
#endif

namespace zz::bench {
namespace {

void add_tri(std::vector<glm::vec3>& p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  p.push_back(a), p.push_back(b), p.push_back(c);
}

void bounds(const std::vector<glm::vec3>& p, glm::vec3& lo, glm::vec3& hi) {
  lo = glm::vec3(kInfinity), hi = glm::vec3(-kInfinity);
  for (glm::vec3 v : p) lo = glm::min(lo, v), hi = glm::max(hi, v);
}

// A default view and light for meshes without their own: from the front, above.
void frame(Mesh& m) {
  glm::vec3 lo, hi;
  bounds(m.positions, lo, hi);
  glm::vec3 c = 0.5f * (lo + hi), e = hi - lo;
  float r = 0.5f * glm::length(e);
  m.target = c;
  m.eye = c + glm::vec3(0.3f * r, 0.6f * r, 2.2f * r);
  m.light = c + glm::vec3(-0.2f * r, 1.5f * r, 0.4f * r);
}

}  // namespace

Mesh load_mesh(const std::string& path, std::string* why) {
  Mesh m;
  m.name = std::filesystem::path(path).stem().string();
  if (!std::filesystem::exists(path)) {
    *why = "missing";
    return m;
  }
#ifdef ZZ_BENCH_HAVE_LOADER
  try {
    LoadOptions opt;
    opt.quiet = true;
    Scene s = load_scene(path, opt);
    m.positions = s.positions;
    frame(m);
    if (!s.cameras.empty()) {
      const Camera& c = s.cameras.front();
      m.eye = c.position;
      m.target = c.position + c.forward;
      m.yfov = c.yfov;
    }
    for (const Light& l : s.lights)
      if (l.type != Light::Type::Directional) {
        m.light = l.position;
        break;
      }
  } catch (const std::exception& e) {
    *why = e.what();
    m.positions.clear();
  }
#else
  *why = "zz::load_scene not linked (host/scene has no implementation yet)";
#endif
  return m;
}

Mesh random_soup_mesh(int triangles) {
  Mesh m;
  m.name = "soup" + std::to_string(triangles / 1000) + "k";
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < triangles; ++i) {
    glm::vec3 c(u(rng), u(rng), u(rng));
    add_tri(m.positions, c, c + 0.05f * glm::vec3(u(rng), u(rng), u(rng)),
            c + 0.05f * glm::vec3(u(rng), u(rng), u(rng)));
  }
  frame(m);
  return m;
}

Mesh heightfield_mesh(int n) {
  Mesh m;
  m.name = "heightfield" + std::to_string(2 * n * n / 1000) + "k";
  auto h = [&](int i, int j) {
    float x = float(i) / float(n), z = float(j) / float(n);
    return glm::vec3(x, 0.08f * std::sin(11.0f * x) * std::cos(7.0f * z) +
                            0.03f * std::sin(37.0f * x + 23.0f * z), z);
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      add_tri(m.positions, h(i, j), h(i + 1, j), h(i + 1, j + 1));
      add_tri(m.positions, h(i, j), h(i + 1, j + 1), h(i, j + 1));
    }
  frame(m);
  m.eye = glm::vec3(0.5f, 0.45f, 1.4f);
  m.target = glm::vec3(0.5f, 0.0f, 0.4f);
  return m;
}

Workload make_workload(Mesh mesh, const Bvh& bvh, int width, int height) {
  Workload w;
  Camera cam = Camera::look_at(mesh.eye, mesh.target, glm::vec3(0, 1, 0), mesh.yfov);
  CameraRays rays(cam, width, height);
  std::mt19937 rng(7);
  std::normal_distribution<float> g;
  for (int y = 0; y < height; y += 2)
    for (int x = 0; x < width; x += 2) {
      RayPacket4 p;
      float4 px(x + 0.5f, x + 1.5f, x + 0.5f, x + 1.5f), py(y + 0.5f, y + 0.5f, y + 1.5f, y + 1.5f);
      rays.directions4(px, py, p.dx, p.dy, p.dz);
      p.ox = float4(rays.origin.x), p.oy = float4(rays.origin.y), p.oz = float4(rays.origin.z);
      p.tmax = float4(kInfinity);
      w.primary.packets.push_back(p);
      w.primary.masks.push_back(0xF);
      w.primary.ray_count += 4;

      HitPacket4 h;
      bvh.intersect4(p, mask4(true), h);
      RayPacket4 s{}, r{};
      alignas(16) float so[7][4] = {}, ro[7][4] = {};
      int mask = 0;
      for (int i = 0; i < 4; ++i) {
        int prim = h.prim[i];
        if (prim < 0) continue;
        mask |= 1 << i;
        const glm::vec3* v = &mesh.positions[3 * size_t(prim)];
        glm::vec3 d(p.dx[i], p.dy[i], p.dz[i]);
        const SurfacePosition hit = interpolate_hit(v[0], v[1], v[2], h.u[i], h.v[i]);
        glm::vec3 n = glm::normalize(glm::cross(v[1] - v[0], v[2] - v[0]));
        if (glm::dot(n, d) > 0.0f) n = -n;  // the side the camera sees
        glm::vec3 o = offset_ray_origin(hit, n);
        glm::vec3 to_light = mesh.light - o;
        // Shadow ray: towards the light, stopping just short of it.
        float sv[7] = {o.x, o.y, o.z, to_light.x, to_light.y, to_light.z, 0.9999f};
        // Secondary: a random direction in the hemisphere around n.
        glm::vec3 rd(g(rng), g(rng), g(rng));
        if (glm::dot(rd, n) < 0.0f) rd = -rd;
        rd = glm::normalize(rd);
        float rv[7] = {o.x, o.y, o.z, rd.x, rd.y, rd.z, kInfinity};
        for (int k = 0; k < 7; ++k) so[k][i] = sv[k], ro[k][i] = rv[k];
      }
      if (!mask) continue;
      auto fill = [](RayPacket4& q, float f[7][4]) {
        q.ox = float4::load(f[0]), q.oy = float4::load(f[1]), q.oz = float4::load(f[2]);
        q.dx = float4::load(f[3]), q.dy = float4::load(f[4]), q.dz = float4::load(f[5]);
        q.tmax = float4::load(f[6]);
      };
      fill(s, so);
      fill(r, ro);
      int active = __builtin_popcount(unsigned(mask));
      w.shadow.packets.push_back(s), w.shadow.masks.push_back(mask), w.shadow.ray_count += active;
      w.secondary.packets.push_back(r), w.secondary.masks.push_back(mask);
      w.secondary.ray_count += active;
    }
  w.mesh = std::move(mesh);
  return w;
}

}  // namespace zz::bench
