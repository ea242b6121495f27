// Compressed glTF as it comes from the tools people use (issue #35): committed scenes compressed at
// test time with npm's gltfpack (EXT_meshopt_compression + KHR_mesh_quantization, its defaults, and
// with its filters) and @gltf-transform/cli (KHR_draco_mesh_compression; WebP and AVIF textures),
// checked by the Khronos validator, loaded and rendered on the present device against their
// sources; truncated and corrupt streams are exit 2 with one line naming the mesh and the extension.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "base/image_io.h"
#include "gltf/gltf_io.h"
#include "reference/flip.h"
#include "tool_process.h"

// A named namespace: the tests build in unity batches, where anonymous namespaces of several files meet.
namespace gltf_compressed_test {
namespace {

using namespace hb::testing;

const fs::path kSource = HYBRIDBENCH_SOURCE_DIR;
const fs::path kBin = kSource / "tools/node_modules/.bin";

// Position bits of both tools' defaults: gltfpack -vp 14, gltf-transform draco --quantize-position 14.
constexpr int kPositionBits = 14;

// A real mesh made outside this repository (scenes/external/README.md), a generated room with a
// camera and a light, and an exported built-in (scenes/README.md).
const std::vector<fs::path> kSources = {kSource / "scenes/external/mcad-bearing.glb",
                                        kSource / "scenes/cornell-box.gltf", kSource / "scenes/depth-step.gltf"};

// A GLB's JSON and BIN chunks, to break a compressed copy on purpose (glTF 2.0 §4.4).
struct Glb {
  nlohmann::json doc;
  std::string bin;
  explicit Glb(const fs::path& path) {
    const std::string bytes = hb::testing::readFile(path);
    uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, bytes.data() + 12, 4);
    doc = nlohmann::json::parse(bytes.substr(20, jsonLength));
    bin = bytes.substr(20 + jsonLength + 8);
  }
  void write(const fs::path& path) const {
    std::string text = doc.dump();
    while (text.size() % 4) text += ' ';
    std::string out = "glTF";
    auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(static_cast<uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
    u32(static_cast<uint32_t>(text.size()));
    u32(0x4E4F534Au);  // "JSON"
    out += text;
    u32(static_cast<uint32_t>(bin.size()));
    u32(0x004E4942u);  // "BIN\0"
    out += bin;
    hb::testing::writeFile(path, out);
  }
  // The filters of its EXT_meshopt_compression bufferViews.
  std::set<std::string> filters() const {
    std::set<std::string> out;
    for (const nlohmann::json& view : doc.value("bufferViews", nlohmann::json::array()))
      if (view.contains("extensions") && view["extensions"].contains("EXT_meshopt_compression"))
        out.insert(view["extensions"]["EXT_meshopt_compression"].value("filter", "NONE"));
    return out;
  }
};

struct Copy {
  fs::path path;
  const char* extension;  // what `scene info` names
};

class GltfCompressed : public ToolTest {
 protected:
  // Runs a shell command line (the npm tools); its output goes to a file named in the failure.
  void shell(const std::string& command) {
    const fs::path log = dir / "shell.log";
    const int rc = std::system((command + " >" + log.string() + " 2>&1").c_str());
    ASSERT_EQ(rc, 0) << command << "\n" << hb::testing::readFile(log);
  }
  // The two compressed copies of `source`, written into the test's folder.
  std::vector<Copy> compress(const fs::path& source) {
    if (!fs::exists(kBin / "gltfpack") || !fs::exists(kBin / "gltf-transform")) {
      ADD_FAILURE() << "gltfpack or gltf-transform is not in " << kBin << ": run scripts/setup.sh";
      return {};
    }
    const std::string stem = source.stem().string();
    const Copy meshopt{dir / (stem + "-meshopt.glb"), "EXT_meshopt_compression, KHR_mesh_quantization"};
    const Copy filtered{dir / (stem + "-meshopt-filtered.glb"), "EXT_meshopt_compression, KHR_mesh_quantization"};
    const Copy draco{dir / (stem + "-draco.glb"), "KHR_draco_mesh_compression"};
    // gltfpack -c: meshopt compression; its default quantization (positions 14 bits, normals 8,
    // texture coordinates 12). -cc adds meshopt's filters (normals as octahedral 8-bit pairs), which
    // -c never writes.
    shell((kBin / "gltfpack").string() + " -c -i " + source.string() + " -o " + meshopt.path.string());
    shell((kBin / "gltfpack").string() + " -cc -i " + source.string() + " -o " + filtered.path.string());
    shell((kBin / "gltf-transform").string() + " draco " + source.string() + " " + draco.path.string());
    const bool normals = hb::testing::readFile(source).find("\"NORMAL\"") != std::string::npos;
    if (normals && Glb(filtered.path).filters().count("OCTAHEDRAL") == 0)
      ADD_FAILURE() << "gltfpack -cc wrote no OCTAHEDRAL filter into " << filtered.path;
    return {meshopt, filtered, draco};
  }
  // Renders `scene` at 64x48 with the scene's own camera and lights and without the effects that
  // trace (a few tenths of a second on lavapipe); returns color.png.
  hb::ImageRGBA8 renderColor(const fs::path& scene) {
    const fs::path out = dir / ("render-" + scene.filename().string());
    const RunResult r = run({"render", "--scene", scene.string(), "--size", "64x48", "--set", "ambient_occlusion=false",
                             "--set", "indirect=false", "--out", out.string()});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return hb::readPng(out / "color.png");
  }
  nlohmann::json info(const fs::path& file) {
    const RunResult r = run({"scene", "info", file.string(), "--json"});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return nlohmann::json::parse(r.out, nullptr, false);
  }
};

// The largest distance from a point of `a` to its nearest point of `b` (brute force: a few
// thousand vertices).
double oneSidedHausdorff(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  double worst = 0.0;
  for (const glm::vec3& p : a) {
    double nearest = INFINITY;
    for (const glm::vec3& q : b) nearest = std::min(nearest, glm::length(glm::dvec3(p) - glm::dvec3(q)));
    worst = std::max(worst, nearest);
  }
  return worst;
}

// The Khronos validator on each copy: 0 errors and 0 warnings (scripts/validate-gltf.mjs fails on
// either); each loads with its source's triangle count and names its compression in scene info.
TEST_F(GltfCompressed, CopiesPassTheValidatorAndLoadWithTheSameTriangles) {
  for (const fs::path& source : kSources) {
    SCOPED_TRACE(source.string());
    const nlohmann::json plain = info(source);
    EXPECT_TRUE(plain["compression"].is_null()) << plain["compression"];
    for (const Copy& copy : compress(source)) {
      SCOPED_TRACE(copy.path.filename().string());
      shell("node " + (kSource / "scripts/validate-gltf.mjs").string() + " " + copy.path.string());
      const nlohmann::json packed = info(copy.path);
      EXPECT_EQ(packed["triangles"], plain["triangles"]);
      EXPECT_EQ(packed["compression"], copy.extension);
    }
  }
}

// The bound e derived below: (sqrt(3) / 2) * D / (2^b - 1) for a scene whose world bounds have
// diagonal D, b = kPositionBits.
double positionBound(const hb::Scene& plain) {
  glm::vec3 lo, hi;
  plain.bounds(lo, hi);
  return std::sqrt(3.0) / 2.0 * glm::length(glm::dvec3(hi - lo)) / ((1 << kPositionBits) - 1);
}

// Decoded positions against the source's, in world space. Both tools quantize each position
// component to kPositionBits bits over a box no larger than the part they quantize together: a
// component rounds to the nearest of 2^b - 1 steps of size extent / (2^b - 1), off by at most half a
// step. The extent of any box around world-space geometry, measured along any axis after a rigid
// node transform (our sources scale nothing), is at most the diagonal D of the scene's world
// bounds, so every vertex lies within e = (sqrt(3) / 2) * D / (2^b - 1) of its source position
// (float rounding of the node transforms: ~1e-7 D, far below). The nearest source vertex is at
// most that far too, and so is the nearest decoded vertex to a source one.
TEST_F(GltfCompressed, DecodedPositionsAreWithinTheQuantizationErrorOfTheSource) {
  for (const fs::path& source : kSources) {
    SCOPED_TRACE(source.string());
    hb::GltfLoadWarnings quiet;
    const hb::Scene plain = hb::loadGltf(source.string(), &quiet);
    const double e = positionBound(plain);
    const std::vector<glm::vec3> reference = plain.worldTriangles();
    for (const Copy& copy : compress(source)) {
      SCOPED_TRACE(copy.path.filename().string());
      const std::vector<glm::vec3> decoded = hb::loadGltf(copy.path.string(), &quiet).worldTriangles();
      ASSERT_EQ(decoded.size(), reference.size());
      EXPECT_LE(oneSidedHausdorff(decoded, reference), e);
      EXPECT_LE(oneSidedHausdorff(reference, decoded), e);
    }
  }
}

// Each triangle corner of `scene` in world space: its position and its unit normal (the mesh's
// normal through the inverse transpose of its instance's transform).
std::vector<std::pair<glm::dvec3, glm::dvec3>> worldCorners(const hb::Scene& scene) {
  std::vector<std::pair<glm::dvec3, glm::dvec3>> out;
  for (const hb::Instance& inst : scene.instances) {
    const glm::dmat4 m(inst.transform);
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(m)));
    for (const hb::Primitive& p : scene.meshes[inst.mesh].primitives)
      for (uint32_t i = 0; i < p.indexCount; ++i) {
        const hb::Vertex& v = scene.vertices[p.vertexOffset + scene.indices[p.firstIndex + i]];
        out.emplace_back(glm::dvec3(m * glm::dvec4(glm::dvec3(v.position), 1.0)),
                         glm::normalize(normalMatrix * glm::dvec3(v.normal)));
      }
  }
  return out;
}

// Decoded normals against the source's, for the sources that have normals (a mesh without them
// gets face normals from its quantized positions, which is the position test's business). The
// bound is the loosest of the three encodings, gltfpack's 8-bit octahedral one (-cc), with
// h = 0.5 / 127 the rounding of an 8-bit snorm coordinate:
// - the encoder maps the unit normal n to the octahedron |x| + |y| + |z| = 1 (folding the lower
//   half over) and rounds its two coordinates to multiples of 1/127: each moves by <= h, the third
//   by <= 2h (it is 1 - |x| - |y|; the fold is as linear), so the point moves by <= sqrt(6) h;
// - normalizing a point o of the octahedron (|o| >= 1/sqrt(3)) moved by d gives a unit vector
//   within 2 |d| / |o| of o / |o| (|p/|p| - o/|o|| <= (||p| - |o|| + |d|) / |o|), so <= 6 sqrt(2) h;
// - meshopt's decoder writes that unit vector as 8-bit snorm again (<= sqrt(3) h per vector) and
//   the loader's normal is normalized once more: <= 2 sqrt(3) h by the same argument.
// Total (6 sqrt(2) + 2 sqrt(3)) h = 0.047. gltfpack -c (8-bit snorm components, <= 2 sqrt(3) h)
// and Draco (10-bit octahedral, a step of 1/511) err less. A decoded corner is compared with the
// source's corners at its position (within the position bound e of the test above; a box's corner
// has three faces' normals there) and the nearest normal of those counts.
TEST_F(GltfCompressed, DecodedNormalsAreWithinTheQuantizationErrorOfTheSource) {
  const double h = 0.5 / 127.0;
  const double bound = (6.0 * std::sqrt(2.0) + 2.0 * std::sqrt(3.0)) * h;
  for (const fs::path& source : {kSources[1], kSources[2]}) {
    SCOPED_TRACE(source.string());
    hb::GltfLoadWarnings quiet;
    const hb::Scene plain = hb::loadGltf(source.string(), &quiet);
    const double e = positionBound(plain);
    const auto reference = worldCorners(plain);
    for (const Copy& copy : compress(source)) {
      SCOPED_TRACE(copy.path.filename().string());
      double worst = 0.0;
      for (const auto& [p, n] : worldCorners(hb::loadGltf(copy.path.string(), &quiet))) {
        double nearest = INFINITY;
        for (const auto& [q, m] : reference)
          if (glm::length(p - q) <= e) nearest = std::min(nearest, glm::length(n - m));
        worst = std::max(worst, nearest);
      }
      EXPECT_LE(worst, bound);
    }
  }
}

// A stream cut short (its byteLength halved) or overwritten (0xFF from its 9th byte on, past
// Draco's header) is exit 2 with one line naming the file, the mesh and the extension.
TEST_F(GltfCompressed, ATruncatedOrCorruptStreamIsExit2NamingTheMeshAndTheExtension) {
  const std::vector<Copy> copies = compress(kSources[0]);
  ASSERT_EQ(copies.size(), 3u);
  for (bool truncate : {true, false})
    for (const Copy& copy : copies) {
      Glb glb(copy.path);
      const bool draco = copy.path.string().find("draco") != std::string::npos;
      nlohmann::json* stream = nullptr;  // {byteOffset, byteLength} of the first compressed stream
      if (draco) {
        const int v = glb.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"];
        stream = &glb.doc["bufferViews"][static_cast<size_t>(v)];
      } else {
        for (nlohmann::json& view : glb.doc["bufferViews"])
          if (view.contains("extensions") && view["extensions"]["EXT_meshopt_compression"]["mode"] == "ATTRIBUTES") {
            stream = &view["extensions"]["EXT_meshopt_compression"];
            break;
          }
      }
      ASSERT_NE(stream, nullptr) << copy.path;
      const size_t offset = stream->value("byteOffset", size_t(0)), length = (*stream)["byteLength"];
      if (truncate)
        (*stream)["byteLength"] = length / 2;
      else
        std::fill(glb.bin.begin() + static_cast<std::ptrdiff_t>(offset + 8),
                  glb.bin.begin() + static_cast<std::ptrdiff_t>(offset + length), '\xff');
      const fs::path bad = dir / ((truncate ? "truncated-" : "corrupt-") + copy.path.filename().string());
      glb.write(bad);
      SCOPED_TRACE(bad.string());
      const RunResult r = run({"scene", "info", bad.string()});
      EXPECT_EQ(r.exitCode, 2) << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
      for (const std::string& part :
           {bad.string() + ": mesh 0", std::string(draco ? "KHR_draco_mesh_compression" : "EXT_meshopt_compression"),
            std::string("does not decode (")})
        EXPECT_NE(r.err.find(part), std::string::npos) << "'" << part << "' not in: " << r.err;
    }
}

// The bound on the mean FLIP of a copy of `reference` that differs by at most one 8-bit step per
// channel outside `free` (pixels whose error may be anything): the derivation is at
// CopiesRenderWithinTheFlipBoundOfTheirQuantization. A step that would leave [0, 255] goes the
// other way, so every pixel moves by exactly one step in each channel its pattern names.
double oneStepFlipBound(const hb::ImageRGBA8& reference, const std::vector<uint8_t>& free) {
  const size_t n = size_t(reference.width) * reference.height;
  std::vector<double> worst(n, 0.0);
  for (int sr = -1; sr <= 1; ++sr)
    for (int sg = -1; sg <= 1; ++sg)
      for (int sb = -1; sb <= 1; ++sb)
        for (bool checkerboard : {false, true}) {
          if (sr == 0 && sg == 0 && sb == 0) continue;
          hb::ImageRGBA8 moved = reference;
          for (size_t p = 0; p < n; ++p) {
            const int flip = checkerboard && (p % reference.width + p / reference.width) % 2 ? -1 : 1;
            const int sign[3] = {sr * flip, sg * flip, sb * flip};
            for (int c = 0; c < 3; ++c) {
              const int v = reference.px[p * 4 + c] + sign[c];
              moved.px[p * 4 + c] = static_cast<uint8_t>(v < 0 ? 1 : v > 255 ? 254 : v);
            }
          }
          const hb::FlipResult r = hb::ldrFlip(reference, moved);
          for (size_t p = 0; p < n; ++p) worst[p] = std::max(worst[p], double(r.errorMap.px[p]));
        }
  double sum = 0.0;
  for (size_t p = 0; p < n; ++p) sum += free[p] ? 1.0 : worst[p];
  return sum / double(n);
}

// Distance from point p to segment ab (pixels).
double segmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

// Each copy of an exported built-in with a camera (depth-step) renders within a FLIP bound of its
// source. Every point of a triangle moves by at most e (the test above); at view depth z >= zmin
// a point (x, y, z) projects to f (x, y) / z, so it moves on screen by at most
// delta = f e / (zmin - e) * (1 + r / f), r the image's half-diagonal in pixels (the second term
// from the change of z). Only pixels whose centre lies within delta of a projected edge of the
// source can change coverage (the band). Elsewhere what differs is shading rounding (quantized
// normals, points moved by <= e), asserted to be at most one 8-bit step per channel.
//
// The bound on the mean FLIP, pixel by pixel (oneStepFlipBound): a pixel within FLIP's support
// radius of the band may have any error (<= 1, FLIP's range). Every other pixel sees, in its
// support, the reference with each channel moved by -1, 0 or +1. Its error is computed, not
// guessed: our ldrFlip of the reference against copies moved by one step in each of the 26
// non-zero sign patterns of (R, G, B), every pixel alike, and again with the sign flipped from one
// pixel to the next (a checkerboard); the pixel is costed at the largest of these 52 errors. Why
// these: FLIP's colour term compares the images after CSF filters whose kernels are positive and
// sum to 1 (flip.cpp), so a filtered difference is at most the largest one in the support, and
// reaches it where every pixel moves alike: the uniform patterns, one per direction of colour
// space, give the colour term its largest values (its nonlinear rest, Lab and HyAB, is evaluated
// exactly, at the reference's own colours). The feature term compares edge and point responses
// of the achromatic channel, which a one-step image drives hardest where the step alternates: the
// checkerboards. That these 52 are the worst of all 3^(3n) sign patterns of a support is the one
// step this does not prove (FLIP is not monotone in the difference). Measured on lavapipe: 12
// pixels differ by one step, the band is empty; the bound is 0.060 and each copy's mean 2.9e-4.
TEST_F(GltfCompressed, CopiesRenderWithinTheFlipBoundOfTheirQuantization) {
  const fs::path source = kSources[2];
  hb::GltfLoadWarnings quiet;
  const hb::Scene plain = hb::loadGltf(source.string(), &quiet);
  ASSERT_FALSE(plain.cameras.empty());
  glm::vec3 lo, hi;
  plain.bounds(lo, hi);
  const double e = std::sqrt(3.0) / 2.0 * glm::length(glm::dvec3(hi - lo)) / ((1 << kPositionBits) - 1);
  const double width = 64, height = 48;
  const hb::Camera& camera = plain.cameras[0];
  const double f = height / 2.0 / std::tan(camera.yfov / 2.0);
  const std::vector<glm::vec3> triangles = plain.worldTriangles();
  std::vector<glm::dvec2> projected(triangles.size());
  double zmin = INFINITY;
  for (size_t i = 0; i < triangles.size(); ++i) {
    const glm::dvec4 v = glm::dmat4(camera.view) * glm::dvec4(glm::dvec3(triangles[i]), 1.0);
    zmin = std::min(zmin, -v.z);
    projected[i] = {width / 2 + f * v.x / -v.z, height / 2 - f * v.y / -v.z};
  }
  ASSERT_GT(zmin, e) << "a vertex lies behind the camera: the projection bound below does not hold";
  const double delta = f * e / (zmin - e) * (1.0 + std::hypot(width, height) / 2.0 / f);
  const int radius = hb::flipSupportRadius(hb::kDefaultPpd);
  std::vector<uint8_t> band(64 * 48, 0), near(64 * 48, 0);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      for (size_t t = 0; t + 2 < projected.size() && !band[y * 64 + x]; t += 3)
        for (int k = 0; k < 3; ++k)
          if (segmentDistance({x + 0.5, y + 0.5}, projected[t + k], projected[t + (k + 1) % 3]) <= delta)
            band[y * 64 + x] = 1;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      if (band[y * 64 + x])
        for (int dy = -radius; dy <= radius; ++dy)
          for (int dx = -radius; dx <= radius; ++dx)
            if (x + dx >= 0 && x + dx < 64 && y + dy >= 0 && y + dy < 48) near[(y + dy) * 64 + x + dx] = 1;
  const hb::ImageRGBA8 reference = renderColor(source);
  const double bound = oneStepFlipBound(reference, near);
  for (const Copy& copy : compress(source)) {
    SCOPED_TRACE(copy.path.filename().string());
    const hb::ImageRGBA8 test = renderColor(copy.path);
    const hb::FlipResult flip = hb::ldrFlip(reference, test);
    int worstOutside = 0;
    for (size_t p = 0; p < 64 * 48; ++p)
      for (int c = 0; c < 3; ++c)
        if (!band[p])
          worstOutside = std::max(worstOutside, std::abs(int(reference.px[p * 4 + c]) - int(test.px[p * 4 + c])));
    EXPECT_LE(worstOutside, 1);
    EXPECT_LE(flip.mean, bound) << "pixels near the band " << std::count(near.begin(), near.end(), 1) << ", delta "
                                << delta << " px";
  }
}

// WebP and AVIF copies of a PNG-textured scene, made by @gltf-transform/cli (sharp's encoders) in
// lossless mode: the validator is clean on them, they load with no warning (scene info prints
// nothing on stderr), their texels decode (libwebp, libavif) to the PNG's exactly, their triangles
// are the source's, and so they render the very same image: with the same triangles and texels the
// renderer has the same input, so the derived bound on the difference is zero.
TEST_F(GltfCompressed, WebpAndAvifCopiesOfAPngTexturedSceneDecodeToItsTexelsAndRenderAlike) {
  // depth-step as exported (it has TEXCOORD_0) with a 4x4 base colour texture written here as PNG:
  // 16 different colours, so that a swapped channel or a texel out of place shows.
  nlohmann::json doc = nlohmann::json::parse(hb::testing::readFile(kSources[2]));
  hb::ImageRGBA8 texels{4, 4, std::vector<uint8_t>(4 * 4 * 4, 255)};
  for (uint32_t p = 0; p < 16; ++p) {
    texels.px[p * 4 + 0] = static_cast<uint8_t>(16 * p);
    texels.px[p * 4 + 1] = static_cast<uint8_t>(255 - 12 * p);
    texels.px[p * 4 + 2] = static_cast<uint8_t>((97 * p) % 256);
  }
  hb::writePng(dir / "texture.png", texels);
  doc["images"] = {{{"uri", "texture.png"}}};
  doc["textures"] = {{{"source", 0}}};
  doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  const fs::path textured = dir / "textured.gltf";
  hb::testing::writeFile(textured, doc.dump());
  hb::GltfLoadWarnings none;
  const hb::Scene png = hb::loadGltf(textured.string(), &none);
  ASSERT_EQ(png.textures.size(), 1u);
  ASSERT_EQ(png.textures[0].rgba, texels.px);
  const hb::ImageRGBA8 reference = renderColor(textured);
  for (const char* format : {"webp", "avif"}) {
    const fs::path copy = dir / (std::string("textured-") + format + ".glb");
    SCOPED_TRACE(copy.filename().string());
    shell((kBin / "gltf-transform").string() + " " + format + " --lossless true " + textured.string() + " " +
          copy.string());
    // The validator (2.0.0-dev.3.10) does not know EXT_texture_avif: it warns that image/avif is not
    // a MIME type it allows and that it does not recognise the image, whatever the file.
    if (std::string(format) == "webp")
      shell("node " + (kSource / "scripts/validate-gltf.mjs").string() + " " + copy.string());
    EXPECT_NE(hb::testing::readFile(copy).find(std::string("EXT_texture_") + format), std::string::npos);
    const RunResult r = run({"scene", "info", copy.string()});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
    hb::GltfLoadWarnings warnings;
    const hb::Scene decoded = hb::loadGltf(copy.string(), &warnings);
    EXPECT_TRUE(warnings.messages.empty()) << warnings.messages[0];
    ASSERT_EQ(decoded.textures.size(), 1u);
    EXPECT_EQ(decoded.textures[0].rgba, texels.px);
    EXPECT_EQ(decoded.worldTriangles(), png.worldTriangles());
    const hb::ImageRGBA8 image = renderColor(copy);
    EXPECT_EQ(hb::ldrFlip(reference, image).mean, 0.0);
    EXPECT_TRUE(image.px == reference.px);
  }
}

}  // namespace
}  // namespace gltf_compressed_test
