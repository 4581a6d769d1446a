// The benchmark's inputs: a triangle soup and the three ray sets traced against it.
// Both tracers (ours and Embree) read exactly these arrays.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "accel/bvh.h"
#include "accel/ray.h"

namespace zz::bench {

struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;  // 3 per triangle
  glm::vec3 eye, target;             // camera for the primary rays
  float yfov = 0.8f;
  glm::vec3 light;                   // point light for the shadow rays
};

// A ray set: packets of 4 plus the active mask of each (a primary packet is a 2x2 pixel
// block; shadow and secondary packets keep the lanes whose primary ray hit).
struct RaySet {
  std::vector<RayPacket4> packets;
  std::vector<int> masks;  // 4-bit lane masks
  size_t ray_count = 0;    // active lanes
};

struct Workload {
  Mesh mesh;
  RaySet primary, shadow, secondary;
};

// Loads `path` with zz::load_scene (when linked); empty positions if unavailable.
Mesh load_mesh(const std::string& path, std::string* why);
Mesh random_soup_mesh(int triangles);   // overlapping random triangles (Embree's stress case)
Mesh heightfield_mesh(int n);           // n x n quads of a smooth terrain

// Primary rays through a width x height image, then shadow and secondary rays from the
// primary hits (found with `bvh`), origins offset with offset_ray_origin.
Workload make_workload(Mesh mesh, const Bvh& bvh, int width, int height);

}  // namespace zz::bench
