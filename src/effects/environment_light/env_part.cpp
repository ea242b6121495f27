#include "effects/environment_light/env_part.h"

#include <string>

#include "base/errors.h"
#include "effects/ambient_occlusion/ao_part.h"
#include "effects/environment_light/env_effect.h"
#include "frame/base_parts.h"

namespace hb {

EnvironmentLightPart::EnvironmentLightPart(FrameBuilder& f) {
  HB_ASSERT(f.scene.environment);
  const SurfaceInputs surface = surfaceInputs(f);
  AoPassSettings ps;
  ps.ao = environmentSettingsOf(f.value);
  ps.worldPos = surface.worldPos;
  ps.normals = surface.normals;
  ps.environment = &*f.scene.environment;
  ps.effect = environmentLightEffect().name;
  const AoInputs in = surfaceBindings(f, surface);
  ps.tracer = f.tracer;
  const AoPassNames names{environmentLightEffect().name, kEnvironmentLdmBuildPass, "environment_light.ldm",
                          kEnvironmentLightPass, kEnvironmentLightResource};
  FrameLdmSet ldm;
  pass_ = makeFrameAoPass(f, ps, in, names, ldm);
  f.resources.publish(kEnvironmentLightResource, pass_->output(),
                      "vec4 per pixel: (1/pi) integral of L V cos (rgb), w = 1 or kAoSky / kAoNoNormal",
                      std::to_string(f.settings.width) + " x " + std::to_string(f.settings.height));
  // (1/π)∫ L V cos dω per pixel (ao_common.glsl.inc RADIANCE), reflected as Lambertian; w < 0: none.
  f.resources.addShadingTerm({kEnvironmentLightResource,
                              ShadingTerm::Storage::Vec4PerPixel,
                              {1.0f, 1.0f, 1.0f},
                              ShadingTerm::Weight::DiffuseAlbedo,
                              0.0f});

  passes_ = aoFramePasses(f, *pass_, surface, names, ldm, skipped_);
}

AoPass* environmentPassOf(const Renderer& renderer) {
  const EnvironmentLightPart* p = renderer.part<EnvironmentLightPart>(environmentLightEffect().name);
  return p ? &p->pass() : nullptr;
}

std::unique_ptr<FramePart> buildEnvironmentLight(FrameBuilder& frame) {
  return std::make_unique<EnvironmentLightPart>(frame);
}

}  // namespace hb
