// The flag rule of shaders/geo_flags.comp on the host, with SSE id compares: the test
// oracle for the compute shader and a benchmark baseline (bench_visibility), not the
// production path. Same float operations as the shader (the build disables FMA
// contraction, the shader marks its arithmetic `precise`), so the flags match bit for bit
// on lavapipe, whose division is IEEE and which keeps denormals here. A GPU may divide to
// 2.5 ULP and flush denormals (SPIR-V's precision rules allow both), so there a pair right
// at the angle or distance threshold may flag differently: compare with a tolerance there.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "core/geo_map.h"
#include "shaders/visibility_shared.h"

namespace zz {

// Per triangle: the unit normal and h = n.(v0 - origin), as triangle_planes.comp computes them.
std::vector<glm::vec4> triangle_planes(const std::vector<glm::vec3>& positions,
                                       const std::vector<glm::vec4>& normals, glm::vec3 origin);

// The map from a whole-frame id image in VisibilityPass::render_ids' layout (ring
// included) and the frame's planes; `p` from make_flag_push. Each differing sample pair
// is tested once, then every pixel counts the differing pairs of its block, horizontal and
// vertical apart, into the shader's flag byte (kGeoEdge, kGeoAlongX). With the material rule on
// (p.limits.z), `normals` are geometric_normals (material tags in w).
GeoMap geo_flags_cpu(const std::vector<uint32_t>& ids, const std::vector<glm::vec4>& planes,
                     const gpu::FlagPush& p, const std::vector<glm::vec4>* normals = nullptr);

}  // namespace zz
