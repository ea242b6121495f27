// glTF images, textures and materials (Loader members declared in gltf_load_internal.h), and
// the image loader that checks an image's bufferView before tinygltf decodes it.
#include <avif/avif.h>
#include <webp/decode.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>

#include "gltf/gltf_load_internal.h"

namespace hb::gltf_detail {

namespace {

// The largest image the WebP and AVIF decoders are asked for, in pixels (a 16k x 16k texture, 1 GiB
// as RGBA8): a header that claims more is a corrupt file, refused before anything is allocated.
constexpr uint64_t kMaxImagePixels = uint64_t(16384) * 16384;

// RGBA8 pixels into the tinygltf image, as its own stb loader leaves a PNG (4 components, 8 bits).
void setRgba8(tinygltf::Image* image, int width, int height, const uint8_t* rows, size_t rowBytes) {
  image->width = width;
  image->height = height;
  image->component = 4;
  image->bits = 8;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  const size_t row = static_cast<size_t>(width) * 4;
  image->image.resize(row * static_cast<size_t>(height));
  for (size_t y = 0; y < static_cast<size_t>(height); ++y)
    std::memcpy(image->image.data() + y * row, rows + y * rowBytes, row);
}

// EXT_texture_webp: Debian's libwebp, lossy and lossless alike, to RGBA8.
bool decodeWebp(tinygltf::Image* image, const unsigned char* bytes, int size, std::string* problem) {
  int width = 0, height = 0;
  if (!WebPGetInfo(bytes, static_cast<size_t>(size), &width, &height)) {
    *problem = "its WebP header does not parse";
    return false;
  }
  if (uint64_t(width) * uint64_t(height) > kMaxImagePixels) {
    *problem = "its WebP header claims " + std::to_string(width) + "x" + std::to_string(height) + " pixels";
    return false;
  }
  const std::unique_ptr<uint8_t, void (*)(void*)> rgba(
      WebPDecodeRGBA(bytes, static_cast<size_t>(size), &width, &height), WebPFree);
  if (rgba == nullptr) {
    *problem = "its WebP data does not decode";
    return false;
  }
  setRgba8(image, width, height, rgba.get(), static_cast<size_t>(width) * 4);
  return true;
}

// EXT_texture_avif: Debian's libavif (its AV1 decoder dav1d or libgav1), converted to RGBA8 by
// libavif from the image's own YUV matrix and range (identity for lossless files: exact).
bool decodeAvif(tinygltf::Image* image, const unsigned char* bytes, int size, std::string* problem) {
  const std::unique_ptr<avifDecoder, void (*)(avifDecoder*)> decoder(avifDecoderCreate(), avifDecoderDestroy);
  const std::unique_ptr<avifImage, void (*)(avifImage*)> yuv(avifImageCreateEmpty(), avifImageDestroy);
  if (decoder == nullptr || yuv == nullptr) {
    *problem = "libavif could not allocate its decoder";
    return false;
  }
  decoder->imageSizeLimit = static_cast<uint32_t>(kMaxImagePixels - 1);
  decoder->maxThreads = 1;  // one texture among many; the loader is not where the cores go
  if (const avifResult r = avifDecoderReadMemory(decoder.get(), yuv.get(), bytes, static_cast<size_t>(size));
      r != AVIF_RESULT_OK) {
    *problem = std::string("its AVIF data does not decode (libavif: ") + avifResultToString(r) + ")";
    return false;
  }
  avifRGBImage rgb;
  avifRGBImageSetDefaults(&rgb, yuv.get());
  rgb.format = AVIF_RGB_FORMAT_RGBA;
  rgb.depth = 8;  // 10- and 12-bit images round to 8 bits, as 16-bit PNGs do (loadTextures)
  avifRGBImageAllocatePixels(&rgb);
  const avifResult r = avifImageYUVToRGB(yuv.get(), &rgb);
  if (r == AVIF_RESULT_OK)
    setRgba8(image, static_cast<int>(rgb.width), static_cast<int>(rgb.height), rgb.pixels, rgb.rowBytes);
  avifRGBImageFreePixels(&rgb);
  if (r != AVIF_RESULT_OK)
    *problem = std::string("its AVIF colours do not convert (libavif: ") + avifResultToString(r) + ")";
  return r == AVIF_RESULT_OK;
}

}  // namespace

// tinygltf hands an image stored in a bufferView to its decoder without checking that the view
// lies inside its buffer; this loader checks first (the buffers are parsed before the images),
// then decodes: WebP and AVIF with Debian's libwebp and libavif, KTX2 not at all (no Debian
// library transcodes Basis Universal; see loadTextures), the rest with tinygltf's stb loader. Every
// decoded image is RGBA.
bool checkedImageLoader(tinygltf::Image* image, const int imageIndex, std::string* err, std::string* warn, int width,
                        int height, const unsigned char* bytes, int size, void* userData) {
  const auto* model = static_cast<const tinygltf::Model*>(userData);
  const std::string field = "images[" + std::to_string(imageIndex) + "]";
  if (image->bufferView >= 0) {
    const tinygltf::BufferView& view = model->bufferViews[static_cast<size_t>(image->bufferView)];
    const tinygltf::Buffer& buffer = model->buffers[static_cast<size_t>(view.buffer)];
    if (static_cast<uint64_t>(view.byteOffset) + view.byteLength > buffer.data.size()) {
      *err += field + ".bufferView: bufferViews[" + std::to_string(image->bufferView) +
              "] ends past the end of buffers[" + std::to_string(view.buffer) + "] (" +
              std::to_string(buffer.data.size()) + " bytes)";
      return false;
    }
  }
  if (size >= 12) {
    const auto has = [&](size_t at, const char* magic) {
      return std::memcmp(bytes + at, magic, std::strlen(magic)) == 0;
    };
    std::string problem;
    if (has(0, "\xABKTX 20\xBB")) {  // left empty, its format named: its textures render with their factors
      image->mimeType = "image/ktx2";
      return true;
    }
    const bool webp = has(0, "RIFF") && has(8, "WEBP");
    if (webp || has(4, "ftypavif") || has(4, "ftypavis")) {
      image->mimeType = webp ? "image/webp" : "image/avif";
      if (webp ? decodeWebp(image, bytes, size, &problem) : decodeAvif(image, bytes, size, &problem)) return true;
      *err += field + ": " + problem + " (truncated or corrupt); re-export the texture";
      return false;
    }
  }
  return tinygltf::LoadImageData(image, imageIndex, err, warn, width, height, bytes, size, nullptr);
}

void Loader::loadTextures() {
  // Textures whose only source is KTX2 / Basis Universal, which no Debian library transcodes.
  std::map<std::string, size_t> undecoded;
  textureSlot_.assign(model_.textures.size(), -1);
  for (size_t t = 0; t < model_.textures.size(); ++t) {
    const tinygltf::Texture& tex = model_.textures[t];
    // The image a texture reads: its EXT_texture_webp or EXT_texture_avif source where it has one
    // (decoded by checkedImageLoader), else its core source (PNG or JPEG, which a KHR_texture_basisu
    // texture may give as its fallback).
    std::string field = "textures[" + std::to_string(t) + "].source";
    int source = tex.source;
    for (const char* e : {"EXT_texture_avif", "EXT_texture_webp"})
      if (const auto it = tex.extensions.find(e); it != tex.extensions.end() && it->second.Get("source").IsNumber()) {
        source = it->second.Get("source").GetNumberAsInt();
        field = "textures[" + std::to_string(t) + "].extensions." + e + ".source";
      }
    if (source < 0) {  // only a KTX2 source, no PNG/JPEG fallback
      if (!tex.extensions.count("KHR_texture_basisu"))
        fail(field, "the texture has no source image", "give it a PNG, JPEG, WebP or AVIF source image");
      ++undecoded["KHR_texture_basisu"];
      continue;
    }
    size_t i = checkIndex(source, model_.images.size(), field, "images");
    const tinygltf::Image& image = model_.images[i];
    const std::string imageField = "images[" + std::to_string(i) + "]";
    if (image.mimeType == "image/ktx2" && image.image.empty()) {
      ++undecoded["KHR_texture_basisu"];
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
    warnings_->messages.push_back(
        path_ + ": " + std::to_string(total) + " texture(s) in " + list +
        " not decoded (hybridbench decodes PNG, JPEG, WebP and AVIF); their materials render with "
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
