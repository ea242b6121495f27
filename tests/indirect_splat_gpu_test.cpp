// The photon splats on the real device (effects/indirect/indirect_pass.h; shaders/indirect/
// photon_splat*.glsl*): both splats bit-for-bit deterministic and close to each other, both against
// the CPU's double sum of the GPU's own photons (reference/photon_ref.h), and max_anisotropy's
// footprints. The rest of indirect light: indirect_gpu_test.cpp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "base/numbers.h"
#include "effects/indirect/indirect_analysis.h"
#include "effects/indirect/indirect_part.h"
#include "effects/shadows/shadows_part.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "indirect_test_scenes.h"
#include "reference/photon_ref.h"
#include "scene/camera.h"
#include "scene/mesh_builder.h"

namespace hb {
namespace {

using namespace indirect_testing;  // indirect_test_scenes.h

class IndirectSplatGpuTest : public testing::GpuTest {};

// Every slot is written every frame and the splat is one draw in slot order (additive blending
// in primitive order): the irradiance is bit for bit the same frame after frame and renderer
// after renderer.
TEST_F(IndirectSplatGpuTest, LdmIrradianceIsBitForBitDeterministic) {
  const Scene scene = diffuseBox("box-and-block", true);
  std::map<std::string, std::vector<float>> bySplat;
  for (const char* splat : {"compute", "raster"}) {  // both sum the slots in slot order
    SCOPED_TRACE(splat);
    const RenderSettings rs = indirectSettings(
        48, 32, {{"method", "ldm"}, {"directions", 64}, {"photons", 8}, {"ldm_resolution", 64}, {"splat", splat}});
    std::vector<float> first, second, other;
    {
      Renderer r(*ctx, scene, rs);
      r.renderFrame(true);
      first = indirectPassOf(r)->readIrradiance();
      r.renderFrame(true);
      second = indirectPassOf(r)->readIrradiance();
    }
    {
      Renderer r(*ctx, scene, rs);
      r.renderFrame(true);
      other = indirectPassOf(r)->readIrradiance();
    }
    ASSERT_EQ(first.size(), size_t(48 * 32 * 4));
    ASSERT_EQ(second.size(), first.size());
    ASSERT_EQ(other.size(), first.size());
    size_t lit = 0;
    for (size_t i = 0; i < first.size(); i += 4) lit += first[i] > 0.0f;
    std::printf("box and block, ldm, splat=%s: %zu of %d pixels lit; frames %s, renderers %s\n", splat, lit, 48 * 32,
                std::memcmp(first.data(), second.data(), first.size() * 4) == 0 ? "identical" : "DIFFER",
                std::memcmp(first.data(), other.data(), first.size() * 4) == 0 ? "identical" : "DIFFER");
    EXPECT_GT(lit, size_t(48 * 32 / 2));  // not vacuous: most of the box is lit indirectly
    EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(first.data(), other.data(), first.size() * sizeof(float)), 0);
    bySplat[splat] = first;
  }
  // The two splats on a perspective view of a box: the same terms in the same order, but for a
  // pixel centre on a quad's edge or a receiver off the photon's plane at the quad's edge
  // (photon_splat.comp.glsl). How far apart they are is printed; the bound that holds them to
  // each other is TheSplatIsTheCpuDoubleSumOfTheGpusOwnPhotons's, where every receiver is on the
  // photons' plane.
  const std::vector<float>&c = bySplat["compute"], &r = bySplat["raster"];
  double num = 0, den = 0, maxE = 0, maxDiff = 0;
  size_t equal = 0;
  for (size_t i = 0; i < c.size(); ++i) {
    if (i % 4 == 3) continue;
    num += (double(c[i]) - r[i]) * (double(c[i]) - r[i]);
    den += double(r[i]) * r[i];
    maxE = std::max(maxE, double(r[i]));
    maxDiff = std::max(maxDiff, std::abs(double(c[i]) - r[i]));
    equal += c[i] == r[i];
  }
  std::printf(
      "box and block: compute vs raster splat: relative MSE %.3g, largest difference %.3g of max E, %zu of %zu "
      "values equal\n",
      num / den, maxDiff / maxE, equal, c.size() / 4 * 3);
}

// Both splats (photon_splat.comp.glsl; photon_splat.{vert,frag}.glsl) against the CPU's double sum of photon_ref.h
// splatIrradiance over the GPU's own stored photons, at the pixels' own floor points. A floor and
// a ceiling 2 m apart, an orthographic camera looking straight down from under the ceiling: every
// pixel shows the floor, every stored photon lies on it (the ceiling's are hidden). The receivers
// y are the GPU's own (the shadow pass's analysis positions: surface.glsl.inc's worldPos, the body
// the splat's fragment stage runs), checked against the double reconstruction from depth.
TEST_F(IndirectSplatGpuTest, TheSplatIsTheCpuDoubleSumOfTheGpusOwnPhotons) {
  Scene scene;
  scene.name = "floor-and-ceiling";
  scene.materials.push_back(diffuse(0.6f));
  MeshBuilder mb("floor-and-ceiling");
  addQuad(mb, 0, {-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}, {0, 1, 0});
  addQuad(mb, 0, {-10, 2, -10}, {10, 2, -10}, {10, 2, 10}, {-10, 2, 10}, {0, -1, 0});
  mb.appendTo(scene);
  scene.lights.push_back(pointLight({0.3f, 1.0f, 0.2f}, 10.0f));
  Camera cam;
  cam.projection = CameraProjection::Orthographic;
  cam.xmag = cam.ymag = 3.0f;
  cam.view = lookAt({0, 1.9f, 0}, {0, 0, 0}, {0, 0, -1});
  cam.znear = 0.05f;
  cam.zfar = 10.0f;
  scene.cameras.push_back(cam);
  constexpr uint32_t W = 96, H = 96;
  // Both splats (splat=compute, the default, and splat=raster) of the same photons.
  auto settingsWith = [&](const char* splat) {
    RenderSettings rs;
    rs.width = W;
    rs.height = H;
    rs.lightCulling = false;  // the light tiles are frusta of a perspective view
    rs.effects.add(EffectSource::Config, "test",
                   {{"shadows", true},
                    {"indirect", {{"method", "raytraced"}, {"directions", 64}, {"photons", 8}, {"splat", splat}}}});
    return rs;
  };
  std::vector<float> rasterE;
  std::vector<gpu::Photon> rasterPhotons;
  {
    Renderer raster(*ctx, scene, settingsWith("raster"));
    raster.renderFrame(true);
    ASSERT_NE(indirectPassOf(raster), nullptr);
    rasterE = indirectPassOf(raster)->readIrradiance();
    rasterPhotons = indirectPassOf(raster)->readPhotons();
  }
  Renderer r(*ctx, scene, settingsWith("compute"));
  r.renderFrame(true);
  ASSERT_NE(indirectPassOf(r), nullptr);
  const IndirectPass& pass = *indirectPassOf(r);
  const std::vector<float> gpuE = pass.readIrradiance();
  const std::vector<gpu::Photon> photons = pass.readPhotons();
  ASSERT_EQ(rasterPhotons.size(), photons.size());
  ASSERT_EQ(std::memcmp(rasterPhotons.data(), photons.data(), photons.size() * sizeof(gpu::Photon)), 0)
      << "the same photons under either splat";
  ASSERT_EQ(rasterE.size(), gpuE.size());
  const std::vector<float> depth = r.readDepth();
  const ShadowReadback sh = shadowsOf(r)->readShadows();
  ASSERT_EQ(gpuE.size(), size_t(W * H * 4));
  ASSERT_EQ(depth.size(), size_t(W * H));
  ASSERT_EQ(sh.positions.size(), size_t(W * H * 4));

  // Each pixel's floor point: the GPU's, and (a check on it) the double reconstruction from the
  // pixel centre's NDC (Vulkan: row j down), its depth and the inverse view-projection.
  const glm::dmat4 inv = glm::inverse(glm::dmat4(r.proj()) * glm::dmat4(r.view()));
  std::vector<glm::dvec3> ys(size_t(W) * H);
  double reconstruction = 0;
  for (uint32_t j = 0; j < H; ++j)
    for (uint32_t i = 0; i < W; ++i) {
      const size_t k = size_t(j) * W + i;
      ASSERT_GT(depth[k], 0.0f) << "pixel " << i << ", " << j << " sees no floor";
      const glm::dvec4 w =
          inv * glm::dvec4(2.0 * (i + 0.5) / W - 1.0, 2.0 * (j + 0.5) / H - 1.0, double(depth[k]), 1.0);
      ys[k] = glm::dvec3(sh.positions[4 * k], sh.positions[4 * k + 1], sh.positions[4 * k + 2]);
      reconstruction = std::max(reconstruction, glm::length(ys[k] - glm::dvec3(w) / w.w));
    }
  // Float reconstruction of points within 3√2 m: a few roundings of u·3 m each.
  EXPECT_LE(reconstruction, 2e-6);

  // E_cpu per pixel and channel, and a bound on what float evaluation may move each photon's
  // term by. The fragment stage computes in float, with |du|, |dv| and den = du·(dv × n): den's
  // rounding is ~5u·|du||dv| absolute, i.e. 5u·κ relative with κ = |du||dv|/|den| (large for a
  // needle-shaped footprint: du and dv nearly parallel, which the diffuse rotation of the
  // differentials makes now and then), each filter row dot(·, r) ~5u·max(|du|,|dv|)·|r|: so
  // |Δm| <= 8u·(κ|m| + 2·max(|du|,|dv|)·|r|/|den|) (8 for 5, rounding up), Δ(l²) <= δ = 2|m||Δm| + |Δm|²,
  // and the term 3E_p(1 − l²)² moves by <= 3E_p·(2(1 − l²)₊δ + δ²), plus its area's 2uκ relative.
  // For a well-conditioned photon (κ ~ 1) this is ~1e-6 of its peak.
  std::vector<glm::dvec3> cpuE(ys.size(), glm::dvec3(0.0));
  std::vector<double> conditioning(ys.size(), 0.0);  // the bound above, for Φ = 1 W
  uint64_t stored = 0, onFloor = 0;
  // The (pixel, photon) pairs inside the ellipse in double: surely (l² + δ < 1) and possibly
  // (l² − δ < 1). The ellipse lies inside its quad and the view is orthographic, so the gather's
  // counted terms (covered, facing, l² < 1 in float) lie between the two.
  uint64_t termsSure = 0, termsMaybe = 0;
  double worstKappa = 0;
  for (const gpu::Photon& p : photons) {
    if (statusOf(p) != gpu::kPhotonStored) continue;
    ++stored;
    const glm::dvec3 x(p.positionFluxR), du(p.duFluxG), dv(p.dvFluxB), n(p.normalStatus);
    if (!(n.y > 0.0)) continue;  // the fragment stage keeps photons facing the receiver's way only
    const glm::dvec3 dvn = glm::cross(dv, n), ndu = glm::cross(n, du);
    const double den = glm::dot(du, dvn), area = glm::length(glm::cross(du, dv));
    if (!(area > 0.0) || !(den != 0.0)) continue;  // the fragment stage discards it
    ++onFloor;
    const double kappa = glm::length(du) * glm::length(dv) / std::abs(den),
                 big = std::max(glm::length(du), glm::length(dv));
    worstKappa = std::max(worstKappa, kappa);
    const double ep = 1.0 / (0.25 * 3.14159265358979 * area);  // E_p per watt
    // The support lies inside x ± du/2 ± dv/2.
    const double hx = 0.5 * (std::abs(du.x) + std::abs(dv.x)) + 1e-3,
                 hz = 0.5 * (std::abs(du.z) + std::abs(dv.z)) + 1e-3;
    const glm::dvec3 phi(p.positionFluxR.w, p.duFluxG.w, p.dvFluxB.w);
    for (size_t k = 0; k < ys.size(); ++k) {
      const glm::dvec3& y = ys[k];
      if (std::abs(y.x - x.x) > hx || std::abs(y.z - x.z) > hz) continue;
      const glm::dvec3 rr = y - x;
      const glm::dvec3 m =
          (2.0 / den) * glm::dvec3(glm::dot(dvn, rr), glm::dot(ndu, rr), std::sqrt(std::abs(den)) * glm::dot(n, rr));
      const double l2 = glm::dot(m, m), lm = std::sqrt(l2);
      const double dm = 8.0 * kU * (kappa * lm + 2.0 * big * glm::length(rr) / std::abs(den));
      const double delta = 2.0 * lm * dm + dm * dm;
      if (!(l2 - delta < 1.0)) continue;
      ++termsMaybe;
      termsSure += l2 + delta < 1.0;
      const double term = splatIrradiance(x, du, dv, n, 1.0, y);
      cpuE[k] += term * phi;
      conditioning[k] +=
          (3.0 * ep * (2.0 * std::max(1.0 - l2, 0.0) * delta + delta * delta) + term * 2.0 * kU * kappa) *
          std::max({phi.x, phi.y, phi.z});
    }
  }
  // Per pixel and channel: |E_gpu − E_cpu| <= 1e-3·E_cpu + 1e-4·max E + the conditioning bound.
  // The first two: each term's own float evaluation (a few u relative) and the additive blending
  // of k terms (k·u relative, k a few hundred at most), well inside 1e-3 of E; 1e-4 of the
  // image's largest E covers terms at the kernel's edge (where the float and the double l² fall
  // either side of 1 they are (1 − l²)² ≈ 0).
  double maxE = 0;
  for (const glm::dvec3& e : cpuE) maxE = std::max({maxE, e.x, e.y, e.z});
  size_t lit = 0;
  for (size_t k = 0; k < cpuE.size(); ++k) lit += cpuE[k].x > 0.0;
  auto check = [&](const std::vector<float>& e, const char* splat) {
    size_t bad = 0, outsideBase = 0;
    double worst = 0, worstConditioning = 0;
    for (size_t k = 0; k < cpuE.size(); ++k)
      for (int c = 0; c < 3; ++c) {
        const double want = cpuE[k][c], got = e[4 * k + c];
        const double diff = std::abs(got - want), base = 1e-3 * want + 1e-4 * maxE;
        bad += diff > base + conditioning[k];
        outsideBase += diff > base;
        if (want > 1e-4 * maxE) {
          worst = std::max(worst, diff / want);
          worstConditioning = std::max(worstConditioning, conditioning[k] / want);
        }
      }
    std::printf(
        "floor under an orthographic camera, %ux%u, splat=%s: %llu stored photons (%llu on the floor, largest κ = "
        "|du||dv|/|den| %.3g), %zu pixels lit, max E %.5g W/m^2; GPU positions within %.2g m of the double "
        "reconstruction; GPU vs CPU double: largest relative difference %.3g (conditioning bound up to %.3g of E), "
        "%zu channel values beyond 1e-3·E + 1e-4·max E, %zu beyond that plus the conditioning bound\n",
        W, H, splat, (unsigned long long)stored, (unsigned long long)onFloor, worstKappa, lit, maxE, reconstruction,
        worst, worstConditioning, outsideBase, bad);
    return bad;
  };
  EXPECT_GT(onFloor, 100u);
  EXPECT_GT(lit, size_t(W * H / 2));
  EXPECT_GT(maxE, 0.0);
  EXPECT_EQ(check(gpuE, "compute"), 0u);
  const auto work = pass.splatStats();
  ASSERT_TRUE(work && work->counted);
  std::printf("the gather's counted terms %llu (CPU: %llu surely, %llu possibly inside), coverage tests %llu\n",
              (unsigned long long)work->terms, (unsigned long long)termsSure, (unsigned long long)termsMaybe,
              (unsigned long long)work->tests);
  EXPECT_GE(work->terms, termsSure);
  EXPECT_LE(work->terms, termsMaybe);
  EXPECT_GE(work->tests, work->terms);
  EXPECT_EQ(check(rasterE, "raster"), 0u);
  // The two splats sum the same terms in the same order: each within the bound above of the
  // double sum, so of each other; how many values are bit-equal is printed.
  size_t equal = 0;
  for (size_t i = 0; i < gpuE.size(); ++i) equal += std::memcmp(&gpuE[i], &rasterE[i], sizeof(float)) == 0;
  std::printf("compute and raster splats: %zu of %zu values bit-equal\n", equal, gpuE.size());
}

// A stored footprint's longest axis over its shortest: σ1/σ2 of [du dv] in the plane of n, in double
// from the stored floats.
double axisRatio(const gpu::Photon& p) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(p.normalStatus)), du(p.duFluxG), dv(p.dvFluxB);
  glm::dvec3 t1 = du - n * glm::dot(n, du);
  if (glm::dot(t1, t1) == 0.0) t1 = dv - n * glm::dot(n, dv);
  t1 = glm::normalize(t1);
  const glm::dvec3 t2 = glm::cross(n, t1);
  const double ux = glm::dot(du, t1), uy = glm::dot(du, t2), vx = glm::dot(dv, t1), vy = glm::dot(dv, t2);
  const double pp = ux * ux + vx * vx, q = uy * uy + vy * vy, r = ux * uy + vx * vy;
  const double mid = 0.5 * (pp + q), rad = std::sqrt(0.25 * (pp - q) * (pp - q) + r * r);
  const double l2 = std::max(mid - rad, 0.0);
  return l2 > 0.0 ? std::sqrt((mid + rad) / l2) : std::numeric_limits<double>::infinity();
}

// effects.indirect.max_anisotropy (indirect_common.glsl.inc limitAnisotropy): every stored footprint's
// longest axis over its shortest is at most k afterwards, where without it some are far beyond; the
// photons are the same photons (same slots, status, position and flux: only du, dv change), so the
// flux each deposits is unchanged. The ratio is σ1/σ2 of [du dv] in the plane of n, in double from
// the stored floats. Slack: the GPU's float SVD of a 2x2 loses ε·σ1²/σ2² = ε·k² relative in σ2²
// (the cancellation in mid − rad), 1e-6 at k = 4, and the stored floats move σ2 by ~ε·σ1: 1e-4
// covers both a hundred times over.
TEST_F(IndirectSplatGpuTest, MaxAnisotropyWidensNeedleFootprintsAndKeepsTheirFlux) {
  const Scene scene = diffuseBox("box-and-block", true);
  constexpr double k = 4.0;
  auto photonsWith = [&](double maxAnisotropy) {
    Renderer r(
        *ctx, scene,
        indirectSettings(
            48, 32, {{"method", "raytraced"}, {"directions", 64}, {"photons", 8}, {"max_anisotropy", maxAnisotropy}}));
    r.renderFrame(true);
    return indirectPassOf(r)->readPhotons();
  };
  const std::vector<gpu::Photon> before = photonsWith(0.0), after = photonsWith(k);
  ASSERT_EQ(before.size(), after.size());
  size_t stored = 0, needles = 0, beyond = 0, sameOtherwise = 0;
  double worstBefore = 0, worstAfter = 0;
  for (size_t i = 0; i < before.size(); ++i) {
    const gpu::Photon &a = before[i], &b = after[i];
    sameOtherwise += std::memcmp(&a.positionFluxR, &b.positionFluxR, sizeof a.positionFluxR) == 0 &&
                     a.duFluxG.w == b.duFluxG.w && a.dvFluxB.w == b.dvFluxB.w &&
                     std::memcmp(&a.normalStatus, &b.normalStatus, sizeof a.normalStatus) == 0;
    if (statusOf(a) != gpu::kPhotonStored) continue;
    ++stored;
    const double ra = axisRatio(a), rb = axisRatio(b);
    needles += ra > k;
    beyond += rb > k * (1.0 + 1e-4);
    worstBefore = std::max(worstBefore, ra);
    worstAfter = std::max(worstAfter, rb);
  }
  std::printf(
      "box and block, raytraced: %zu stored photons, %zu with an axis ratio over %.0f (largest %.3g); with "
      "max_anisotropy %.0f: %zu over it (largest %.6g)\n",
      stored, needles, k, worstBefore, k, beyond, worstAfter);
  EXPECT_EQ(sameOtherwise, before.size());  // the same photons: position, flux, normal and status
  EXPECT_GT(stored, 1000u);
  EXPECT_GT(needles, 0u);  // not vacuous: some footprints are needles
  EXPECT_EQ(beyond, 0u);
}

// effects.indirect.footprint "cell" (indirect_common.glsl.inc splitDifferentials): the same photons
// as the paper's footprints (slot by slot the same position, flux, normal and status: only du, dv
// change), with fewer needles (axis ratio over 4; the paper's leave many: the test above) and,
// against the gathered reference, a smaller relative MSE: the streaks were error.
TEST_F(IndirectSplatGpuTest, CellFootprintsChangeOnlyTheFootprintsAndLeaveFewerNeedles) {
  const Scene scene = diffuseBox("box-and-block", true);
  auto run = [&](const char* footprint, std::vector<gpu::Photon>& photons) {
    Renderer r(
        *ctx, scene,
        indirectSettings(
            48, 32,
            {{"method", "raytraced"}, {"directions", 64}, {"photons", 8}, {"samples", 256}, {"footprint", footprint}}));
    r.renderFrame(true);
    IndirectPass& pass = *indirectPassOf(r);
    photons = pass.readPhotons();
    const std::vector<float> mine = pass.readIrradiance(), reference = pass.computeWith(IndirectMethod::Reference);
    return indirectErrors(mine, reference, 48, 32).relMse;
  };
  std::vector<gpu::Photon> rotated, cell;
  const double rotatedError = run("rotated", rotated), cellError = run("cell", cell);
  ASSERT_EQ(rotated.size(), cell.size());
  size_t same = 0, stored = 0, rotatedNeedles = 0, cellNeedles = 0;
  for (size_t i = 0; i < cell.size(); ++i) {
    const gpu::Photon &a = rotated[i], &b = cell[i];
    same += std::memcmp(&a.positionFluxR, &b.positionFluxR, sizeof a.positionFluxR) == 0 &&
            a.duFluxG.w == b.duFluxG.w && a.dvFluxB.w == b.dvFluxB.w &&
            std::memcmp(&a.normalStatus, &b.normalStatus, sizeof a.normalStatus) == 0;
    if (statusOf(a) != gpu::kPhotonStored) continue;
    ++stored;
    rotatedNeedles += axisRatio(a) > 4.0;
    cellNeedles += axisRatio(b) > 4.0;
  }
  std::printf(
      "box and block: %zu stored photons, axis ratio over 4: rotated %zu, cell %zu; relative MSE against "
      "the reference: rotated %.4f, cell %.4f\n",
      stored, rotatedNeedles, cellNeedles, rotatedError, cellError);
  EXPECT_EQ(same, cell.size());
  EXPECT_GT(stored, 1000u);
  EXPECT_LT(cellNeedles, rotatedNeedles);
  EXPECT_LT(cellError, rotatedError);
}

}  // namespace
}  // namespace hb
