// libFuzzer target for the glTF loader: any bytes, read as a .glb when they begin with "glTF" and
// as .gltf JSON otherwise (loadGltfFromMemory decides as loadGltf does for a file). InputError is
// the loader's answer to bad input, not a finding. A finding is anything else: another exception
// escaping, a crash, a sanitizer report, a leak, a timeout, or a loaded scene that the passes
// cannot draw (an index outside its array, an inf or NaN in a transform, light or camera).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <glm/glm.hpp>
#include <span>

#include "base/errors.h"
#include "gltf/gltf_io.h"

#define FUZZ_TARGET_NAME "fuzz_gltf"
#include "fuzz_checks.h"

namespace {

// A directory that does not exist: external buffer and image URIs are not found, so the fuzzer
// exercises data URIs and .glb chunks, never the files of the machine it runs on.
constexpr const char* kNoBaseDir = "/nonexistent-hybridbench-fuzz-dir";

using hb::fuzz::finite;

// What the GPU upload and the CPU references rely on after a successful load: indices inside their
// arrays, and finite transforms, lights and cameras (a float that overflowed to inf, or a NaN).
void checkScene(const hb::Scene& scene) {
  for (const hb::Mesh& mesh : scene.meshes)
    for (const hb::Primitive& p : mesh.primitives) {
      FUZZ_CHECK(uint64_t(p.firstIndex) + p.indexCount <= scene.indices.size());
      FUZZ_CHECK(uint64_t(p.vertexOffset) + p.vertexCount <= scene.vertices.size());
      FUZZ_CHECK(p.indexCount % 3 == 0);
      FUZZ_CHECK(p.material < scene.materials.size());
      for (uint32_t i = 0; i < p.indexCount; ++i) FUZZ_CHECK(scene.indices[p.firstIndex + i] < p.vertexCount);
    }
  for (const hb::Instance& instance : scene.instances)
    FUZZ_CHECK(instance.mesh < scene.meshes.size() && finite(instance.transform));
  for (const hb::Material& m : scene.materials) {
    FUZZ_CHECK(m.baseColorTexture < int(scene.textures.size()));
    FUZZ_CHECK(m.metallicRoughnessTexture < int(scene.textures.size()));
  }
  for (const hb::Texture& t : scene.textures)
    FUZZ_CHECK(t.width > 0 && t.height > 0 && t.rgba.size() == uint64_t(t.width) * t.height * 4);
  for (const hb::Light& l : scene.lights) {
    FUZZ_CHECK(l.type == hb::LightType::Directional ? l.range == 0.0f : l.range > 0.0f);
    FUZZ_CHECK(finite(l.position) && finite(l.direction) && finite(l.color));
    FUZZ_CHECK(std::isfinite(l.intensity) && std::isfinite(l.range));
  }
  for (const hb::Camera& c : scene.cameras)
    FUZZ_CHECK(finite(c.view) && std::isfinite(c.znear) && std::isfinite(c.zfar));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  hb::GltfLoadWarnings warnings;  // collected, not printed
  try {
    const hb::Scene scene = hb::loadGltfFromMemory(std::span(data, size), "fuzz.gltf", kNoBaseDir, &warnings);
    checkScene(scene);
    // What `scene info` and the results' scene hash do with any scene that loads.
    (void)hb::sceneInfoText(scene);
    (void)hb::sceneSha256(scene);
  } catch (const hb::InputError&) {
  }
  return 0;
}
