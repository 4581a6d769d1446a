// Light arriving at a point from one punctual light, and the highlight lobe it makes:
// shared by the shader (render/shader.cpp) and the analytic highlight test
// (render/specular_peak.cpp), so both see the same lights and the same lobe.
#pragma once

#include <glm/glm.hpp>

#include "scene/lights.h"

namespace zz {

// glTF KHR_lights_punctual: unit direction from `p` to the light, the distance to it
// (infinity for directional lights) and the incident radiance factor (intensity x
// distance falloff x range window x spot cone). False where the light gives nothing.
bool light_towards(const Light& light, glm::vec3 p, glm::vec3& to_light, float& tmax, glm::vec3& radiance_scale);

// Normalised Phong (energy-conserving): (n + 2) / (2 pi) cos^n of the angle between the
// light's mirror direction about the shading normal and the direction to the viewer.
inline float phong_normalisation(float shininess) { return (shininess + 2.0f) * 0.5f * 0.318309886f; }

}  // namespace zz
