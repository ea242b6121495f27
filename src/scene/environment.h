// The environment's JSON form, shared by a glTF scene's extras.environment and a config's
// "environment" (scene.h Environment):
//   {"image": "sky.hdr"            an equirectangular Radiance .hdr, relative to the file that names it
//    "color": [r, g, b]           linear RGB >= 0 multiplying the image, or alone a uniform colour
//    "intensity": x               >= 0, default 1
//    "rotation": degrees}         about +y, default 0
// One of image and color is required.
#pragma once
#include <filesystem>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "base/json_reader.h"
#include "scene/scene.h"

namespace hb {

// At most this many texels (a 4096 x 2048 map: 128 MiB as the GPU's vec4, lavapipe's largest
// storage binding) so that every device can bind it.
inline constexpr uint64_t kEnvironmentMaxTexels = 4096ull * 2048ull;

// Reads and loads it (the image through stb_image, relative paths against baseDir). Throws
// InputError naming where, the file and the fix.
Environment readEnvironment(const nlohmann::ordered_json& value, const json_reader::Where& where,
                            const std::filesystem::path& baseDir);
// What it was given (the image's path as resolved), in the form readEnvironment reads.
nlohmann::json toJson(const Environment& e);

// The radiance arriving along unit direction d (scene.h Environment): the map bilinearly
// filtered between texel centres (wrapping in azimuth, clamped at the poles), times color and
// intensity, in double. The GPU's lookup (shaders/environment.glsl.inc) is the same in float.
glm::dvec3 environmentRadiance(const Environment& e, const glm::dvec3& d);

}  // namespace hb
