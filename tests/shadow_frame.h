// A frame rendered with shadows, read back for the CPU references (shadows_gpu_test.cpp,
// many_lights_gpu_test.cpp): the settings it ran with, its depth, light lists and shadow words,
// and the float matrices the renderer used.
#pragma once
#include <vector>

#include <glm/glm.hpp>

#include "frame/render_settings.h"
#include "frame/renderer.h"

namespace hb::testing {

struct ShadowedFrame {
  RenderSettings settings;
  std::vector<float> depth;
  CullingReadback culling;
  ShadowReadback shadows;
  glm::mat4 view, proj;
};

}  // namespace hb::testing
