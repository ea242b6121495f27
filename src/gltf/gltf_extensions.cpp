// Which glTF extensions the loader reads, and what it says about the others. glTF files name
// every extension they use in extensionsUsed and, where a reader that ignores one would draw the
// wrong thing, also in extensionsRequired (glTF 2.0 §3.12). tinygltf accepts any of them silently,
// so a required one the loader does not read would otherwise load as the wrong thing.
#include <algorithm>
#include <string>
#include <vector>

#include "base/errors.h"
#include "gltf/gltf_load_internal.h"

namespace hb::gltf_detail {
namespace {

// Read by the loader: compressed geometry is decoded (gltf_compression.cpp), quantized attributes
// read as integers (gltf_accessors.cpp), texture transforms applied to the texture coordinates
// (gltf_meshes.cpp), WebP and AVIF images decoded (gltf_materials.cpp).
const std::vector<std::string> kRead = {
    "KHR_lights_punctual",   "KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization",
    "KHR_texture_transform", "EXT_texture_webp",           "EXT_texture_avif"};
// KTX2 / Basis Universal images, which no Debian library transcodes: a texture that has only such a
// source renders with its material's factors, and one warning line counts them (gltf_materials.cpp).
const std::vector<std::string> kImageFormats = {"KHR_texture_basisu"};

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
    if (!contains(kRead, e) && !contains(kImageFormats, e) && e != kImageBasedLight) unknownRequired.push_back(e);
  if (!unknownRequired.empty())
    throw InputError(path + ": requires " + joined(unknownRequired) +
                     ", which hybridbench does not read (extensionsRequired: a reader that ignores it draws the "
                     "wrong thing); re-export it without");
  for (const std::string& e : model.extensionsUsed)
    if (!contains(kRead, e) && !contains(kImageFormats, e) && e != kImageBasedLight) ignored.push_back(e);
  if (!ignored.empty())
    warnings.messages.push_back(path + ": ignores the optional extension(s) " + joined(ignored) +
                                " (materials and textures render as their core glTF values)");
}

}  // namespace hb::gltf_detail
