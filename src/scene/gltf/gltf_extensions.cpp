// Which glTF extensions the loader reads, and what it says about the others. glTF files name
// every extension they use in extensionsUsed and, where a reader that ignores one would draw the
// wrong thing, also in extensionsRequired (glTF 2.0 §3.12). tinygltf accepts any of them silently,
// so a Draco-compressed mesh would otherwise fail later with a generic accessor message (or load
// with nothing to draw).
#include <algorithm>
#include <string>
#include <vector>

#include "base/errors.h"
#include "scene/gltf/gltf_load_internal.h"

namespace hb::gltf_detail {
namespace {

// Read by the loader.
const std::vector<std::string> kRead = {"KHR_lights_punctual"};

struct Unreadable {
  const char* name;
  const char* what;  // what the file holds that the loader cannot read
  const char* fix;
};

// Extensions that replace the data the loader reads (geometry or images): refused whether required
// or only used, since a file may list one as used with no fallback for some primitives.
const Unreadable kRefused[] = {
    {"KHR_draco_mesh_compression", "Draco-compressed meshes",
     "re-export it without mesh compression (Blender's glTF exporter: untick Compression)"},
    {"EXT_meshopt_compression", "meshopt-compressed buffers", "re-export it without meshopt compression"},
    {"KHR_mesh_quantization", "quantized (integer) vertex attributes",
     "re-export it with float positions, normals and texture coordinates"},
    {"KHR_texture_basisu", "KTX2 / Basis Universal textures", "re-export it with PNG or JPEG textures"},
    {"EXT_texture_webp", "WebP textures", "re-export it with PNG or JPEG textures"},
    {"EXT_texture_avif", "AVIF textures", "re-export it with PNG or JPEG textures"},
};

bool contains(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

void checkExtensions(const tinygltf::Model& model, const std::string& path, GltfLoadWarnings& warnings) {
  for (const Unreadable& u : kRefused)
    if (contains(model.extensionsRequired, u.name) || contains(model.extensionsUsed, u.name))
      throw InputError(path + ": uses " + u.name + " (" + u.what + "), which hybridbench does not read; " + u.fix);
  // Image-based light: its prefiltered cube maps and spherical harmonics are not what the
  // environment light traces (an equirectangular radiance map), so the scene loads without it.
  constexpr const char* kImageBasedLight = "EXT_lights_image_based";
  if (contains(model.extensionsRequired, kImageBasedLight) || contains(model.extensionsUsed, kImageBasedLight))
    warnings.messages.push_back(path +
                                ": ignores EXT_lights_image_based (its cube maps and spherical harmonics are "
                                "not read); give the environment as an equirectangular .hdr in "
                                "scenes[s].extras.environment or a config's \"environment\"");
  std::vector<std::string> unknownRequired, ignored;
  for (const std::string& e : model.extensionsRequired)
    if (!contains(kRead, e) && e != kImageBasedLight) unknownRequired.push_back(e);
  if (!unknownRequired.empty())
    throw InputError(path + ": requires " + joined(unknownRequired) +
                     ", which hybridbench does not read (extensionsRequired: a reader that ignores it draws the "
                     "wrong thing); re-export it without");
  for (const std::string& e : model.extensionsUsed)
    if (!contains(kRead, e) && e != kImageBasedLight) ignored.push_back(e);
  if (!ignored.empty())
    warnings.messages.push_back(path + ": ignores the optional extension(s) " + joined(ignored) +
                                " (materials and textures render as their core glTF values)");
}

}  // namespace hb::gltf_detail
