#include "app/auto_scene.h"
#include "base/numbers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>

#include "base/errors.h"
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
constexpr double kEyeHeight = 1.7;  // m (glTF's unit): a standing person's eyes
constexpr uint64_t kProbeSeed = 0xCA3E7A;
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

// The free-space test's rays: the 6 axes and the 8 diagonals. kDirs[2] is straight up.
const std::array<glm::dvec3, 14> kDirs = {
    glm::dvec3(1, 0, 0),  glm::dvec3(-1, 0, 0),  glm::dvec3(0, 1, 0),   glm::dvec3(0, -1, 0),  glm::dvec3(0, 0, 1),
    glm::dvec3(0, 0, -1), glm::dvec3(1, 1, 1),   glm::dvec3(1, 1, -1),  glm::dvec3(1, -1, 1),  glm::dvec3(1, -1, -1),
    glm::dvec3(-1, 1, 1), glm::dvec3(-1, 1, -1), glm::dvec3(-1, -1, 1), glm::dvec3(-1, -1, -1)};
constexpr size_t kUp = 2, kDown = 3;

// What the 14 rays from a point find: each one's first hit (INFINITY for a miss) and whether it is
// a back face (triangles wind counter-clockwise around outward normals).
struct RaySurvey {
  std::array<double, 14> t{};
  int backFaces = 0, misses = 0;
  double nearest = INFINITY;
};

RaySurvey survey(const Bvh& bvh, const glm::dvec3& p) {
  RaySurvey s;
  for (size_t i = 0; i < kDirs.size(); ++i) {
    const glm::dvec3 dir = glm::normalize(kDirs[i]);
    uint32_t tri = 0;
    if (!bvh.closestHit(p, dir, 0.0, INFINITY, s.t[i], tri)) {
      s.t[i] = INFINITY;
      ++s.misses;
      continue;
    }
    s.nearest = std::min(s.nearest, s.t[i]);
    const BvhTriangle& T = bvh.input(tri);
    if (glm::dot(glm::cross(T.v1 - T.v0, T.v2 - T.v0), dir) > 0.0) ++s.backFaces;
  }
  return s;
}

// Is p in free space: every one of the 14 rays first hits at >= clearance, and at most half of
// them hit a back face.
bool freeSpace(const RaySurvey& s, double clearance) {
  return s.nearest >= clearance && 2 * s.backFaces <= int(kDirs.size());
}
bool freeSpace(const Bvh& bvh, const glm::dvec3& p, double clearance) { return freeSpace(survey(bvh, p), clearance); }

// Enclosed: free, and every ray but the one straight up hits the scene (auto_scene.h says why).
bool enclosed(const RaySurvey& s, double clearance) {
  return freeSpace(s, clearance) && s.misses == (std::isinf(s.t[kUp]) ? 1 : 0);
}

std::unique_ptr<Bvh> sceneBvh(const Scene& scene) {
  if (scene.triangleCount() == 0) return nullptr;
  const std::vector<glm::vec3> w = scene.worldTriangles();
  std::vector<BvhTriangle> tris(w.size() / 3);
  for (size_t t = 0; t < tris.size(); ++t)
    tris[t] = {glm::dvec3(w[3 * t]), glm::dvec3(w[3 * t + 1]), glm::dvec3(w[3 * t + 2])};
  return std::make_unique<Bvh>(std::move(tris));
}

// A point drawn where interior lights are: the bounds shrunk by 5 % on each side in x and z, at
// 15-75 % of their height.
glm::dvec3 interiorDraw(const Sphere& s, SplitMix64& rng) {
  const glm::dvec3 ext = s.hi - s.lo;
  return {s.lo.x + ext.x * rng.uniform(0.05, 0.95), s.lo.y + ext.y * rng.uniform(0.15, 0.75),
          s.lo.z + ext.z * rng.uniform(0.05, 0.95)};
}

// The 24 level directions every 15° of azimuth, from +z towards +x (the exterior camera's
// azimuth). Built from the exact sines of multiples of 15° with sqrt, which IEEE 754 rounds
// correctly, so they are the same bits on every machine (std::sin need not be).
std::array<glm::dvec3, 24> levelDirections() {
  const double s6 = std::sqrt(6.0), s2 = std::sqrt(2.0);
  const std::array<double, 7> sinK = {0.0, (s6 - s2) / 4, 0.5, s2 / 2, std::sqrt(3.0) / 2, (s6 + s2) / 4, 1.0};
  std::array<glm::dvec3, 24> d;
  for (int k = 0; k < 24; ++k) {
    // sin and cos of k·15° from the first quadrant's table; + 0.0 turns -0 into 0 for the stderr line.
    const int q = k / 6, m = k % 6;
    const double a = sinK[m], b = sinK[6 - m];  // sin, cos of m·15°
    const double sinA = q == 0 ? a : q == 1 ? b : q == 2 ? -a : -b;
    const double cosA = q == 0 ? b : q == 1 ? -a : q == 2 ? -b : a;
    d[k] = glm::dvec3(sinA + 0.0, 0.0, cosA + 0.0);
  }
  return d;
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

Camera exteriorCamera(const Sphere& s) {
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

// Every level direction's first hit from `eye` (INFINITY for a miss); returns how many hit.
int levelFreeDistances(const Bvh& bvh, const glm::dvec3& eye, std::array<double, 24>& t) {
  const std::array<glm::dvec3, 24> dirs = levelDirections();
  int hits = 0;
  for (size_t k = 0; k < dirs.size(); ++k) {
    if (bvh.closestHit(eye, dirs[k], 0.0, INFINITY, t[k]))
      ++hits;
    else
      t[k] = INFINITY;
  }
  return hits;
}

}  // namespace

Camera exteriorCamera(const Scene& scene) { return exteriorCamera(boundingSphere(scene)); }

AutoCameraChoice chooseAutoCamera(const Scene& scene) {
  AutoCameraChoice c;
  const Sphere s = boundingSphere(scene);
  c.camera = exteriorCamera(s);
  const std::unique_ptr<Bvh> bvh = sceneBvh(scene);
  if (!bvh) return c;
  const double clearance = kClearance * s.radius;

  // The probe: the centre when it is free, else the free point nearest it among the interior
  // lights' kind of draws (a seed of its own, so the lights stay as they were).
  RaySurvey at = survey(*bvh, s.centre);
  c.centreFree = freeSpace(at, clearance);
  if (c.centreFree) {
    c.probe = s.centre;
    c.probeFound = true;
  } else {
    SplitMix64 rng{kProbeSeed};
    double best = INFINITY;
    for (int draw = 0; draw < kInteriorDraws; ++draw) {
      const glm::dvec3 p = interiorDraw(s, rng);
      const double d = glm::length(p - s.centre);
      if (!(d < best)) continue;  // the first of equals stays
      const RaySurvey r = survey(*bvh, p);
      if (!freeSpace(r, clearance)) continue;
      best = d;
      c.probe = p;
      c.probeFound = true;
      at = r;
    }
  }
  if (!c.probeFound) return c;
  c.probeMisses = at.misses;
  c.enclosed = enclosed(at, clearance);
  if (!c.enclosed) return c;

  // Stand at eye height above what is straight below the probe (enclosure says the ray down hits),
  // when the probe is higher than that and the standing point is free and sees a wall level.
  std::array<double, 24> t{};
  c.eye = c.probe;
  const double below = at.t[kDown];
  if (below > kEyeHeight) {
    const glm::dvec3 standing(c.probe.x, c.probe.y - below + kEyeHeight, c.probe.z);
    if (freeSpace(*bvh, standing, clearance) && levelFreeDistances(*bvh, standing, t) > 0) c.eye = standing;
  }
  // At the probe the four level axes hit (enclosure), so some level direction always does.
  HB_ASSERT(levelFreeDistances(*bvh, c.eye, t) > 0);
  // The longest free level direction that hits the scene (a miss would look at the background);
  // among lengths equal to 1e-9 relative, the first in azimuth order. The hits are computed in
  // double to about 1e-15 relative, so two machines whose arithmetic differs in the last bits
  // (contracted multiply-adds) still agree on which is longest.
  const std::array<glm::dvec3, 24> dirs = levelDirections();
  int chosen = -1;
  for (int k = 0; k < 24; ++k)
    if (std::isfinite(t[k]) && (chosen < 0 || t[k] > t[chosen] * (1.0 + 1e-9))) chosen = k;
  c.direction = dirs[chosen];
  c.freeDistance = t[chosen];

  Camera& cam = c.camera;
  cam.view = lookAt(glm::vec3(c.eye), glm::vec3(c.eye + c.direction), {0.0f, 1.0f, 0.0f});
  // Near: a quarter of the clearance the free-space test guarantees along its 14 rays, leaving
  // room for geometry between them; reverse-Z keeps depth precise however small it is. Far: the
  // farthest corner of the bounds (no geometry is farther from a point inside them) plus the
  // clearance, far beyond float rounding of the view matrix.
  cam.znear = float(0.25 * clearance);
  double farthest = 0.0;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner(k & 1 ? s.hi.x : s.lo.x, k & 2 ? s.hi.y : s.lo.y, k & 4 ? s.hi.z : s.lo.z);
    farthest = std::max(farthest, glm::length(corner - c.eye));
  }
  cam.zfar = float(farthest + clearance);
  return c;
}

Camera autoCamera(const Scene& scene) { return chooseAutoCamera(scene).camera; }

std::string cameraChoiceText(const AutoCameraChoice& c) {
  static const std::string kSeeDocs = "README \"Bring your own glTF\"";
  const std::string probe = c.centreFree
                                ? "the centre of its bounds"
                                : "the centre of its bounds is not in free space; the free point nearest it, " +
                                      vecText(glm::vec3(c.probe)) + ",";
  if (c.enclosed) {
    char len[32];
    std::snprintf(len, sizeof len, "%.3g m", c.freeDistance);
    return probe + " is enclosed (every free-space ray but the one straight up hits the scene), so an automatic " +
           "camera inside at " + vecText(glm::vec3(c.eye)) + " looking along " + vecText(glm::vec3(c.direction)) +
           ", the longest free level direction (" + len + "; yfov 60°; " + kSeeDocs + ")";
  }
  const glm::mat4 world = glm::inverse(c.camera.view);
  const std::string open =
      !c.probeFound ? "neither the centre of its bounds nor any point drawn near it is in free space (not enclosed)"
                    : probe + " is open (" + std::to_string(c.probeMisses) + " of its 14 free-space rays " +
                          (c.probeMisses == 1 ? "escapes" : "escape") + " the scene)";
  return open + ", so an automatic camera outside at " + vecText(glm::vec3(world[3])) +
         " framing its bounds (yfov 60°, from azimuth 30° and elevation 20°; " + kSeeDocs + ")";
}

AutoLights autoLights(const Scene& scene, uint32_t count, uint32_t seed) {
  AutoLights out;
  if (count == 0) return out;
  const Sphere s = boundingSphere(scene);
  const double r = s.radius;
  SplitMix64 rng{0xA070117ull ^ seed};
  // Interior lights need geometry to test free space against.
  const std::unique_ptr<Bvh> bvh = sceneBvh(scene);
  const double goldenAngle = kPi * (3.0 - std::sqrt(5.0));
  for (uint32_t i = 0; i < count; ++i) {
    bool placed = false;
    if (i % 2 == 0 && bvh) {
      for (int draw = 0; draw < kInteriorDraws && !placed; ++draw) {
        const glm::dvec3 p = interiorDraw(s, rng);
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
    const AutoCameraChoice c = chooseAutoCamera(scene);
    scene.cameras.insert(scene.cameras.begin(), c.camera);
    scene.cameraSource = "auto";
    lines.push_back(name + " " + why + ": " + cameraChoiceText(c));
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
