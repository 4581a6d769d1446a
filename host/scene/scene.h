// The scene as the renderer sees it: flat world-space triangle arrays (3 vertices per
// triangle, no index buffer, so the BVH, the raster pass and the shader share one
// triangle numbering), materials, textures, lights, cameras and render settings.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "scene/camera.h"
#include "scene/lights.h"
#include "scene/materials.h"
#include "scene/texture.h"

namespace zz {

// The effects a scene calls for; the shader specialises on it so that a scene without
// lights spawns no shadow ray and one without glass runs no refraction code.
struct EffectSet {
  bool shadows = false;      // any light
  bool reflection = false;   // any material with a mirror component
  bool refraction = false;   // any transmissive material
  bool absorption = false;   // any transmissive material with volume attenuation
  bool textures = false;     // any sampled texture
  bool emission = false;     // any emissive material
  bool material_textures = false;    // metallic/roughness/transmission sampled per hit
  bool normal_maps = false;          // any normal texture
  bool alpha_mask = false;           // any alphaMode MASK material
  bool alpha_blend = false;          // any alphaMode BLEND material
  bool shadow_transmission = false;  // lights and glass: shadow rays pass transmissive surfaces

  std::vector<std::string> names() const;  // e.g. {"shadows", "reflection"}
};

// The trace depth (bounces) a rig's "max_depth" and --max-depth accept.
inline constexpr int kMinTraceDepth = 0;
inline constexpr int kMaxTraceDepth = 16;

// The longest image side a frame may have (rig, command line, viewer window), in pixels.
inline constexpr int kMaxImageSide = 16384;

// The tone-mapping exposure and animation frame rate a rig and the command line accept:
// an exposure of 1e-30 gave a black image without a word.
inline constexpr double kMinExposure = 1e-6, kMaxExposure = 1e6;
inline constexpr double kMinFps = 1e-3, kMaxFps = 1000.0;

struct Scene {
  std::string name;

  // Triangle t has vertices positions[3t .. 3t+2] (world space).
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;     // shading normals, 3 per triangle (world space, unit)
  std::vector<glm::vec2> uvs;         // TEXCOORD_0, 3 per triangle (zero when the mesh has none)
  std::vector<glm::vec2> uvs1;        // TEXCOORD_1, 3 per triangle; empty when no mesh has one
  // Tangent frame for normal maps, 3 per triangle: xyz world-space unit tangent (along +u),
  // w = bitangent sign (B = w * cross(N, T)); empty when no material has a normal texture.
  std::vector<glm::vec4> tangents;
  std::vector<uint32_t> material_of;  // 1 per triangle, index into materials

  std::vector<Material> materials;
  std::vector<WhittedMaterial> whitted;  // 1 per material, from whitted_from_gltf
  std::vector<Texture> textures;
  std::vector<Light> lights;
  std::vector<Camera> cameras;  // at least one after loading

  glm::vec3 background{0.0f};
  float exposure = 1.0f;
  int max_depth = 2;  // trace depth: reflection/refraction bounces along a path (0 = none)
  int default_width = 512;
  int default_height = 512;
  bool width_given = false;   // the rig set "width" (else it follows the camera's aspect)
  bool height_given = false;  // the rig set "height"

  // Animation: glTF node animations, posed at `time` when loaded (scene/animation.h).
  bool animated = false;
  float animation_end = 0.0f;  // the last keyframe time, seconds
  double fps = 24.0;           // --fps, else the rig's "fps", else 24
  int first_frame = 0;         // the rig's "frames", else 0 .. ceil(animation_end * fps)
  int last_frame = 0;
  double time = 0.0;           // seconds the scene is posed at
  int frame = 0;               // the frame it was loaded as (-1 when given as a time)

  // Load-time bookkeeping, reported in stats.
  size_t dropped_degenerate = 0;
  // Every file the scene was read from: the rig, the glTF, its external buffers and images
  // (`zigzag info` lists them, so a farm knows when a finished frame is stale).
  std::vector<std::string> source_files;

  size_t triangle_count() const { return material_of.size(); }
  // Fill `whitted` from `materials`; call after editing materials.
  void finalize_materials();
  EffectSet effects() const;
  // The box around every vertex: {lo, hi}, both 0 without any.
  struct Bounds {
    glm::vec3 lo{0.0f}, hi{0.0f};
  };
  Bounds bounds() const;
};

}  // namespace zz
