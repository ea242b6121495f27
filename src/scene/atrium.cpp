#include "scene/atrium.h"
#include "base/numbers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "base/errors.h"
#include "base/splitmix64.h"
#include "scene/camera.h"
#include "scene/mesh_builder.h"

namespace hb {

namespace {

// ---- Layout (metres). Sponza after its node scale: 29.8 x 12.4 x 18.3 (the Crytek Sponza glTF's bounds).
constexpr double kHalfX = 14.9, kHalfZ = 9.15, kFloorY = -0.2, kTopY = 12.2;
constexpr double kWall = 0.4;  // outer wall thickness
constexpr double kInnerX = kHalfX - kWall, kInnerZ = kHalfZ - kWall;
constexpr double kColonnadeZ = 4.0;  // |z| of both colonnades
constexpr int kGroundColumns = 9, kUpperColumns = 17;
constexpr double kGroundPitch = 3.0, kUpperPitch = 1.5, kFirstColumnX = -12.0;
constexpr double kGroundSpringY = 4.3, kGalleryFloorY = 5.9, kUpperSpringY = 9.0;

// ---- Materials: exactly 25, in this order.
enum MaterialId : uint32_t {
  kFloorStone,
  kWallBrick,
  kWallPlaster,
  kColumnStone,
  kColumnUpperStone,
  kColumnTrim,
  kArchStone,
  kGallerySlab,
  kBalustradeMarble,
  kRoofStone,
  kFabricRed,
  kFabricGreen,
  kFabricBlue,
  kFabricGold,
  kVaseTerracotta,
  kVaseGlazed,
  kSoil,
  kLeaf,
  kStem,
  kLionStone,
  kBeadStone,
  kMetalBronze,
  kMetalGold,
  kMetalIron,
  kMetalBrass,
  kMaterialCount
};
static_assert(kMaterialCount == 25);
enum TextureId : int { kCheckerTexture, kBrickTexture, kMetalRoughnessTexture };

uint32_t tess(double base, double q, uint32_t minimum) {
  return std::max<uint32_t>(minimum, uint32_t(std::lround(base * q)));
}

Texture makeTexture(const char* name, bool srgb, glm::u8vec4 (*texel)(uint32_t x, uint32_t y)) {
  Texture t;
  t.name = name;
  t.width = t.height = 64;
  t.srgb = srgb;
  t.rgba.reserve(64 * 64 * 4);
  for (uint32_t y = 0; y < 64; ++y)
    for (uint32_t x = 0; x < 64; ++x) {
      const glm::u8vec4 c = texel(x, y);
      t.rgba.insert(t.rgba.end(), {c.r, c.g, c.b, c.a});
    }
  return t;
}

void addTextures(Scene& scene) {
  // 8x8-texel checker of two stone tones.
  scene.textures.push_back(makeTexture("checker-64", true, [](uint32_t x, uint32_t y) {
    return ((x / 8 + y / 8) % 2) ? glm::u8vec4(200, 192, 176, 255) : glm::u8vec4(150, 140, 125, 255);
  }));
  // 16x8-texel bricks, 1-texel mortar, every other course offset by half a brick.
  scene.textures.push_back(makeTexture("brick-64", true, [](uint32_t x, uint32_t y) {
    const uint32_t course = y / 8, xs = (x + (course % 2) * 8) % 16;
    const bool mortar = y % 8 == 0 || xs == 0;
    return mortar ? glm::u8vec4(205, 200, 190, 255) : glm::u8vec4(170 + 10 * (course % 3), 80, 60, 255);
  }));
  // glTF metallic-roughness: G = roughness (bands 0.25..0.88), B = metallic (1); linear.
  scene.textures.push_back(makeTexture("metal-roughness-64", false, [](uint32_t x, uint32_t y) {
    return glm::u8vec4(255, uint8_t(64 + 10 * ((x / 4 + y / 16) % 17)), 255, 255);
  }));
}

void addMaterials(Scene& scene) {
  struct Spec {
    const char* name;
    glm::vec3 color;
    float metallic, roughness;
    int baseTex = -1, mrTex = -1;
    bool doubleSided = false;
  };
  const Spec specs[kMaterialCount] = {
      {"floor-stone", {0.80f, 0.78f, 0.72f}, 0, 0.8f, kCheckerTexture},
      {"wall-brick", {0.75f, 0.55f, 0.45f}, 0, 0.9f, kBrickTexture},
      {"wall-plaster", {0.85f, 0.82f, 0.75f}, 0, 0.9f},
      {"column-stone", {0.78f, 0.74f, 0.66f}, 0, 0.7f},
      {"column-upper-stone", {0.72f, 0.70f, 0.64f}, 0, 0.7f},
      {"column-trim", {0.90f, 0.88f, 0.80f}, 0, 0.5f},
      {"arch-stone", {0.76f, 0.72f, 0.64f}, 0, 0.75f, kBrickTexture},
      {"gallery-slab", {0.70f, 0.68f, 0.62f}, 0, 0.85f},
      {"balustrade-marble", {0.92f, 0.92f, 0.90f}, 0, 0.3f},
      {"roof-stone", {0.60f, 0.58f, 0.55f}, 0, 0.9f},
      {"fabric-red", {0.70f, 0.08f, 0.06f}, 0, 0.95f, -1, -1, true},
      {"fabric-green", {0.10f, 0.45f, 0.12f}, 0, 0.95f, -1, -1, true},
      {"fabric-blue", {0.08f, 0.15f, 0.60f}, 0, 0.95f, -1, -1, true},
      {"fabric-gold", {0.80f, 0.60f, 0.15f}, 0, 0.9f, -1, -1, true},
      {"vase-terracotta", {0.72f, 0.36f, 0.20f}, 0, 0.8f},
      {"vase-glazed", {0.20f, 0.35f, 0.55f}, 0, 0.25f},
      {"soil", {0.25f, 0.17f, 0.10f}, 0, 1.0f},
      {"leaf", {0.15f, 0.45f, 0.10f}, 0, 0.6f},
      {"stem", {0.30f, 0.35f, 0.12f}, 0, 0.7f},
      {"lion-stone", {0.80f, 0.76f, 0.68f}, 0, 0.6f},
      {"bead-stone", {0.85f, 0.80f, 0.70f}, 0, 0.5f},
      {"metal-bronze", {0.80f, 0.50f, 0.25f}, 1, 0.35f},
      {"metal-gold", {1.00f, 0.77f, 0.34f}, 1, 0.15f},
      {"metal-iron", {0.56f, 0.57f, 0.58f}, 1, 1.0f, -1, kMetalRoughnessTexture},
      {"metal-brass", {0.90f, 0.70f, 0.40f}, 1, 0.45f},
  };
  for (const Spec& s : specs) {
    Material m;
    m.name = s.name;
    m.baseColorFactor = glm::vec4(s.color, 1.0f);
    m.metallicFactor = s.metallic;
    m.roughnessFactor = s.roughness;
    m.baseColorTexture = s.baseTex;
    m.metallicRoughnessTexture = s.mrTex;
    m.doubleSided = s.doubleSided;
    scene.materials.push_back(m);
  }
}

glm::dmat4 translate(glm::dvec3 t) { return glm::translate(glm::dmat4(1.0), t); }
glm::dmat4 scale(glm::dvec3 s) { return glm::scale(glm::dmat4(1.0), s); }
glm::dmat4 rotate(double angle, glm::dvec3 axis) { return glm::rotate(glm::dmat4(1.0), angle, axis); }

// Axis-aligned box given in a frame that is a translation plus a multiple of 90 degrees about y.
void addBoxInFrame(MeshBuilder& mb, uint32_t material, const glm::dmat4& frame, glm::dvec3 lo, glm::dvec3 hi) {
  const glm::dvec3 a(frame * glm::dvec4(lo, 1.0)), b(frame * glm::dvec4(hi, 1.0));
  addBox(mb, material, glm::min(a, b), glm::max(a, b));
}

// Closed arch spandrel: the block [cx-w/2, cx+w/2] x [y0, y0+h] x [zc-d/2, zc+d/2] minus the
// half-disc of radius r (r < w/2, r < h) centred at (cx, y0). The front and back faces are cut
// into quads along rays from the disc centre, from the arch curve to the block's outline; the
// block's two top corners are among the ray angles so that every outline piece lies on one side.
void addArchSpandrel(MeshBuilder& mb, uint32_t material, double cx, double y0, double zc, double w, double h, double r,
                     double d, uint32_t n) {
  HB_ASSERT(r < w / 2 && r < h && n >= 2);
  const double cornerAngle = std::atan2(h, w / 2);
  std::vector<double> angles;
  for (uint32_t k = 0; k <= n; ++k) angles.push_back(kPi * k / n);
  angles.push_back(cornerAngle);
  angles.push_back(kPi - cornerAngle);
  std::sort(angles.begin(), angles.end());
  angles.erase(std::unique(angles.begin(), angles.end(), [](double a, double b) { return b - a < 1e-6; }),
               angles.end());
  const size_t m = angles.size();
  std::vector<glm::dvec2> arch(m), outline(m), archNormal(m);
  for (size_t i = 0; i < m; ++i) {
    const double c = std::cos(angles[i]), s = std::sin(angles[i]);
    arch[i] = {cx + r * c, y0 + r * s};
    archNormal[i] = {-c, -s};  // the intrados faces the disc centre
    // Where the ray leaves the block; the corners exactly, to keep the top and sides straight.
    if (std::abs(angles[i] - cornerAngle) < 1e-6)
      outline[i] = {cx + w / 2, y0 + h};
    else if (std::abs(angles[i] - (kPi - cornerAngle)) < 1e-6)
      outline[i] = {cx - w / 2, y0 + h};
    else {
      const double tSide = std::abs(c) > 1e-12 ? (w / 2) / std::abs(c) : 1e300;
      const double tTop = s > 1e-12 ? h / s : 1e300;
      const double t = std::min(tSide, tTop);
      outline[i] = {cx + t * c, y0 + t * s};
    }
  }
  auto vtx = [&](glm::dvec2 p, double z, glm::dvec3 nrm) {
    return mb.vertex(material, Vertex{glm::vec3(p.x, p.y, z), glm::vec3(nrm), glm::vec2(p.x * 0.5, p.y * 0.5)});
  };
  // Front (courtyard or gallery side) and back caps.
  for (int side = 0; side < 2; ++side) {
    const double z = side ? zc + d / 2 : zc - d / 2;
    const glm::dvec3 nrm(0, 0, side ? 1 : -1);
    std::vector<uint32_t> a(m), o(m);
    for (size_t i = 0; i < m; ++i) a[i] = vtx(arch[i], z, nrm), o[i] = vtx(outline[i], z, nrm);
    for (size_t i = 0; i + 1 < m; ++i) mb.quad(material, a[i], a[i + 1], o[i + 1], o[i]);
  }
  // Side faces: a quad per outline edge from front to back, flat normals except on the intrados.
  auto sideQuad = [&](glm::dvec2 p, glm::dvec2 q, glm::dvec2 np, glm::dvec2 nq) {
    const double z0 = zc - d / 2, z1 = zc + d / 2;
    mb.quad(material, vtx(p, z0, {np, 0}), vtx(q, z0, {nq, 0}), vtx(q, z1, {nq, 0}), vtx(p, z1, {np, 0}));
  };
  for (size_t i = 0; i + 1 < m; ++i) {
    const glm::dvec2 e = outline[i + 1] - outline[i];
    const glm::dvec2 nOut = glm::normalize(glm::dvec2(e.y, -e.x));  // outline runs counter-clockwise
    sideQuad(outline[i], outline[i + 1], nOut, nOut);
    sideQuad(arch[i], arch[i + 1], archNormal[i], archNormal[i + 1]);
  }
  sideQuad(arch[0], outline[0], {0, -1}, {0, -1});          // bottom right, on the capital
  sideQuad(arch[m - 1], outline[m - 1], {0, -1}, {0, -1});  // bottom left
}

double groundColumnX(int k) { return kFirstColumnX + kGroundPitch * k; }
double upperColumnX(int k) { return kFirstColumnX + kUpperPitch * k; }

// Floor, outer walls, gallery floors and roofs, balustrades: closed boxes (~200 triangles).
void addStructure(Scene& scene) {
  MeshBuilder mb("structure");
  addBox(mb, kFloorStone, {-kHalfX, kFloorY, -kHalfZ}, {kHalfX, 0.0, kHalfZ}, 0.5);
  for (int s : {-1, 1}) {
    addBox(mb, kWallBrick, {-kHalfX, 0.0, s > 0 ? kInnerZ : -kHalfZ}, {kHalfX, kTopY, s > 0 ? kHalfZ : -kInnerZ}, 0.5);
    addBox(mb, kWallBrick, {s > 0 ? kInnerX : -kHalfX, 0.0, -kInnerZ}, {s > 0 ? kHalfX : -kInnerX, kTopY, kInnerZ},
           0.5);
    auto zs = [s](double a, double b) { return std::pair(std::min(s * a, s * b), std::max(s * a, s * b)); };
    auto [z0, z1] = zs(kColonnadeZ - 0.3, kInnerZ);
    addBox(mb, kGallerySlab, {-kInnerX, kGalleryFloorY - 0.3, z0}, {kInnerX, kGalleryFloorY, z1});
    auto [b0, b1] = zs(kColonnadeZ - 0.1, kColonnadeZ + 0.1);
    addBox(mb, kBalustradeMarble, {groundColumnX(0), kGalleryFloorY, b0},
           {-groundColumnX(0), kGalleryFloorY + 1.0, b1});
    auto [t0, t1] = zs(kColonnadeZ - 0.3, kColonnadeZ + 0.3);
    addBox(mb, kWallPlaster, {-kInnerX, 9.75, t0}, {kInnerX, 11.3, t1});
    auto [r0, r1] = zs(kColonnadeZ + 0.2, kInnerZ);
    addBox(mb, kRoofStone, {-kInnerX, 11.0, r0}, {kInnerX, 11.4, r1});
  }
  mb.appendTo(scene);
}

void addColumns(Scene& scene, double q) {
  MeshBuilder mb("columns");
  const uint32_t gSeg = tess(48, q, 8), gRings = tess(12, q, 1), upSeg = tess(24, q, 6), upRings = tess(8, q, 1);
  const uint32_t torusSeg = tess(32, q, 6), torusTube = tess(8, q, 3);
  for (double z : {-kColonnadeZ, kColonnadeZ}) {
    for (int k = 0; k < kGroundColumns; ++k) {
      const double x = groundColumnX(k);
      addBox(mb, kColumnTrim, {x - 0.4, 0.0, z - 0.4}, {x + 0.4, 0.3, z + 0.4});
      addCylinder(mb, kColumnStone, translate({x, 0.3, z}), 0.3, 3.7, gSeg, gRings);
      addTorus(mb, kMetalBronze, translate({x, 0.38, z}), 0.3, 0.05, torusSeg, torusTube);
      addTorus(mb, kMetalBronze, translate({x, 3.92, z}), 0.3, 0.05, torusSeg, torusTube);
      addBox(mb, kColumnTrim, {x - 0.45, 4.0, z - 0.45}, {x + 0.45, kGroundSpringY, z + 0.45});
    }
    for (int k = 0; k < kUpperColumns; ++k) {
      const double x = upperColumnX(k);
      addBox(mb, kColumnTrim, {x - 0.22, kGalleryFloorY, z - 0.22}, {x + 0.22, kGalleryFloorY + 0.2, z + 0.22});
      addCylinder(mb, kColumnUpperStone, translate({x, kGalleryFloorY + 0.2, z}), 0.17, 2.7, upSeg, upRings);
      addBox(mb, kColumnTrim, {x - 0.25, 8.8, z - 0.25}, {x + 0.25, kUpperSpringY, z + 0.25});
    }
  }
  mb.appendTo(scene);
}

// Arches between neighbouring columns on both storeys, and strings of small beads round the
// arches' courtyard faces.
void addArches(Scene& scene, double q) {
  MeshBuilder arches("arches"), beads("arch-beads");
  const uint32_t gN = tess(32, q, 4), upN = tess(20, q, 4);
  const uint32_t beadSeg = tess(8, q, 4), beadBands = tess(4, q, 2) + 1;
  struct Storey {
    int count;
    double pitch, springY, radius, height, depth, beadRadius, beadSpacing;
    uint32_t n;
  };
  const Storey storeys[2] = {{kGroundColumns - 1, kGroundPitch, kGroundSpringY, 1.05, 1.4, 0.8, 0.035, 0.1, gN},
                             {kUpperColumns - 1, kUpperPitch, kUpperSpringY, 0.5, 0.8, 0.5, 0.028, 0.08, upN}};
  for (double z : {-kColonnadeZ, kColonnadeZ}) {
    const double toCourtyard = z > 0 ? -1.0 : 1.0;
    for (const Storey& s : storeys)
      for (int k = 0; k < s.count; ++k) {
        const double cx = kFirstColumnX + s.pitch * (k + 0.5);
        addArchSpandrel(arches, kArchStone, cx, s.springY, z, s.pitch, s.height, s.radius, s.depth, s.n);
        // Beads sit on the courtyard face just outside the arch curve, sunk 60 % into it.
        const double path = s.radius + s.beadRadius + 0.01;
        const int count = int(std::lround(kPi * path / s.beadSpacing)) + 1;
        const double faceZ = z + toCourtyard * s.depth / 2;
        for (int b = 0; b < count; ++b) {
          const double a = kPi * b / (count - 1);
          const glm::dvec3 c(cx + path * std::cos(a), s.springY + path * std::sin(a),
                             faceZ + toCourtyard * 0.4 * s.beadRadius);
          addSphere(beads, kBeadStone, translate(c) * scale(glm::dvec3(s.beadRadius)), beadSeg, beadBands);
        }
      }
  }
  arches.appendTo(scene);
  beads.appendTo(scene);
}

// Wavy cloth hanging in every other ground-floor bay, just behind the arches, and brass rods.
void addCurtains(Scene& scene, double q) {
  MeshBuilder mb("curtains");
  const uint32_t nu = tess(36, q, 2), nv = tess(72, q, 2);
  const uint32_t fabrics[4] = {kFabricRed, kFabricGreen, kFabricBlue, kFabricGold};
  int index = 0;
  for (double side : {-1.0, 1.0})
    for (int k = 0; k < kGroundColumns - 1; k += 2, ++index) {
      const double cx = groundColumnX(k) + kGroundPitch / 2, z0 = side * (kColonnadeZ + 0.55);
      const double width = 2.4, top = 5.55, length = 4.55, amplitude = 0.12, folds = 3.0 + index % 3;
      // P(u, v) = (cx - w/2 + w u, top - L v, z0 + A e(v) sin(2 pi f u)), e(v) = 0.3 + 0.7 v: the
      // folds deepen towards the hem. Normal = P_u x P_v, computed analytically.
      addSheet(mb, fabrics[index % 4], nu, nv, [&](double u, double v) {
        const double k2 = 2 * kPi * folds, e = 0.3 + 0.7 * v;
        const glm::dvec3 p(cx - width / 2 + width * u, top - length * v, z0 + amplitude * e * std::sin(k2 * u));
        const glm::dvec3 pu(width, 0, amplitude * e * k2 * std::cos(k2 * u));
        const glm::dvec3 pv(0, -length, amplitude * 0.7 * std::sin(k2 * u));
        const glm::dvec3 n = glm::normalize(glm::cross(pu, pv));
        return Vertex{glm::vec3(p), glm::vec3(n), glm::vec2(u * 2, v * 4)};
      });
      addCylinder(mb, kMetalBrass, translate({cx - 1.3, top + 0.02, z0}) * rotate(-kPi / 2, {0, 0, 1}), 0.025, 2.6,
                  tess(12, q, 4), 1);
    }
  mb.appendTo(scene);
}

// Vases with plants along both sides of the courtyard, one per ground-floor bay.
void addVases(Scene& scene, double q) {
  MeshBuilder vases("vases"), plants("plants");
  const uint32_t seg = tess(32, q, 6), bodyBands = tess(16, q, 2);
  const uint32_t leafSeg = tess(8, q, 4), leafBands = tess(4, q, 2) + 1;
  // Profile in (r, y), counter-clockwise (solid on the left), one section per crease.
  std::vector<glm::dvec2> body;
  for (uint32_t i = 0; i <= bodyBands; ++i) {
    const double t = double(i) / bodyBands;
    body.push_back({0.11 + 0.2 * std::sin(kPi * t) * (1 - 0.4 * t) + 0.05 * t * t * t, 0.06 + 0.89 * t});
  }
  body.front() = {0.11, 0.06};  // the exact end points of the neighbouring sections: closed seams
  body.back() = {0.16, 0.95};
  const std::vector<std::vector<glm::dvec2>> shell = {{{0, 0}, {0.18, 0}},          {{0.18, 0}, {0.18, 0.06}},
                                                      {{0.18, 0.06}, {0.11, 0.06}}, body,
                                                      {{0.16, 0.95}, {0.13, 0.95}}, {{0.13, 0.95}, {0.13, 0.9}}};
  const std::vector<std::vector<glm::dvec2>> soil = {{{0.13, 0.9}, {0, 0.9}}};
  SplitMix64 rng{0xA7121Aull};  // fixed: the geometry does not depend on AtriumParams::seed
  int index = 0;
  for (double side : {-1.0, 1.0})
    for (int k = 0; k < kGroundColumns - 1; ++k, ++index) {
      const double s = rng.uniform(1.0, 1.3);
      const glm::dvec3 base(groundColumnX(k) + kGroundPitch / 2, 0.0, side * (kColonnadeZ - 1.0));
      const glm::dmat4 frame = translate(base) * scale(glm::dvec3(s));
      addLathe(vases, index % 2 ? kVaseGlazed : kVaseTerracotta, shell, seg, frame);
      addLathe(vases, kSoil, soil, seg, frame);
      addTorus(vases, kMetalIron, frame * translate({0, 0.8, 0}), 0.215, 0.012, seg, tess(6, q, 3));
      // Plant: a stem and 24 leaves (flat ellipsoids) on a golden-angle spiral.
      const double stemTop = 0.5 + 0.2 * rng.uniform();
      addCylinder(plants, kStem, frame * translate({0, 0.85, 0}), 0.015, stemTop, tess(6, q, 3), 1);
      for (int leaf = 0; leaf < 24; ++leaf) {
        const double phi = 2.399963229728653 * leaf, t = leaf / 24.0;
        const double tilt = rng.uniform(-0.6, 0.5);
        const glm::dvec3 dir(std::cos(phi), 0, -std::sin(phi));  // local +x after rotate(phi, y)
        const glm::dmat4 m = frame * translate(glm::dvec3(0, 0.9 + stemTop * (1 - t), 0) + dir * 0.12) *
                             rotate(phi, {0, 1, 0}) * rotate(tilt, {0, 0, 1}) * scale({0.13, 0.012, 0.045});
        addSphere(plants, kLeaf, m, leafSeg, leafBands);
      }
    }
  vases.appendTo(scene);
  plants.appendTo(scene);
}

// Lion-head ornaments on the inner faces of both end walls, at both storeys. Local frame: the
// wall is the plane z = 0, the head faces +z.
void addLionHeads(Scene& scene, double q) {
  MeshBuilder mb("lion-heads");
  const glm::dmat4 toZAxis = rotate(kPi / 2, {1, 0, 0});  // lathe axis (y) -> local z
  for (double side : {-1.0, 1.0})
    for (double y : {2.6, 7.6}) {
      // rotate(+90 deg about y) maps local +z to world +x: the wall at x = -kInnerX faces +x.
      const glm::dmat4 frame = translate({side * kInnerX, y, 0.0}) * rotate(-side * kPi / 2, {0, 1, 0});
      addBoxInFrame(mb, kLionStone, frame, {-0.6, -0.6, -0.05}, {0.6, 0.6, 0.06});
      addTorus(mb, kLionStone, frame * translate({0, 0, 0.12}) * toZAxis, 0.42, 0.1, tess(40, q, 6), tess(12, q, 3));
      for (int c = 0; c < 20; ++c) {
        const double a = 2 * kPi * c / 20;
        addSphere(mb, kLionStone,
                  frame * translate({0.55 * std::cos(a), 0.55 * std::sin(a), 0.1}) * scale(glm::dvec3(0.07)),
                  tess(10, q, 4), tess(5, q, 2));
      }
      addSphere(mb, kLionStone, frame * translate({0, 0, 0.15}) * scale({0.3, 0.36, 0.22}), tess(32, q, 6),
                tess(16, q, 3));
      addSphere(mb, kLionStone, frame * translate({0, -0.1, 0.34}) * scale({0.12, 0.09, 0.1}), tess(16, q, 4),
                tess(8, q, 2));
      for (double ex : {-0.11, 0.11}) {
        addSphere(mb, kMetalIron, frame * translate({ex, 0.1, 0.33}) * scale(glm::dvec3(0.04)), tess(12, q, 4),
                  tess(6, q, 2));
        addSphere(mb, kLionStone, frame * translate({ex * 2.5, 0.3, 0.12}) * scale({0.08, 0.1, 0.05}), tess(12, q, 4),
                  tess(6, q, 2));
      }
      addTorus(mb, kMetalGold, frame * translate({0, -0.38, 0.2}) * toZAxis, 0.14, 0.022, tess(32, q, 6),
               tess(10, q, 3));
    }
  mb.appendTo(scene);
}

void addLights(Scene& scene, const AtriumParams& params) {
  SplitMix64 rng{0x5EED0000ull ^ params.seed};
  for (uint32_t i = 0; i < params.lightCount; ++i) {
    Light l;
    char name[32];
    std::snprintf(name, sizeof name, "light-%02u", i);
    l.name = name;
    // Three regions in turn, clear of every solid: courtyard centre (|z| <= 2.5; vases and
    // plants keep to |z| >= 2.6), ground gallery (behind the curtains, |z| >= 5.2) and upper
    // gallery (above its floor at 5.9 m, behind the balustrade and columns at |z| <= 4.2).
    const double x = rng.uniform(-11.0, 11.0), side = rng.uniform() < 0.5 ? -1.0 : 1.0;
    glm::dvec3 p;
    switch (i % 3) {
      case 0: p = {x, rng.uniform(1.5, 8.0), rng.uniform(-2.5, 2.5)}; break;
      case 1: p = {x, rng.uniform(1.0, 5.0), side * rng.uniform(5.2, 8.2)}; break;
      default: p = {x, rng.uniform(6.5, 8.0), side * rng.uniform(5.2, 8.2)}; break;
    }
    l.position = glm::vec3(p);
    const glm::dvec3 c(rng.uniform(0.55, 1.0), rng.uniform(0.55, 1.0), rng.uniform(0.55, 1.0));
    l.color = glm::vec3(c / std::max({c.r, c.g, c.b}));
    l.intensity = float(rng.uniform(5.0, 60.0));  // candela
    const double explicitRange = rng.uniform(3.0, 12.0);
    if (params.lightRangeMax > 0.0) {
      // The same draw mapped onto [min, max], so that the sequence (and every other light
      // property) does not change.
      l.rangeFromEq41 = false;
      l.range =
          float(params.lightRangeMin + (explicitRange - 3.0) / 9.0 * (params.lightRangeMax - params.lightRangeMin));
    } else {
      l.rangeFromEq41 = i % 5 == 4;  // two in ten take thesis eq. 4.1
      l.range = float(l.rangeFromEq41 ? rangeFromIntensity(l.intensity) : explicitRange);
    }
    scene.lights.push_back(l);
  }
}

}  // namespace

Scene makeAtrium(const AtriumParams& params) {
  if (!(params.triangleScale >= 0.25 && params.triangleScale <= 64.0))
    throw InputError("atrium: triangleScale " + std::to_string(params.triangleScale) +
                     " is out of range; use a value in [0.25, 64]");
  if (params.lightRangeMax > 0.0 && !(params.lightRangeMin > 0.0 && params.lightRangeMin <= params.lightRangeMax))
    throw InputError("atrium: light range [" + std::to_string(params.lightRangeMin) + ", " +
                     std::to_string(params.lightRangeMax) + "] is not a range; use 0 < min <= max");
  if (params.lightCount > 4096)
    throw InputError("atrium: lightCount " + std::to_string(params.lightCount) + " is too large; use at most 4096");
  // Curved parts get sqrt(scale) more divisions in each of their two directions.
  const double q = std::sqrt(params.triangleScale);
  Scene scene;
  scene.name = "atrium";
  addTextures(scene);
  addMaterials(scene);
  addStructure(scene);
  addColumns(scene, q);
  addArches(scene, q);
  addCurtains(scene, q);
  addVases(scene, q);
  addLionHeads(scene, q);
  addLights(scene, params);
  // A sky above the open courtyard: bluish ambient light, which reaches the frame only where a
  // config calls for ambient occlusion (scene.h Ambient).
  scene.ambient = Ambient{{0.55f, 0.65f, 0.85f}, 0.3f};

  Camera cam;
  cam.name = "central";
  cam.view = lookAt({-8.0f, 1.8f, 0.0f}, {10.0f, 3.0f, 0.0f}, {0.0f, 1.0f, 0.0f});
  cam.yfov = float(kPi / 3);
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  scene.cameras.push_back(cam);
  return scene;
}

}  // namespace hb
