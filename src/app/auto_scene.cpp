#include "app/auto_scene.h"
#include "base/numbers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>

#include "base/splitmix64.h"
#include "base/text_format.h"
#include "reference/bvh.h"
#include "scene/camera.h"

namespace hb {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr double kCameraYfovDeg = 60.0, kCameraAzimuthDeg = 30.0, kCameraElevationDeg = 20.0;
constexpr double kShellRadius = 1.25, kShellRange = 2.3;             // × r
constexpr double kInteriorRangeMin = 0.15, kInteriorRangeMax = 0.6;  // × r
constexpr double kClearance = 0.02;                                  // × r
constexpr int kInteriorDraws = 64;
constexpr double kIntensityPerRange2 = 0.5;  // interior lights: cd per m² of range (the atrium's)
// Shell lights: 0.6 cd per m² of the shell's radius, so that each gives the centre an illuminance
// of 0.6 × the range window there, (1 - (1.25/2.3)^4)² = 0.83: 0.5 lx. (0.5 cd per m² of the full
// range, as inside, would be 3.5 times that: five of them burnt an object's image out; 0.3 left
// the sides of a large scene in the dark. Looked at on the cube and the exported atrium.)
constexpr double kShellIntensityPerRadius2 = 0.6;

// The bounds' centre and sphere radius; a scene with no geometry (or a single point) gets r = 1
// around its centre (or the origin), so that every camera and light is well defined.
struct Sphere {
  glm::dvec3 centre{0.0};
  double radius = 1.0;
  glm::dvec3 lo{-1.0}, hi{1.0};
};

Sphere boundingSphere(const Scene& scene) {
  Sphere s;
  if (scene.instances.empty()) return s;
  glm::vec3 lo, hi;
  scene.bounds(lo, hi);
  if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return s;  // no vertices
  s.lo = glm::dvec3(lo);
  s.hi = glm::dvec3(hi);
  s.centre = 0.5 * (s.lo + s.hi);
  const double r = 0.5 * glm::length(s.hi - s.lo);
  if (r > 0.0 && std::isfinite(r)) {
    s.radius = r;
  } else {
    s.lo = s.centre - glm::dvec3(1.0);
    s.hi = s.centre + glm::dvec3(1.0);
  }
  return s;
}

glm::vec3 paleColour(SplitMix64& rng) {  // the atrium's: each channel in [0.55, 1], max 1
  const glm::dvec3 c(rng.uniform(0.55, 1.0), rng.uniform(0.55, 1.0), rng.uniform(0.55, 1.0));
  return glm::vec3(c / std::max({c.r, c.g, c.b}));
}

// Is p in free space: every one of 14 rays (6 axes, 8 diagonals) first hits at >= clearance, and
// at most half of them hit a back face (triangles wind counter-clockwise around outward normals).
bool freeSpace(const Bvh& bvh, const glm::dvec3& p, double clearance) {
  static const std::array<glm::dvec3, 14> kDirs = {
      glm::dvec3(1, 0, 0),  glm::dvec3(-1, 0, 0),  glm::dvec3(0, 1, 0),   glm::dvec3(0, -1, 0),  glm::dvec3(0, 0, 1),
      glm::dvec3(0, 0, -1), glm::dvec3(1, 1, 1),   glm::dvec3(1, 1, -1),  glm::dvec3(1, -1, 1),  glm::dvec3(1, -1, -1),
      glm::dvec3(-1, 1, 1), glm::dvec3(-1, 1, -1), glm::dvec3(-1, -1, 1), glm::dvec3(-1, -1, -1)};
  int backFaces = 0;
  for (const glm::dvec3& d : kDirs) {
    const glm::dvec3 dir = glm::normalize(d);
    double t = 0.0;
    uint32_t tri = 0;
    if (!bvh.closestHit(p, dir, 0.0, INFINITY, t, tri)) continue;
    if (t < clearance) return false;
    const BvhTriangle& T = bvh.input(tri);
    if (glm::dot(glm::cross(T.v1 - T.v0, T.v2 - T.v0), dir) > 0.0) ++backFaces;
  }
  return 2 * backFaces <= int(kDirs.size());
}

Light pointLight(uint32_t index, const glm::dvec3& position, double range, double intensity, SplitMix64& rng) {
  Light l;
  char name[32];
  std::snprintf(name, sizeof name, "auto-%02u", index);
  l.name = name;
  l.type = LightType::Point;
  l.position = glm::vec3(position);
  l.color = paleColour(rng);
  l.range = float(range);
  l.intensity = float(intensity);
  l.rangeFromEq41 = false;
  return l;
}

std::string vecText(const glm::vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.3g, %.3g, %.3g)", double(v.x), double(v.y), double(v.z));
  return buf;
}

}  // namespace

Camera autoCamera(const Scene& scene) {
  const Sphere s = boundingSphere(scene);
  const double az = kCameraAzimuthDeg * kDeg, el = kCameraElevationDeg * kDeg, yfov = kCameraYfovDeg * kDeg;
  const glm::dvec3 toEye(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
  const double d = s.radius / std::sin(0.5 * yfov);
  Camera cam;
  cam.name = "auto";
  cam.projection = CameraProjection::Perspective;
  cam.view = lookAt(glm::vec3(s.centre + d * toEye), glm::vec3(s.centre), {0.0f, 1.0f, 0.0f});
  cam.yfov = float(yfov);
  cam.znear = float(0.5 * (d - s.radius));
  cam.zfar = float(d + 2.0 * s.radius);
  return cam;
}

AutoLights autoLights(const Scene& scene, uint32_t count, uint32_t seed) {
  AutoLights out;
  if (count == 0) return out;
  const Sphere s = boundingSphere(scene);
  const double r = s.radius;
  SplitMix64 rng{0xA070117ull ^ seed};
  // Interior lights need geometry to test free space against.
  std::unique_ptr<Bvh> bvh;
  if (scene.triangleCount() > 0) {
    const std::vector<glm::vec3> w = scene.worldTriangles();
    std::vector<BvhTriangle> tris(w.size() / 3);
    for (size_t t = 0; t < tris.size(); ++t)
      tris[t] = {glm::dvec3(w[3 * t]), glm::dvec3(w[3 * t + 1]), glm::dvec3(w[3 * t + 2])};
    bvh = std::make_unique<Bvh>(std::move(tris));
  }
  const glm::dvec3 ext = s.hi - s.lo;
  const double goldenAngle = kPi * (3.0 - std::sqrt(5.0));
  for (uint32_t i = 0; i < count; ++i) {
    bool placed = false;
    if (i % 2 == 0 && bvh) {
      for (int draw = 0; draw < kInteriorDraws && !placed; ++draw) {
        const glm::dvec3 p(s.lo.x + ext.x * rng.uniform(0.05, 0.95), s.lo.y + ext.y * rng.uniform(0.15, 0.75),
                           s.lo.z + ext.z * rng.uniform(0.05, 0.95));
        if (!freeSpace(*bvh, p, kClearance * r)) {
          ++out.rejectedDraws;
          continue;
        }
        const double range = r * rng.uniform(kInteriorRangeMin, kInteriorRangeMax);
        out.lights.push_back(pointLight(i, p, range, kIntensityPerRange2 * range * range, rng));
        ++out.interior;
        placed = true;
      }
    }
    if (placed) continue;
    const double azimuth = goldenAngle * i, elevation = rng.uniform(20.0, 65.0) * kDeg;
    const glm::dvec3 dir(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                         std::cos(elevation) * std::cos(azimuth));
    const double shell = kShellRadius * r;
    out.lights.push_back(
        pointLight(i, s.centre + shell * dir, kShellRange * r, kShellIntensityPerRadius2 * shell * shell, rng));
    ++out.shell;
  }
  return out;
}

std::vector<std::string> completeScene(Scene& scene, const AutoRequest& request) {
  std::vector<std::string> lines;
  const std::string name = "scene \"" + scene.name + "\"";
  if (scene.cameras.empty() || request.camera) {
    const std::string why = request.camera ? "camera=auto" : "has no camera";
    scene.cameras.insert(scene.cameras.begin(), autoCamera(scene));
    scene.cameraSource = "auto";
    const glm::mat4 world = glm::inverse(scene.cameras[0].view);
    lines.push_back(
        name + " " + why + ": automatic camera at " + vecText(glm::vec3(world[3])) +
        " framing its bounds (yfov 60°, from azimuth 30° and elevation 20°; README \"Bring your own glTF\")");
  }
  const bool noLights = scene.lights.empty() && scene.lightsSource == "scene";
  if (request.lightCount || noLights) {
    const uint32_t count = request.lightCount.value_or(kDefaultAutoLights);
    AutoLights made = autoLights(scene, count);
    scene.lights = std::move(made.lights);
    scene.lightsSource = "auto";
    lines.push_back(name +
                    (request.lightCount ? " light_count=" + std::to_string(count) : std::string(" has no lights")) +
                    ": " + countOf(count, "automatic point light") + ", " + std::to_string(made.interior) +
                    " in free space inside its bounds and " + std::to_string(made.shell) +
                    " on a sphere round them (README \"Bring your own glTF\")");
  }
  return lines;
}

}  // namespace hb
