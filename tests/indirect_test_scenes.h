// The scenes and helpers of the indirect-light GPU tests (indirect_gpu_test.cpp,
// indirect_splat_gpu_test.cpp): the settings of a frame with the effect, a Lambertian grey, a
// point light, the closed diffuse box with an optional floating block, and a photon's status and
// flux.
#pragma once
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "scene/mesh_builder.h"
#include "shared/gpu_types.h"

namespace hb::indirect_testing {

inline RenderSettings indirectSettings(uint32_t w, uint32_t h, const nlohmann::json& indirect) {
  return testing::settingsWithEffects(w, h, {{"shadows", false}, {"indirect", indirect}});
}

// A Lambertian grey: glTF's defaults are metallic (albedo·(1 − metallic) = 0), so metallic is 0.
inline Material diffuse(float albedo) {
  Material m;
  m.name = "diffuse";
  m.baseColorFactor = glm::vec4(albedo, albedo, albedo, 1.0f);
  m.metallicFactor = 0.0f;
  return m;
}

// A white point light whose glTF window (1 − (d/range)⁴)² is 1 to ~1e-13 over a few metres.
inline Light pointLight(glm::vec3 position, float intensity) {
  Light l;
  l.position = position;
  l.intensity = intensity;
  l.range = 1e4f;
  return l;
}

inline const glm::dvec3 kBoxLo(-2, 0, -2.5), kBoxHi(2, 3, 2.5);
inline const glm::vec3 kBoxLight(0.3f, 2.0f, 0.4f);

// The closed box 4 x 3 x 5 m of albedo 0.5 with the light and the camera inside (ao_gpu_test's
// closedBox), optionally with a floating block inside as an occluder.
inline Scene diffuseBox(const char* name, bool block) {
  Scene s;
  s.name = name;
  s.materials.push_back(diffuse(0.5f));
  MeshBuilder mb(name);
  addBox(mb, 0, kBoxLo, kBoxHi);
  if (block) addBox(mb, 0, {-1.2, 0.6, -1.6}, {0.2, 1.4, -0.4});
  mb.appendTo(s);
  s.lights.push_back(pointLight(kBoxLight, 20.0f));
  s.cameras.push_back(testing::lookFrom({0.3f, 1.5f, 2.0f}, {-0.5f, 1.0f, -2.5f}));
  return s;
}

inline uint32_t statusOf(const gpu::Photon& p) {
  uint32_t s;
  std::memcpy(&s, &p.normalStatus.w, 4);
  return s;
}

inline double fluxOf(const gpu::Photon& p) {
  return double(p.positionFluxR.w) + double(p.duFluxG.w) + double(p.dvFluxB.w);
}

}  // namespace hb::indirect_testing
