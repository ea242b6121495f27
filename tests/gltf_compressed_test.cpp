// Compressed glTF as it comes from the tools people use (issue #35): committed scenes compressed at
// test time with npm's gltfpack (EXT_meshopt_compression + KHR_mesh_quantization, its defaults)
// and @gltf-transform/cli (KHR_draco_mesh_compression), checked by the Khronos validator, loaded
// and rendered on the present device against their sources; truncated and corrupt streams are
// exit 2 with one line naming the mesh and the extension.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "base/image_io.h"
#include "reference/flip.h"
#include "scene/gltf/gltf_io.h"
#include "tool_process.h"

#ifndef HYBRIDBENCH_SOURCE_DIR
#error "HYBRIDBENCH_SOURCE_DIR must name the source tree (for scenes/ and tools/)"
#endif

// A named namespace: the tests build in unity batches, where anonymous namespaces of several files meet.
namespace gltf_compressed_test {
namespace {

namespace fs = std::filesystem;
using hb::testing::RunResult;

const fs::path kSource = HYBRIDBENCH_SOURCE_DIR;
const fs::path kBin = kSource / "tools/node_modules/.bin";

// Position bits of both tools' defaults: gltfpack -vp 14, gltf-transform draco --quantize-position 14.
constexpr int kPositionBits = 14;

// A real mesh made outside this repository (scenes/external/README.md), a generated room with a
// camera and a light, and an exported built-in (scenes/README.md).
const std::vector<fs::path> kSources = {kSource / "scenes/external/mcad-bearing.glb",
                                        kSource / "scenes/cornell-box.gltf", kSource / "scenes/depth-step.gltf"};

struct Copy {
  fs::path path;
  const char* extension;  // what `scene info` names
};

class GltfCompressed : public hb::testing::ToolTest {
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
    const Copy draco{dir / (stem + "-draco.glb"), "KHR_draco_mesh_compression"};
    // gltfpack -c: meshopt compression; its default quantization (positions 14 bits, normals 8,
    // texture coordinates 12).
    shell((kBin / "gltfpack").string() + " -c -i " + source.string() + " -o " + meshopt.path.string());
    shell((kBin / "gltf-transform").string() + " draco " + source.string() + " " + draco.path.string());
    return {meshopt, draco};
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
    glm::vec3 lo, hi;
    plain.bounds(lo, hi);
    const double e = std::sqrt(3.0) / 2.0 * glm::length(glm::dvec3(hi - lo)) / ((1 << kPositionBits) - 1);
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
};

// A stream cut short (its byteLength halved) or overwritten (0xFF from its 9th byte on, past
// Draco's header) is exit 2 with one line naming the file, the mesh and the extension.
TEST_F(GltfCompressed, ATruncatedOrCorruptStreamIsExit2NamingTheMeshAndTheExtension) {
  const std::vector<Copy> copies = compress(kSources[0]);
  ASSERT_EQ(copies.size(), 2u);
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
// source can change coverage: that band, grown by FLIP's support radius, bounds the pixels whose
// FLIP may be anything. The rest is shading rounding, bounded by one 8-bit step (asserted) and
// costed as one step everywhere. The one-step margin is the assumption here (FLIP is not proven
// monotone in the difference); measured on lavapipe: 12 pixels differ by one step, band empty.
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
  const double bandFraction = std::count(near.begin(), near.end(), 1) / (64.0 * 48.0);
  const hb::ImageRGBA8 reference = renderColor(source);
  for (const Copy& copy : compress(source)) {
    SCOPED_TRACE(copy.path.filename().string());
    const hb::ImageRGBA8 test = renderColor(copy.path);
    const hb::FlipResult flip = hb::ldrFlip(reference, test);
    // Outside the band no coverage changes: what differs there is shading rounding (quantized
    // normals, points moved by <= e), asserted to be at most one 8-bit step per channel.
    int worstOutside = 0;
    for (size_t p = 0; p < 64 * 48; ++p)
      for (int c = 0; c < 3; ++c)
        if (!band[p])
          worstOutside = std::max(worstOutside, std::abs(int(reference.px[p * 4 + c]) - int(test.px[p * 4 + c])));
    EXPECT_LE(worstOutside, 1);
    // Bound on the mean FLIP: the band's pixels and those within FLIP's support radius of them may
    // be anything (FLIP <= 1 each); every other pixel sees at most one step of difference in its
    // support, which costs no more than one step everywhere does: ldrFlip(reference, reference + 1).
    hb::ImageRGBA8 oneStep = reference;
    for (size_t i = 0; i < oneStep.px.size(); ++i)
      if (i % 4 != 3) oneStep.px[i] = static_cast<uint8_t>(oneStep.px[i] < 255 ? oneStep.px[i] + 1 : 254);
    const double bound = bandFraction + hb::ldrFlip(reference, oneStep).mean;
    EXPECT_LE(flip.mean, bound) << "band " << bandFraction << ", delta " << delta << " px";
  }
}

}  // namespace
}  // namespace gltf_compressed_test
