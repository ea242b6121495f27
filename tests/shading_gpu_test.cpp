// The shading pass on the real device (lavapipe on CI) against a double-precision CPU evaluation of
// the same Cook-Torrance model (shaders/shading.frag.glsl): a lit ground plane, a shadow cast on it,
// metal vs dielectric, sampled textures (a checker and an sRGB decode), the shadows-off path, and
// the atrium free of NaN/Inf.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "base/image_io.h"
#include "base/numbers.h"
#include "effects/shadows/shadows_part.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "scene/atrium.h"
#include "scene/camera.h"
#include "scene/mesh_builder.h"

namespace hb {
namespace {

using glm::dvec3;

constexpr double kPi = 3.14159265358979323846;
constexpr uint32_t kImageSize = 128;  // square test images
constexpr double kHalf = 2.0;         // the ground: x, z in [-2, 2] at y = 0, facing +y
constexpr double kOccHalf = 0.5;      // the occluder: x, z in [-0.5, 0.5] at y = kOccY, facing +y
constexpr double kOccY = 1.0;
const glm::vec3 kEye(0.0f, 2.5f, 3.0f);  // camera looking at the origin

// ---- the CPU model: shading.frag.glsl's formulas in double -------------------------------------

struct CpuMaterial {
  dvec3 base{0.8};
  double metallic = 0.0;
  double roughness = 0.5;
};

double g1(double nDotX, double roughness) {
  const double r = roughness + 1.0, k = r * r / 8.0;  // Schlick-GGX, direct lighting (Karis 2013)
  return nDotX / (nDotX * (1.0 - k) + k);
}

// Outgoing radiance towards `eye` from point p with shading normal n, lit by `light` (visible).
dvec3 shadeCpu(const dvec3& p, const dvec3& n, const dvec3& eye, const Light& light, const CpuMaterial& mat) {
  const double roughness = std::clamp(mat.roughness, 0.04, 1.0);
  const double metallic = std::clamp(mat.metallic, 0.0, 1.0);
  const dvec3 v = glm::normalize(eye - p);
  const double nDotV = std::max(glm::dot(n, v), 1e-4);
  const dvec3 f0 = glm::mix(dvec3(0.04), mat.base, metallic);
  dvec3 radiance = dvec3(light.color) * double(light.intensity);
  dvec3 l;
  if (light.type == LightType::Directional) {
    l = -glm::normalize(dvec3(light.direction));
  } else {
    const dvec3 toLight = dvec3(light.position) - p;
    const double d2 = glm::dot(toLight, toLight), d = std::sqrt(d2);
    l = toLight / d;
    const double ratio = d / double(light.range);  // glTF window: clamp(1-(d/range)^4, 0, 1)^2 / d^2
    const double window = std::clamp(1.0 - ratio * ratio * ratio * ratio, 0.0, 1.0);
    radiance *= window * window / d2;
    if (light.type == LightType::Spot) {
      const double cosOuter = std::cos(double(light.outerConeAngle)), cosInner = std::cos(double(light.innerConeAngle));
      const double cd = glm::dot(glm::normalize(dvec3(light.direction)), -l);
      const double t = std::clamp((cd - cosOuter) / std::max(cosInner - cosOuter, 1e-4), 0.0, 1.0);
      radiance *= t * t;
    }
  }
  const double nDotL = glm::dot(n, l);
  if (nDotL <= 0.0) return dvec3(0.0);
  const dvec3 h = glm::normalize(v + l);
  const double nDotH = std::max(glm::dot(n, h), 0.0);
  const dvec3 f = f0 + (dvec3(1.0) - f0) * std::pow(std::clamp(1.0 - std::max(glm::dot(h, v), 0.0), 0.0, 1.0), 5.0);
  const double a = roughness * roughness, a2 = a * a;
  const double dd = nDotH * nDotH * (a2 - 1.0) + 1.0;
  const double dTerm = a2 / std::max(kPi * dd * dd, 1e-12);
  const double g = g1(nDotV, roughness) * g1(nDotL, roughness);
  const dvec3 specular = dTerm * g * f / (4.0 * nDotV * nDotL + 1e-7);
  const dvec3 kd = (dvec3(1.0) - f) * (1.0 - metallic);
  return (kd * mat.base / kPi + specular) * radiance * nDotL;
}

// ---- scenes ------------------------------------------------------------------------------------

// A quad at height y over x in [-h, h], z in [-h, h], normal +y, uv = ((x+h)/2h, (z+h)/2h).
void addQuadY(Scene& s, double h, double y, uint32_t material) {
  MeshBuilder mb("quad");
  const float fh = float(h), fy = float(y);
  const uint32_t a = mb.vertex(material, {{-fh, fy, -fh}, {0, 1, 0}, {0, 0}});
  const uint32_t b = mb.vertex(material, {{-fh, fy, fh}, {0, 1, 0}, {0, 1}});
  const uint32_t c = mb.vertex(material, {{fh, fy, fh}, {0, 1, 0}, {1, 1}});
  const uint32_t d = mb.vertex(material, {{fh, fy, -fh}, {0, 1, 0}, {1, 0}});
  mb.quad(material, a, b, c, d);
  mb.appendTo(s);
}

Light pointLight(glm::vec3 position) {
  Light l;
  l.name = "point";
  l.position = position;
  l.color = {1.0f, 0.9f, 0.8f};
  l.intensity = 20.0f;
  l.range = 6.0f;  // (d/range)^4 reaches ~0.2 at the far corners: the window matters
  return l;
}

// The ground (material 0) lit by one point light, optionally with the occluder (material 1) above.
Scene groundScene(const Material& ground, glm::vec3 lightPos, bool occluder) {
  Scene s;
  s.name = "shading-ground";
  s.materials.push_back(ground);
  Material grey;
  grey.metallicFactor = 0.0f;
  s.materials.push_back(grey);
  addQuadY(s, kHalf, 0.0, 0);
  if (occluder) addQuadY(s, kOccHalf, kOccY, 1);
  s.lights.push_back(pointLight(lightPos));
  Camera cam;
  cam.view = lookAt(kEye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
  cam.yfov = 1.0471975512f;
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  s.cameras.push_back(cam);
  return s;
}

Material gpuMaterial(const CpuMaterial& m) {
  Material g;
  g.baseColorFactor = glm::vec4(glm::vec3(m.base), 1.0f);
  g.metallicFactor = float(m.metallic);
  g.roughnessFactor = float(m.roughness);
  return g;
}

// ---- what each pixel sees ----------------------------------------------------------------------

struct Ray {
  dvec3 origin, dir;
};

// The view ray through framebuffer position (x, y) (pixel centres at +0.5), in double.
Ray pixelRay(const Camera& cam, double x, double y) {
  const glm::dmat4 p = reverseZProjectionD(1.0, cam.yfov, cam.znear, cam.zfar);
  const dvec3 dirView((2.0 * x / kImageSize - 1.0) / p[0][0], (2.0 * y / kImageSize - 1.0) / p[1][1], -1.0);
  const glm::dmat4 inv = glm::inverse(glm::dmat4(cam.view));
  return {dvec3(inv[3]), dvec3(inv * glm::dvec4(dirView, 0.0))};
}

dvec3 hitY(const Ray& r, double y) { return r.origin + r.dir * ((y - r.origin.y) / r.dir.y); }

bool allInside(const std::array<dvec3, 4>& q, double h) {
  for (const dvec3& p : q)
    if (!(std::abs(p.x) < h && std::abs(p.z) < h)) return false;
  return true;
}
// True when the quadrilateral q lies entirely on one side of the square |x|, |z| < h (so misses it).
bool allOutsideOneSide(const std::array<dvec3, 4>& q, double h) {
  bool xp = true, xn = true, zp = true, zn = true;
  for (const dvec3& p : q) {
    xp = xp && p.x > h;
    xn = xn && p.x < -h;
    zp = zp && p.z > h;
    zn = zn && p.z < -h;
  }
  return xp || xn || zp || zn;
}

// A pixel is "on the ground" when the rays through the corners of its 3x3 neighbourhood all hit
// the ground inside its edges and all pass the occluder on one side: then neither the rasteriser
// nor the shadow pass's reconstruction (both off by far less than a pixel) can see anything else.
// Likewise "shadowed" / "lit": those corners' segments to the light all cross the occluder's
// plane inside / all on one side outside the occluder.
struct PixelGeom {
  bool onGround = false, shadowed = false, lit = false;
  dvec3 hit;       // the pixel-centre ray's exact ground hit
  dvec3 dPx, dPy;  // how far the hit moves per pixel in x and in y
};

PixelGeom pixelGeom(const Camera& cam, uint32_t px, uint32_t py, bool occluder, const dvec3& light) {
  PixelGeom g;
  const double cx = px + 0.5, cy = py + 0.5;
  g.hit = hitY(pixelRay(cam, cx, cy), 0.0);
  g.dPx = hitY(pixelRay(cam, cx + 1.0, cy), 0.0) - g.hit;
  g.dPy = hitY(pixelRay(cam, cx, cy + 1.0), 0.0) - g.hit;
  std::array<dvec3, 4> ground, atOcc, shadowAtOcc;
  for (int k = 0; k < 4; ++k) {
    const Ray r = pixelRay(cam, cx + ((k & 1) ? 1.5 : -1.5), cy + ((k & 2) ? 1.5 : -1.5));
    if (!(r.dir.y < 0.0)) return g;
    ground[k] = hitY(r, 0.0);
    atOcc[k] = hitY(r, kOccY);
    shadowAtOcc[k] = ground[k] + (light - ground[k]) * (kOccY / light.y);
  }
  g.onGround = allInside(ground, kHalf) && (!occluder || allOutsideOneSide(atOcc, kOccHalf));
  g.shadowed = occluder && allInside(shadowAtOcc, kOccHalf);
  g.lit = !occluder || allOutsideOneSide(shadowAtOcc, kOccHalf);
  return g;
}

// ---- tolerance ---------------------------------------------------------------------------------
//
// Each channel c the GPU writes differs from the CPU model c* at the exact pixel-centre hit by
//  (a) the RGBA16F store: 11-bit significand; Vulkan leaves the rounding mode of float -> half
//      conversions undefined, so up to 1 ulp: relative 2^-10, not the 2^-11 of round-to-nearest.
//      lavapipe truncates (the GPU value is below the model in > 99.7 % of channels and the
//      relative error reaches 0.975e-3 > 2^-11), so 2^-10 is needed, not merely allowed;
//  (b) float shading arithmetic: ~60 roundings on the longest path (normalize, dot products,
//      D, G, F, the window), each <= 2^-24 relative, plus pow(x, 5): Vulkan inherits its
//      precision from exp2(5 log2 x), log2 absolute 2^-21 -> relative 5 ln2 2^-21 ~ 28 ulp, plus
//      the float rounding of the camera position and projection (~1 ulp each): <= 128 * 2^-24;
//  (c) the position at which the fragment is shaded: the interpolated inWorldPos instead of the
//      exact ray hit. Two parts, per in-plane axis (y is exact: every vertex has y = 0 and the
//      interpolated value is a weighted sum of zeros; the normal is a weighted sum of (0,1,0),
//      renormalised, so exact to ~2 ulp and part of (b)):
//      - the rasteriser may snap vertices to its sub-pixel grid (VkPhysicalDeviceLimits::
//        subPixelPrecisionBits = b): each vertex moves <= 2^-(b+1) px per axis, and a point with
//        barycentrics w_i is evaluated as if it sat at sum w_i (v_i + delta_i), i.e. moved by
//        <= 2^-(b+1) px per axis; in the world that is <= 2^-(b+1) (|dP/dpx| + |dP/dpy|) per axis;
//      - float interpolation: clip coordinates (4-term dot products, 4 ulp), viewport transform
//        (2), edge/plane-equation set-up (~8), evaluation at the sample (~4), the perspective
//        divide (2): ~20 ulp on each barycentric weight, times three vertices of size <= L
//        (L = 2 m, the ground's half extent) -> <= 64 * 2^-24 * L.
//      Its effect is bounded by the model's own change over that displacement, evaluated on the
//      CPU: max over +-dx of |c*(p + dx) - c*(p)| + the same for dz.
// So tol = |c*| (2^-10 + 128 * 2^-24) + position term + 2^-24 (the smallest half subnormal step,
// for values near zero).
struct Tol {
  double relative = std::ldexp(1.0, -10) + 128.0 * kU;
  double absolute = kU;
  double snapPx;  // 2^-(subPixelPrecisionBits + 1)
  explicit Tol(const VulkanContext& ctx)
      : snapPx(std::ldexp(1.0, -int(ctx.properties().limits.subPixelPrecisionBits) - 1)) {}

  dvec3 at(const PixelGeom& g, const std::function<dvec3(const dvec3&)>& model) const {
    const double interp = 64.0 * kU * kHalf;
    const double ex = snapPx * (std::abs(g.dPx.x) + std::abs(g.dPy.x)) + interp;
    const double ez = snapPx * (std::abs(g.dPx.z) + std::abs(g.dPy.z)) + interp;
    const dvec3 c = model(g.hit);
    auto change = [&](dvec3 step) {
      return glm::max(glm::abs(model(g.hit + step) - c), glm::abs(model(g.hit - step) - c));
    };
    return glm::abs(c) * relative + change({ex, 0, 0}) + change({0, 0, ez}) + dvec3(absolute);
  }
};

// ---- comparison --------------------------------------------------------------------------------

struct Stats {
  size_t checked = 0, bad = 0, above = 0, below = 0;  // channels where the GPU is above / below the model
  double maxAbsErr = 0, maxRelErr = 0, maxErrOverTol = 0, maxTol = 0;
  int maxToneDiff = 0;  // 8-bit ACES sRGB, over the checked pixels
  void print(const char* what) const {
    std::printf(
        "[%s] %zu px checked, max |err| %.3g (rel %.3g), max err/tol %.3f, max tol %.3g, 8-bit diff %d, "
        "GPU above/below model in %zu/%zu channels\n",
        what, checked, maxAbsErr, maxRelErr, maxErrOverTol, maxTol, maxToneDiff, above, below);
  }
};

// Renders `scene` and returns the linear HDR RGBA image.
std::vector<float> renderColor(const VulkanContext& ctx, const Scene& scene, RenderSettings s = {}) {
  s.width = s.height = kImageSize;
  Renderer r(ctx, scene, s);
  r.renderFrame();
  std::vector<float> c = r.readColor();
  EXPECT_EQ(c.size(), size_t(kImageSize) * kImageSize * 4);
  return c;
}

// Compares every selected ground pixel with the model; `expected` gives c* at a point.
Stats compareGround(const std::vector<float>& rgba, const Scene& scene, const Tol& tol, bool occluder,
                    const std::function<bool(const PixelGeom&)>& select,
                    const std::function<dvec3(const dvec3&)>& expected) {
  Stats st;
  const Camera& cam = scene.cameras[0];
  const dvec3 light(scene.lights[0].position);
  ImageF gpu{kImageSize, kImageSize, 3, std::vector<float>(size_t(kImageSize) * kImageSize * 3, 0.0f)};
  ImageF cpu = gpu;
  std::vector<size_t> checked;
  for (uint32_t py = 0; py < kImageSize; ++py)
    for (uint32_t px = 0; px < kImageSize; ++px) {
      const PixelGeom g = pixelGeom(cam, px, py, occluder, light);
      if (!g.onGround || !select(g)) continue;
      const size_t i = size_t(py) * kImageSize + px;
      const dvec3 want = expected(g.hit), t = tol.at(g, expected);
      bool ok = rgba[4 * i + 3] == 1.0f;
      for (int k = 0; k < 3; ++k) {
        const double err = std::abs(double(rgba[4 * i + k]) - want[k]);
        st.above += double(rgba[4 * i + k]) > want[k];
        st.below += double(rgba[4 * i + k]) < want[k];
        ok = ok && err <= t[k];
        st.maxAbsErr = std::max(st.maxAbsErr, err);
        if (want[k] > 0) st.maxRelErr = std::max(st.maxRelErr, err / want[k]);
        st.maxErrOverTol = std::max(st.maxErrOverTol, err / t[k]);
        st.maxTol = std::max(st.maxTol, t[k]);
        gpu.px[3 * i + k] = rgba[4 * i + k];
        cpu.px[3 * i + k] = float(want[k]);
      }
      if (!ok && st.bad++ < 5)
        ADD_FAILURE() << "pixel " << px << "," << py << " at (" << g.hit.x << ", " << g.hit.z << "): GPU ("
                      << rgba[4 * i] << ", " << rgba[4 * i + 1] << ", " << rgba[4 * i + 2] << ", " << rgba[4 * i + 3]
                      << "), model (" << want.x << ", " << want.y << ", " << want.z << "), tol (" << t.x << ", " << t.y
                      << ", " << t.z << ")";
      ++st.checked;
      checked.push_back(i);
    }
  const ImageRGBA8 a = toneMapToSrgb(gpu, 0.0f, ToneMapOperator::AcesFitted).image;
  const ImageRGBA8 b = toneMapToSrgb(cpu, 0.0f, ToneMapOperator::AcesFitted).image;
  for (size_t i : checked)
    for (int k = 0; k < 3; ++k)
      st.maxToneDiff = std::max(st.maxToneDiff, std::abs(int(a.px[4 * i + k]) - int(b.px[4 * i + k])));
  return st;
}

const dvec3 kUp(0.0, 1.0, 0.0);
const glm::vec3 kLightOverGround(0.5f, 2.0f, -0.5f);
const glm::vec3 kLightForShadow(1.5f, 3.0f, 0.0f);  // the occluder's shadow: x in [-1.5, 0], z in [-0.75, 0.75]

auto modelFor(const Scene& scene, const CpuMaterial& m) {
  const dvec3 eye(kEye);
  const Light light = scene.lights[0];
  return [=](const dvec3& p) { return shadeCpu(p, kUp, eye, light, m); };
}

auto anyPixel = [](const PixelGeom&) { return true; };

class ShadingTest : public testing::GpuTest {};

// 1. One point light over a plane, nothing in the way: the HDR colour is the model's.
TEST_F(ShadingTest, PointLitPlaneMatchesTheCpuModel) {
  const CpuMaterial mat{{0.8, 0.7, 0.6}, 0.0, 0.5};
  const Scene scene = groundScene(gpuMaterial(mat), kLightOverGround, false);
  const std::vector<float> rgba = renderColor(*ctx, scene);
  const Stats st = compareGround(rgba, scene, Tol(*ctx), false, anyPixel, modelFor(scene, mat));
  st.print("point-lit plane");
  EXPECT_GT(st.checked, size_t(kImageSize) * kImageSize / 4);
  EXPECT_EQ(st.bad, 0u);
  EXPECT_LE(st.maxToneDiff, 1);
  // The sky (outside the ground) is cleared to opaque black.
  EXPECT_EQ(rgba[0], 0.0f);
  EXPECT_EQ(rgba[3], 1.0f);
}

// 2. An occluder between the light and part of the plane: the ground behind it is exactly 0
// (no ambient, no emission), the ground outside its shadow is the model's.
TEST_F(ShadingTest, ShadowedGroundIsBlackAndTheRestIsLit) {
  const CpuMaterial mat{{0.8, 0.7, 0.6}, 0.0, 0.5};
  const Scene scene = groundScene(gpuMaterial(mat), kLightForShadow, true);
  const std::vector<float> rgba = renderColor(*ctx, scene);
  const Stats shadow = compareGround(
      rgba, scene, Tol(*ctx), true, [](const PixelGeom& g) { return g.shadowed; },
      [](const dvec3&) { return dvec3(0.0); });
  const Stats lit = compareGround(
      rgba, scene, Tol(*ctx), true, [](const PixelGeom& g) { return g.lit; }, modelFor(scene, mat));
  shadow.print("in shadow");
  lit.print("outside shadow");
  EXPECT_GT(shadow.checked, 100u);
  EXPECT_GT(lit.checked, size_t(kImageSize) * kImageSize / 4);
  EXPECT_EQ(shadow.bad, 0u);
  EXPECT_EQ(shadow.maxAbsErr, 0.0);  // exactly zero, not merely small
  EXPECT_EQ(lit.bad, 0u);
}

// 3. Metal vs dielectric of the same base colour: the metal has no diffuse term (k_d = 0) and a
// base-coloured Fresnel F0; each matches the model, and away from the highlight the metal is dark
// where the dielectric is lit.
TEST_F(ShadingTest, MetalHasNoDiffuseTermAndTintedSpecular) {
  const dvec3 base(0.9, 0.6, 0.3);
  const CpuMaterial metal{base, 1.0, 0.1}, dielectric{base, 0.0, 0.1};
  const Scene metalScene = groundScene(gpuMaterial(metal), kLightOverGround, false);
  const Scene dielScene = groundScene(gpuMaterial(dielectric), kLightOverGround, false);
  const std::vector<float> m = renderColor(*ctx, metalScene), d = renderColor(*ctx, dielScene);
  const Stats sm = compareGround(m, metalScene, Tol(*ctx), false, anyPixel, modelFor(metalScene, metal));
  const Stats sd = compareGround(d, dielScene, Tol(*ctx), false, anyPixel, modelFor(dielScene, dielectric));
  sm.print("metal");
  sd.print("dielectric");
  EXPECT_EQ(sm.bad, 0u);
  EXPECT_EQ(sd.bad, 0u);

  // Where the model's metal is < 1 % of the dielectric (the lobe does not reach), the GPU's metal
  // is too, with the tolerance above added; at the brightest metal pixel the colour is tinted like
  // F ~ F0 = base (r > g > b) while the dielectric's specular is white.
  const auto metalModel = modelFor(metalScene, metal), dielModel = modelFor(dielScene, dielectric);
  size_t dark = 0;
  double brightest = 0;
  size_t brightestAt = 0;
  const Tol tol(*ctx);
  for (uint32_t py = 0; py < kImageSize; ++py)
    for (uint32_t px = 0; px < kImageSize; ++px) {
      const PixelGeom g = pixelGeom(metalScene.cameras[0], px, py, false, dvec3(kLightOverGround));
      if (!g.onGround) continue;
      const size_t i = size_t(py) * kImageSize + px;
      if (m[4 * i] > brightest) brightest = m[4 * i], brightestAt = i;
      const dvec3 wm = metalModel(g.hit), wd = dielModel(g.hit);
      if (!(wm.g < 0.01 * wd.g)) continue;
      ++dark;
      const dvec3 tm = tol.at(g, metalModel);
      EXPECT_LE(m[4 * i + 1], 0.01 * wd.g + tm.g) << "pixel " << px << "," << py;
      EXPECT_GT(d[4 * i + 1], 0.1 * wd.g) << "pixel " << px << "," << py;
    }
  std::printf("[metal] %zu dark pixels (model metal < 1%% of dielectric); brightest metal r %.3f\n", dark, brightest);
  EXPECT_GT(dark, 100u);
  EXPECT_GT(m[4 * brightestAt], m[4 * brightestAt + 1]);
  EXPECT_GT(m[4 * brightestAt + 1], m[4 * brightestAt + 2]);
}

// A w x h texture filled by f(i, j) -> 8-bit grey, alpha 255.
Texture greyTexture(const std::string& name, uint32_t w, uint32_t h, bool srgb,
                    const std::function<uint8_t(uint32_t, uint32_t)>& f) {
  Texture t{name, w, h, srgb, {}};
  for (uint32_t j = 0; j < h; ++j)
    for (uint32_t i = 0; i < w; ++i) {
      const uint8_t g = f(i, j);
      t.rgba.insert(t.rgba.end(), {g, g, g, 255});
    }
  return t;
}

// The effective base colour w the GPU used at a ground pixel: the colour is affine in the base
// (k_d base / pi + specular), so w = (c - c*(0)) / (c*(1) - c*(0)) from the green channel.
struct BaseProbe {
  CpuMaterial white{dvec3(1.0), 0.0, 1.0}, black{dvec3(0.0), 0.0, 1.0};
  double at(const Scene& scene, const PixelGeom& g, float green, const Tol& tol, double* wTol) const {
    const auto mw = modelFor(scene, white), mb = modelFor(scene, black);
    const double cw = mw(g.hit).g, cb = mb(g.hit).g;
    if (wTol) *wTol = tol.at(g, mw).g / (cw - cb);
    return (double(green) - cb) / (cw - cb);
  }
};

// 4. A checker base-colour texture is sampled: along a row, bright and dark squares alternate
// where the CPU says they do.
TEST_F(ShadingTest, CheckerTextureShowsAlternatingSquares) {
  Material m = gpuMaterial({dvec3(1.0), 0.0, 1.0});
  m.baseColorTexture = 0;
  Scene scene = groundScene(m, glm::vec3(0.0f, 3.0f, 0.0f), false);
  scene.textures.push_back(
      greyTexture("checker", 8, 8, true, [](uint32_t i, uint32_t j) { return uint8_t((i + j) % 2 == 0 ? 255 : 0); }));
  const std::vector<float> rgba = renderColor(*ctx, scene);
  // 8 texels over 4 m and a ground pixel of <= ~5 cm: <= 0.1 texel per pixel, so the sampler
  // magnifies (level 0, bilinear). Within 0.25 texel of a texel centre (per axis) bilinear
  // weights give the own colour >= 0.75^2 + 0.25^2 = 0.625 (the diagonal neighbours share it), so
  // the effective base is >= 0.625 on white, <= 0.375 on black; the GPU's uv is off by far less
  // than the 0.25-texel margin (the position error above, < 1e-3 texel).
  const BaseProbe probe;
  const Tol tol(*ctx);
  size_t transitions = 0, expectedTransitions = 0, classified = 0, rows = 0;
  for (uint32_t py = 0; py < kImageSize; ++py) {
    // Rows whose middle runs within 0.1 texel of a row of texel centres (v varies little along a row).
    const PixelGeom mid = pixelGeom(scene.cameras[0], kImageSize / 2, py, false, dvec3(scene.lights[0].position));
    const double vMid = (mid.hit.z + kHalf) / (2 * kHalf) * 8;
    if (!mid.onGround || std::abs(vMid - std::floor(vMid) - 0.5) > 0.1) continue;
    ++rows;
    int lastGpu = -1, lastCpu = -1;
    for (uint32_t px = 0; px < kImageSize; ++px) {
      const PixelGeom g = pixelGeom(scene.cameras[0], px, py, false, dvec3(scene.lights[0].position));
      if (!g.onGround) continue;
      const double u = (g.hit.x + kHalf) / (2 * kHalf) * 8, v = (g.hit.z + kHalf) / (2 * kHalf) * 8;
      if (std::abs(u - std::floor(u) - 0.5) > 0.25 || std::abs(v - std::floor(v) - 0.5) > 0.25) continue;
      const int white = (int(std::floor(u)) + int(std::floor(v))) % 2 == 0;
      double wTol = 0;
      const double w = probe.at(scene, g, rgba[4 * (size_t(py) * kImageSize + px) + 1], tol, &wTol);
      const int gpuWhite = w >= 0.625 - wTol ? 1 : w <= 0.375 + wTol ? 0 : -1;
      EXPECT_EQ(gpuWhite, white) << "pixel " << px << "," << py << " uv*8 (" << u << ", " << v << ") w " << w;
      ++classified;
      transitions += lastGpu >= 0 && gpuWhite != lastGpu;
      expectedTransitions += lastCpu >= 0 && white != lastCpu;
      lastGpu = gpuWhite;
      lastCpu = white;
    }
  }
  std::printf("[checker] %zu rows, %zu pixels classified, %zu transitions (expected %zu)\n", rows, classified,
              transitions, expectedTransitions);
  EXPECT_GE(expectedTransitions, 12u);
  EXPECT_EQ(transitions, expectedTransitions);
}

// 4b. sRGB textures are decoded by the sampler: a uniform sRGB grey of code 188 shades as the
// linear base srgbToLinear(188/255) = 0.503, not 188/255 = 0.737.
TEST_F(ShadingTest, SrgbTextureIsDecodedToLinear) {
  Material m = gpuMaterial({dvec3(1.0), 0.0, 1.0});
  m.baseColorTexture = 0;
  Scene scene = groundScene(m, glm::vec3(0.0f, 3.0f, 0.0f), false);
  scene.textures.push_back(greyTexture("grey188", 4, 4, true, [](uint32_t, uint32_t) { return uint8_t(188); }));
  const std::vector<float> rgba = renderColor(*ctx, scene);
  // Vulkan leaves the decode's accuracy open; demand what identifies the code: the effective base
  // w, widened by the shading tolerance, is closer to decode(188) than to decode(187) or (189).
  // A uniform texture filters to itself (bilinear weights sum to 1).
  const double want = srgbToLinear(188.0 / 255.0);
  const double halfStep = 0.5 * std::min(want - srgbToLinear(187.0 / 255.0), srgbToLinear(189.0 / 255.0) - want);
  const BaseProbe probe;
  const Tol tol(*ctx);
  double maxErr = 0;
  size_t n = 0;
  for (uint32_t py = 0; py < kImageSize; py += 3)
    for (uint32_t px = 0; px < kImageSize; px += 3) {
      const PixelGeom g = pixelGeom(scene.cameras[0], px, py, false, dvec3(scene.lights[0].position));
      if (!g.onGround) continue;
      double wTol = 0;
      const double w = probe.at(scene, g, rgba[4 * (size_t(py) * kImageSize + px) + 1], tol, &wTol);
      EXPECT_LT(std::abs(w - want) + wTol, halfStep) << "pixel " << px << "," << py << " w " << w;
      maxErr = std::max(maxErr, std::abs(w - want));
      ++n;
    }
  std::printf("[srgb] %zu px, effective base max |w - %.5f| = %.3g (half step %.3g)\n", n, want, maxErr, halfStep);
  EXPECT_GT(n, 300u);
}

// 5. With shadows off, or with no light casting shadows, no acceleration structure is built, the
// shadow pass is skipped and every light is visible: the ground behind the occluder is lit.
TEST_F(ShadingTest, WithoutShadowsEveryLightIsVisible) {
  const CpuMaterial mat{{0.8, 0.7, 0.6}, 0.0, 0.5};
  const Scene shadowed = groundScene(gpuMaterial(mat), kLightForShadow, true);
  Scene noCaster = shadowed;
  noCaster.lights[0].castShadows = false;
  RenderSettings off;
  off.effects.add(EffectSource::Config, "test", {{"shadows", false}});

  struct Case {
    const char* name;
    const Scene* scene;
    RenderSettings settings;
  };
  std::vector<float> reference;
  {
    RenderSettings s;
    s.width = s.height = kImageSize;
    Renderer r(*ctx, shadowed, s);
    ASSERT_NE(r.accel(), nullptr);
    r.renderFrame();
    reference = r.readColor();
  }
  for (const Case& c : {Case{"effects.shadows = false", &shadowed, off}, Case{"castShadows = false", &noCaster, {}}}) {
    SCOPED_TRACE(c.name);
    RenderSettings s = c.settings;
    s.width = s.height = kImageSize;
    Renderer r(*ctx, *c.scene, s);
    EXPECT_EQ(r.accel(), nullptr);
    EXPECT_FALSE((shadowsOf(r) != nullptr));
    r.renderFrame();
    bool skipped = false;
    for (const auto& [pass, why] : r.passesSkipped()) skipped = skipped || pass == "shadows";
    EXPECT_TRUE(skipped);
    for (const std::string& pass : r.passesRun()) EXPECT_NE(pass, "shadows");
    const std::vector<float> rgba = r.readColor();
    const Tol tol(*ctx);
    // Behind the occluder: lit as the model says, where the shadowed render is black.
    const Stats behind = compareGround(
        rgba, *c.scene, tol, true, [](const PixelGeom& g) { return g.shadowed; }, modelFor(*c.scene, mat));
    const Stats blackBefore = compareGround(
        reference, shadowed, tol, true, [](const PixelGeom& g) { return g.shadowed; },
        [](const dvec3&) { return dvec3(0.0); });
    // Elsewhere on the ground: the same as with shadows, within the tolerance of each.
    const Stats outside = compareGround(
        rgba, *c.scene, tol, true, [](const PixelGeom& g) { return g.lit; }, modelFor(*c.scene, mat));
    size_t identical = 0, litPixels = 0;
    for (uint32_t py = 0; py < kImageSize; ++py)
      for (uint32_t px = 0; px < kImageSize; ++px) {
        const PixelGeom g = pixelGeom(shadowed.cameras[0], px, py, true, dvec3(kLightForShadow));
        if (!g.onGround || !g.lit) continue;
        const size_t i = size_t(py) * kImageSize + px;
        ++litPixels;
        identical += rgba[4 * i] == reference[4 * i] && rgba[4 * i + 1] == reference[4 * i + 1] &&
                     rgba[4 * i + 2] == reference[4 * i + 2];
      }
    behind.print("behind occluder, unshadowed");
    std::printf("[%s] outside the shadow %zu of %zu px bit-identical to the shadowed render\n", c.name, identical,
                litPixels);
    EXPECT_GT(behind.checked, 100u);
    EXPECT_EQ(behind.bad, 0u);
    EXPECT_EQ(blackBefore.bad, 0u);
    EXPECT_EQ(outside.bad, 0u);
  }
}

// 6. The atrium (small: ~65k triangles, 10 lights) renders with no NaN or Inf in the HDR target.
TEST_F(ShadingTest, AtriumHasNoNanOrInf) {
  const Scene scene = makeAtrium({0.25, 10, 1});
  RenderSettings s;
  s.width = 320;
  s.height = 180;
  Renderer r(*ctx, scene, s);
  r.renderFrame();
  const std::vector<float> rgba = r.readColor();
  ASSERT_EQ(rgba.size(), size_t(320) * 180 * 4);
  size_t nonFinite = 0, lit = 0;
  for (size_t i = 0; i < rgba.size(); ++i) nonFinite += !std::isfinite(rgba[i]);
  for (size_t i = 0; i < rgba.size(); i += 4) lit += rgba[i] + rgba[i + 1] + rgba[i + 2] > 0.0f;
  std::printf("[atrium] %zu non-finite values, %zu of %zu pixels lit\n", nonFinite, lit, rgba.size() / 4);
  EXPECT_EQ(nonFinite, 0u);
  EXPECT_GT(lit, rgba.size() / 4 / 10);  // not a black frame
}

}  // namespace
}  // namespace hb
