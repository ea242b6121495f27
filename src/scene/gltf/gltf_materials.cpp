// glTF images, textures and materials (Loader members declared in gltf_load_internal.h), and
// the image loader that checks an image's bufferView before tinygltf decodes it.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include "scene/gltf/gltf_load_internal.h"

namespace hb::gltf_detail {

// tinygltf hands an image stored in a bufferView to its decoder without checking that the view
// lies inside its buffer; this loader checks first (the buffers are parsed before the images),
// then decodes with tinygltf's stb loader, which expands every image to RGBA.
bool checkedImageLoader(tinygltf::Image* image, const int imageIndex, std::string* err, std::string* warn, int width,
                        int height, const unsigned char* bytes, int size, void* userData) {
  // KTX2 / Basis Universal, WebP and AVIF: no decoder is linked (see loadTextures). The image is
  // left empty, its format named in mimeType, and its textures render with their factors.
  if (size >= 12) {
    const auto has = [&](size_t at, const char* magic) {
      return std::memcmp(bytes + at, magic, std::strlen(magic)) == 0;
    };
    const char* format = has(0, "\xABKTX 20\xBB")                   ? "image/ktx2"
                         : has(0, "RIFF") && has(8, "WEBP")         ? "image/webp"
                         : has(4, "ftypavif") || has(4, "ftypavis") ? "image/avif"
                                                                    : nullptr;
    if (format != nullptr) {
      image->mimeType = format;
      return true;
    }
  }
  const auto* model = static_cast<const tinygltf::Model*>(userData);
  if (image->bufferView >= 0) {
    const tinygltf::BufferView& view = model->bufferViews[static_cast<size_t>(image->bufferView)];
    const tinygltf::Buffer& buffer = model->buffers[static_cast<size_t>(view.buffer)];
    if (static_cast<uint64_t>(view.byteOffset) + view.byteLength > buffer.data.size()) {
      *err += "images[" + std::to_string(imageIndex) + "].bufferView: bufferViews[" +
              std::to_string(image->bufferView) + "] ends past the end of buffers[" + std::to_string(view.buffer) +
              "] (" + std::to_string(buffer.data.size()) + " bytes)";
      return false;
    }
  }
  return tinygltf::LoadImageData(image, imageIndex, err, warn, width, height, bytes, size, nullptr);
}

void Loader::loadTextures() {
  // Textures whose only source is an image in a format no linked library decodes, by extension.
  std::map<std::string, size_t> undecoded;
  auto extensionOf = [](const std::string& mimeType) {
    return mimeType == "image/ktx2"   ? "KHR_texture_basisu"
           : mimeType == "image/webp" ? "EXT_texture_webp"
           : mimeType == "image/avif" ? "EXT_texture_avif"
                                      : "";
  };
  textureSlot_.assign(model_.textures.size(), -1);
  for (size_t t = 0; t < model_.textures.size(); ++t) {
    const tinygltf::Texture& tex = model_.textures[t];
    const std::string field = "textures[" + std::to_string(t) + "].source";
    if (tex.source < 0) {  // only an extension's source (no PNG/JPEG fallback)
      const char* e = nullptr;
      for (const char* candidate : {"KHR_texture_basisu", "EXT_texture_webp", "EXT_texture_avif"})
        if (e == nullptr && tex.extensions.count(candidate)) e = candidate;
      if (e == nullptr) fail(field, "the texture has no source image", "give it a PNG or JPEG source image");
      ++undecoded[e];
      continue;
    }
    size_t i = checkIndex(tex.source, model_.images.size(), field, "images");
    const tinygltf::Image& image = model_.images[i];
    const std::string imageField = "images[" + std::to_string(i) + "]";
    if (const std::string e = extensionOf(image.mimeType); !e.empty() && image.image.empty()) {
      ++undecoded[e];
      continue;
    }
    const size_t pixels =
        static_cast<size_t>(std::max(image.width, 0)) * static_cast<size_t>(std::max(image.height, 0));
    const size_t bytesPerChannel = image.bits == 16 ? 2 : 1;
    if (pixels == 0 || image.component < 1 || image.component > 4 || (image.bits != 8 && image.bits != 16) ||
        image.image.size() < pixels * image.component * bytesPerChannel)
      fail(imageField, "image '" + image.uri.substr(0, 64) + "' was not found or not decoded",
           "put the image file next to the .gltf or embed it as PNG/JPEG");
    Texture out;
    out.name = !tex.name.empty() ? tex.name : image.name;
    out.width = static_cast<uint32_t>(image.width);
    out.height = static_cast<uint32_t>(image.height);
    out.rgba.resize(pixels * 4);
    for (size_t p = 0; p < pixels; ++p) {
      uint8_t channel[4] = {0, 0, 0, 255};
      for (int c = 0; c < image.component; ++c) {
        const size_t at = (p * image.component + c) * bytesPerChannel;
        if (bytesPerChannel == 1) {
          channel[c] = image.image[at];
        } else {
          uint16_t u;
          std::memcpy(&u, &image.image[at], 2);
          channel[c] = static_cast<uint8_t>((u * 255u + 32767u) / 65535u);  // round to nearest
        }
      }
      if (image.component <= 2) {  // grey or grey+alpha: replicate grey, move alpha to A
        channel[3] = image.component == 2 ? channel[1] : 255;
        channel[1] = channel[2] = channel[0];
      }
      std::memcpy(&out.rgba[p * 4], channel, 4);
    }
    textureSlot_[t] = static_cast<int>(scene_.textures.size());
    scene_.textures.push_back(std::move(out));
  }
  if (!undecoded.empty()) {
    std::string list;
    size_t total = 0;
    for (const auto& [e, n] : undecoded) {
      list += (list.empty() ? "" : ", ") + e + " (" + std::to_string(n) + ")";
      total += n;
    }
    warnings_->messages.push_back(path_ + ": " + std::to_string(total) + " texture(s) in " + list +
                                  " not decoded (hybridbench decodes PNG and JPEG); their materials render with "
                                  "their factors");
  }
}

int Loader::textureIndex(const tinygltf::TextureInfo& info, const std::string& field) const {
  if (info.index < 0) return -1;
  // -1 also for a texture that was not decoded: the material's factors alone then apply.
  return textureSlot_[checkIndex(info.index, model_.textures.size(), field, "textures")];
}

void Loader::loadMaterials() {
  for (size_t m = 0; m < model_.materials.size(); ++m) {
    const tinygltf::Material& mat = model_.materials[m];
    const std::string field = "materials[" + std::to_string(m) + "].pbrMetallicRoughness";
    const tinygltf::PbrMetallicRoughness& pbr = mat.pbrMetallicRoughness;
    Material out;
    out.name = mat.name;
    if (pbr.baseColorFactor.size() != 4)
      fail(field + ".baseColorFactor", "has " + std::to_string(pbr.baseColorFactor.size()) + " numbers",
           "give it 4 (RGBA)");
    for (int c = 0; c < 4; ++c) out.baseColorFactor[c] = static_cast<float>(pbr.baseColorFactor[c]);
    out.metallicFactor = static_cast<float>(pbr.metallicFactor);
    out.roughnessFactor = static_cast<float>(pbr.roughnessFactor);
    if (!std::isfinite(out.metallicFactor) || !std::isfinite(out.roughnessFactor) ||
        !std::isfinite(glm::dot(out.baseColorFactor, out.baseColorFactor)))
      fail(field, "a factor is not a finite number", "write factors as numbers in [0, 1]");
    out.baseColorTexture = textureIndex(pbr.baseColorTexture, field + ".baseColorTexture.index");
    out.metallicRoughnessTexture =
        textureIndex(pbr.metallicRoughnessTexture, field + ".metallicRoughnessTexture.index");
    out.doubleSided = mat.doubleSided;
    scene_.materials.push_back(std::move(out));
  }
}

uint32_t Loader::defaultMaterial() {
  if (defaultMaterial_ < 0) {
    defaultMaterial_ = static_cast<int>(scene_.materials.size());
    Material mat;
    mat.name = "default";
    scene_.materials.push_back(mat);
  }
  return static_cast<uint32_t>(defaultMaterial_);
}

void Loader::markSrgbTextures() {
  for (const Material& m : scene_.materials)
    if (m.baseColorTexture >= 0) scene_.textures[static_cast<size_t>(m.baseColorTexture)].srgb = true;
}

}  // namespace hb::gltf_detail
