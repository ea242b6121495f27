#include "scene/hard_cases.h"
#include "base/numbers.h"

#include <random>

#include <algorithm>
#include <cmath>
#include <utility>

#include "base/errors.h"
#include "base/json_reader.h"
#include "scene/atrium.h"
#include "scene/camera.h"
#include "scene/mesh_builder.h"

namespace hb {

namespace {

constexpr uint32_t kGrey = 0;

Scene baseScene(const char* name) {
  Scene s;
  s.name = name;
  Material grey;
  grey.name = "grey";
  grey.baseColorFactor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
  grey.metallicFactor = 0.0f;
  grey.roughnessFactor = 0.5f;
  s.materials.push_back(grey);
  return s;
}

void addLight(Scene& s, glm::dvec3 position, double intensity, double range) {
  Light l;
  l.name = "light-" + std::to_string(s.lights.size());
  l.position = glm::vec3(position);
  l.intensity = float(intensity);
  l.range = float(range);
  s.lights.push_back(l);
}

void addCamera(Scene& s, glm::dvec3 eye, glm::dvec3 target, double znear = 0.1, double zfar = 1000.0) {
  Camera c;
  c.name = "main";
  // An up vector that is not parallel to the view direction.
  const glm::dvec3 up = std::abs(glm::normalize(target - eye).y) > 0.99 ? glm::dvec3(0, 0, -1) : glm::dvec3(0, 1, 0);
  c.view = lookAt(glm::vec3(eye), glm::vec3(target), glm::vec3(up));
  c.yfov = float(kPi / 3);
  c.znear = float(znear);
  c.zfar = float(zfar);
  s.cameras.push_back(c);
}

// How most cases end: the mesh added, one point light, the camera looking at `target`.
Scene finish(Scene s, MeshBuilder& mb, glm::dvec3 light, double intensity, double range, glm::dvec3 eye,
             glm::dvec3 target) {
  mb.appendTo(s);
  addLight(s, light, intensity, range);
  addCamera(s, eye, target);
  return s;
}

// Quad in the plane z = zPlane facing +z.
void addQuadZ(MeshBuilder& mb, uint32_t material, double x0, double x1, double y0, double y1, double zPlane) {
  addQuad(mb, material, {x0, y0, zPlane}, {x1, y0, zPlane}, {x1, y1, zPlane}, {x0, y1, zPlane}, {0, 0, 1});
}

// Quad in the plane y = yPlane facing +y, x and z in [-half, half] (moved by offset).
void addGround(MeshBuilder& mb, uint32_t material, double half, double yPlane, glm::dvec3 offset = {}) {
  addQuad(mb, material, offset + glm::dvec3(-half, yPlane, -half), offset + glm::dvec3(half, yPlane, -half),
          offset + glm::dvec3(half, yPlane, half), offset + glm::dvec3(-half, yPlane, half), {0, 1, 0});
}

}  // namespace

Scene makePlane() {
  Scene s = baseScene("plane");
  MeshBuilder mb("plane");
  addQuadZ(mb, kGrey, -5, 5, -5, 5, 0);
  return finish(std::move(s), mb, {1, 1, 3}, 20, 10, {0, 0, 5}, {0, 0, 0});
}

Scene makeDepthStep() {
  Scene s = baseScene("depth-step");
  MeshBuilder mb("depth-step");
  addQuadZ(mb, kGrey, -5, 0, -5, 5, 0);
  addQuadZ(mb, kGrey, 0, 5, -5, 5, -1);
  return finish(std::move(s), mb, {0, 1, 3}, 20, 10, {0, 0, 5}, {0, 0, 0});
}

Scene makeCube(glm::dvec3 offset) {
  Scene s = baseScene("cube");
  MeshBuilder mb("cube");
  addBox(mb, kGrey, offset + glm::dvec3(-0.5, 0.5, -0.5), offset + glm::dvec3(0.5, 1.5, 0.5));
  addGround(mb, kGrey, 4, 0, offset);
  return finish(std::move(s), mb, offset + glm::dvec3(2, 4, 1.5), 30, 15, offset + glm::dvec3(3, 3, 4),
                offset + glm::dvec3(0, 0.75, 0));
}

Scene makeTinyTriangles() {
  Scene s = baseScene("tiny-triangles");
  MeshBuilder mb("tiny-triangles");
  const double z = -10.0;
  const double pixel = 2 * 10.0 * std::tan(kPi / 6) / 1080;  // metres per pixel at 10 m, 1080 rows
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      const glm::dvec3 p(-5.0 + 0.1 * j, -2.0 + 0.1 * i, z), n(0, 0, 1);
      const uint32_t a = mb.vertex(kGrey, Vertex{glm::vec3(p), glm::vec3(n), {0, 0}});
      const uint32_t b = mb.vertex(kGrey, Vertex{glm::vec3(p + glm::dvec3(0.02, 0, 0)), glm::vec3(n), {1, 0}});
      const uint32_t c = mb.vertex(kGrey, Vertex{glm::vec3(p + glm::dvec3(0, 0.02, 0)), glm::vec3(n), {0, 1}});
      mb.triangle(kGrey, a, b, c);
    }
  for (int k = 0; k < 10; ++k) {
    const double x = 3.0 + 0.5 * k;
    addQuadZ(mb, kGrey, x, x + pixel, -2, 2, z);
  }
  return finish(std::move(s), mb, {0, 2, -5}, 10, 20, {0, 0, 0}, {0, 0, -1});
}

Scene makeGrazing() {
  Scene s = baseScene("grazing");
  MeshBuilder mb("grazing");
  addGround(mb, kGrey, 100, 0);
  mb.appendTo(s);
  // N = +y, so N.L = L.y = 0.01 at the origin.
  const glm::dvec3 toLight(std::sqrt(1.0 - 0.01 * 0.01), 0.01, 0.0);
  addLight(s, 500.0 * toLight, 1e6, 1000);
  addCamera(s, {0, 2, 6}, {0, 0, 0});
  return s;
}

glm::dvec3 grazingFarNormal() { return {std::sin(kPi / 6), 0.0, std::cos(kPi / 6)}; }

Scene makeGrazingFar() {
  Scene s = baseScene("grazing-far");
  MeshBuilder mb("grazing-far");
  const glm::dvec3 centre(0, 0, -kGrazingFarDepth), n = grazingFarNormal(), t(n.z, 0.0, -n.x), up(0, 1, 0);
  addQuad(mb, kGrey, centre - 700.0 * t - 350.0 * up, centre + 700.0 * t - 350.0 * up, centre + 700.0 * t + 350.0 * up,
          centre - 700.0 * t + 350.0 * up, n);
  mb.appendTo(s);
  // 1000 m along the plane and 10 m above it: N.L = 0.01 at the centre.
  addLight(s, centre + 1000.0 * (std::sqrt(1.0 - 0.01 * 0.01) * t + 0.01 * n), 4e6, 2000);
  addCamera(s, {0, 0, 0}, {0, 0, -1}, 0.1, 1000);
  return s;
}

Scene makeThinGap() {
  Scene s = baseScene("thin-gap");
  MeshBuilder mb("thin-gap");
  addGround(mb, kGrey, 1, 0);
  addBox(mb, kGrey, {-0.2, kThinGap, -0.2}, {0.2, kThinGap + 0.01, 0.2});
  mb.appendTo(s);
  addLight(s, {0.5, 2, 0.3}, 10, 10);
  addCamera(s, {0, 0.5, 0.8}, {0, 0, 0}, 0.01, 100);
  return s;
}

Scene makeDegenerate() {
  Scene s = baseScene("degenerate");
  MeshBuilder mb("degenerate");
  constexpr int kCells = 16;
  const glm::vec3 up(0, 1, 0);
  uint32_t grid[kCells + 1][kCells + 1];
  for (int i = 0; i <= kCells; ++i)
    for (int j = 0; j <= kCells; ++j)  // 0.25 m steps: every coordinate exact in float
      grid[i][j] = mb.vertex(kGrey, Vertex{{-2.0f + 0.25f * j, 0.0f, -2.0f + 0.25f * i}, up, {j / 16.0f, i / 16.0f}});
  uint32_t degenerate = 0;
  for (int i = 0; i < kCells; ++i)
    for (int j = 0; j < kCells; ++j) {
      mb.quad(kGrey, grid[i][j], grid[i][j + 1], grid[i + 1][j + 1], grid[i + 1][j]);
      if ((i * kCells + j) % 5 != 0 || degenerate == kDegenerateCount) continue;
      const int row = i, col = std::min(j, kCells - 2);
      switch (degenerate++ % 3) {
        case 0:  // three collinear vertices along a grid row: zero area
          mb.triangle(kGrey, grid[row][col], grid[row][col + 1], grid[row][col + 2]);
          break;
        case 1:  // a repeated index
          mb.triangle(kGrey, grid[row][col], grid[row][col], grid[row + 1][col]);
          break;
        default: {  // three distinct vertices at one position
          const Vertex v{{-2.0f + 0.25f * col, 0.0f, -2.0f + 0.25f * row}, up, {0, 0}};
          mb.triangle(kGrey, mb.vertex(kGrey, v), mb.vertex(kGrey, v), mb.vertex(kGrey, v));
        }
      }
    }
  HB_ASSERT(degenerate == kDegenerateCount);
  return finish(std::move(s), mb, {0.5, 2, 0.5}, 20, 10, {0, 3, 3}, {0, 0, 0});
}

Scene makeOpenOccluder() {
  Scene s = baseScene("open-occluder");
  Material twoSided = s.materials[kGrey];
  twoSided.name = "grey-double-sided";
  twoSided.doubleSided = true;
  s.materials.push_back(twoSided);
  MeshBuilder mb("open-occluder");
  addGround(mb, kGrey, 4, 0);
  addQuadZ(mb, 1, -1, 1, 0.5, 1.5, 0);
  return finish(std::move(s), mb, {0, 6, 3}, 40, 15, {0, 2.5, -4}, {0, 0.5, 0});
}

Scene makeFarOrigin() {
  Scene s = makeCube({kFarOriginOffset, 0, 0});
  s.name = "far-origin";
  return s;
}

Scene makeFarPlanes() {
  Scene s = baseScene("far-planes");
  MeshBuilder mb("far-planes");
  const double tanHalf = std::tan(kPi / 6), aspect = 16.0 / 9.0;
  for (int k = 0; k < 3; ++k) {
    const double d = kFarPlaneDepths[k], third = 2.0 / 3.0, overhang = 0.05 * third;
    const double ndc0 = -1.0 + third * k - overhang, ndc1 = -1.0 + third * (k + 1) + overhang;
    const double sx = d * tanHalf * aspect, sy = d * tanHalf;  // NDC -> view-space metres at depth d
    addQuadZ(mb, kGrey, ndc0 * sx, ndc1 * sx, -1.05 * sy, 1.05 * sy, -d);
    // A light halfway between the camera and the plane, in front of the plane's centre.
    const double xMid = 0.5 * (ndc0 + ndc1) * sx * 0.5;
    addLight(s, {xMid, 0, -d / 2}, 10 * d * d, d);
  }
  mb.appendTo(s);
  addCamera(s, {0, 0, 0}, {0, 0, -1}, 0.05, 1000);
  return s;
}

Scene makeMicrobench(uint32_t triangles, double layers) {
  Scene s = baseScene(layers > 4            ? "microbench-dense"
                      : layers < 4          ? "microbench-tiny"
                      : triangles == 262144 ? "microbench-262144"
                                            : "microbench-144");
  MeshBuilder mb(s.name);
  // Sized so that the triangles cover the 1920x1080 screen about `layers` times over: a triangle's
  // projected area is ~layers·W·H/N pixels, i.e. legs of sqrt(2·layers·W·H/N) pixels; a pixel at
  // depth z is 2·z·tan(30°)/1080 m.
  const double legPixels = std::sqrt(2.0 * layers * 1920.0 * 1080.0 / double(triangles));
  std::mt19937 rng(2012);  // the paper's year: any fixed seed
  std::uniform_real_distribution<double> unit(-1.0, 1.0), depth(4.0, 12.0);
  const double tanHalf = std::tan(kPi / 6), aspect = 1920.0 / 1080.0;
  for (uint32_t t = 0; t < triangles; ++t) {
    const double z = depth(rng);
    const glm::dvec3 centre(unit(rng) * z * tanHalf * aspect, unit(rng) * z * tanHalf, -z);
    const double leg = legPixels * 2.0 * z * tanHalf / 1080.0;
    uint32_t v[3];
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 p = centre + leg * glm::dvec3(unit(rng), unit(rng), 0.3 * unit(rng));
      v[k] = mb.vertex(kGrey, Vertex{glm::vec3(p), glm::vec3(0, 0, 1), {0, 0}});
    }
    mb.triangle(kGrey, v[0], v[1], v[2]);
  }
  return finish(std::move(s), mb, {0, 3, -2}, 200, 30, {0, 0, 0}, {0, 0, -1});
}

std::vector<std::string> builtinSceneNames() {
  return {"atrium",      "plane",    "depth-step", "cube",          "tiny-triangles", "grazing",
          "grazing-far", "thin-gap", "degenerate", "open-occluder", "far-origin",     "far-planes"};
}

std::vector<std::string> benchmarkSceneNames() {
  return {"microbench-262144", "microbench-144", "microbench-dense", "microbench-tiny"};
}

std::vector<std::string> allSceneNames() {
  std::vector<std::string> names = builtinSceneNames();
  for (const std::string& n : benchmarkSceneNames()) names.push_back(n);
  return names;
}

std::string unknownSceneHint(const std::string& name) {
  const std::vector<std::string> names = allSceneNames();
  const std::string guess = json_reader::closestKey(name, std::vector<std::string_view>(names.begin(), names.end()));
  if (!guess.empty()) return "did you mean \"" + guess + "\"?";
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}

std::string builtinSceneDescription(const std::string& name) {
  static const std::pair<const char*, const char*> kDescriptions[] = {
      {"atrium", "the default: a procedural atrium shaped like Crytek Sponza, 10 point lights"},
      {"plane", "a 10 m quad seen head-on"},
      {"depth-step", "a 1 m depth step down the middle of the image"},
      {"cube", "a closed cube with exactly shared edges over a ground quad"},
      {"tiny-triangles", "a field of 2 cm triangles (~1.9 px at 1080p) and 1-px strips against the sky"},
      {"grazing", "a light at N.L = 0.01 over a ground quad"},
      {"grazing-far", "the grazing light on a plane 433-1100 m away: shadow acne with a constant t_min"},
      {"thin-gap", "an occluder 1 mm above its receiver"},
      {"degenerate", "48 zero-area triangles mixed into a grid"},
      {"open-occluder", "a single double-sided quad casting a shadow, seen from behind"},
      {"far-origin", "the cube 10 km from the origin, where float spacing is ~1 mm"},
      {"far-planes", "planes at 0.1 m, 100 m and 900 m (znear 0.05, zfar 1000)"},
      {"microbench-262144", "3D rasterization paper's microbenchmark: 262,144 random triangles"},
      {"microbench-144", "3D rasterization paper's microbenchmark: 144 random triangles"},
      {"microbench-dense", "the microbenchmark's construction, 4,096 triangles about 64 deep: long tile lists"},
      {"microbench-tiny", "the microbenchmark's construction, 262,144 triangles of about 2-pixel legs"},
  };
  for (const auto& [n, description] : kDescriptions)
    if (name == n) return description;
  return "";
}

Scene makeBuiltinScene(const std::string& name) {
  if (name == "atrium") return makeAtrium();
  if (name == "plane") return makePlane();
  if (name == "depth-step") return makeDepthStep();
  if (name == "cube") return makeCube();
  if (name == "tiny-triangles") return makeTinyTriangles();
  if (name == "grazing") return makeGrazing();
  if (name == "grazing-far") return makeGrazingFar();
  if (name == "thin-gap") return makeThinGap();
  if (name == "degenerate") return makeDegenerate();
  if (name == "open-occluder") return makeOpenOccluder();
  if (name == "far-origin") return makeFarOrigin();
  if (name == "far-planes") return makeFarPlanes();
  if (name == "microbench-262144") return makeMicrobench(262144);
  if (name == "microbench-144") return makeMicrobench(144);
  if (name == "microbench-dense") return makeMicrobench(4096, 64);
  if (name == "microbench-tiny") return makeMicrobench(262144, 0.25);
  throw InputError("unknown built-in scene '" + name + "' (" + unknownSceneHint(name) +
                   "; or give a path to a .gltf/.glb file)");
}

}  // namespace hb
