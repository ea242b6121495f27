// Indirect light beyond one bounce on the real device (effects.indirect.bounces; shaders/indirect/
// indirect_common.glsl.inc bounceTrace): in a closed diffuse box every bounce reflects what the one
// before it landed, times the albedo and the direction quadrature, for both photon traces; each
// bounce only adds light; a multi-bounce frame is bit-for-bit deterministic; and the settings'
// errors.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "base/errors.h"
#include "effects/indirect/indirect_effect.h"
#include "effects/indirect/indirect_part.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "indirect_test_scenes.h"
#include "reference/eq_partition.h"

namespace hb {
namespace {

using namespace indirect_testing;  // indirect_test_scenes.h

class IndirectBouncesGpuTest : public testing::GpuTest {};

// The flux of slots [first, first + count) by status: every slot's (what its bounce split off),
// and the part that landed (stored, hidden, grazing: what the next bounce reflects).
struct BounceFlux {
  double reflected = 0, landed = 0, escapedFlux = 0;
  uint64_t escaped = 0, empty = 0;
};
BounceFlux bounceFlux(const std::vector<gpu::Photon>& photons, uint64_t first, uint64_t count) {
  BounceFlux f;
  for (uint64_t s = first; s < first + count; ++s) {
    const uint32_t status = statusOf(photons[s]);
    const double flux = fluxOf(photons[s]);
    if (status == gpu::kPhotonEmpty) {
      ++f.empty;
      continue;
    }
    f.reflected += flux;
    if (status == gpu::kPhotonEscaped) {
      ++f.escaped;
      f.escapedFlux += flux;
    } else {
      f.landed += flux;
    }
  }
  return f;
}

// Bounce b's photons are the landings of bounce b − 1 reflected (albedo 0.5 everywhere) and split
// again. With bounce_directions >= N every split uses all N directions (M_b = N: the strided subset
// is the whole set, whatever its hash offset), with weights 2|n·v_j|/N summing to q(n) =
// (2/N)·Σ_j |n·v_j|, and the box's walls have axis normals (the landing triangle's own, exact to
// a few ulps): so bounce b's flux lies in 0.5·landed_{b−1}·[min q, max q] over the three axes,
// to float rounding of the per-photon products (a few u, 2^-24) and the double tally. Asserted
// with 1e-5 of slack. Escaped photons count in their bounce's flux (they left x with it). Even the
// ray tracer loses a few in the closed box: the axis-aligned box and directions (N = 16 has
// directions in the coordinate planes) put some landings on an edge of the box, and a photon sent
// from there along the plane of the adjacent wall passes between its triangles (0.003 % of bounce
// 3's flux here). The LDM trace also skips walls within its bias (indirect_gpu_test.cpp's closed
// box). A photon that lands nowhere leaves the next bounce's slots empty.
TEST_F(IndirectBouncesGpuTest, InAClosedBoxEveryBounceReflectsWhatTheLastOneLanded) {
  const Scene scene = diffuseBox("closed-box", false);
  constexpr uint32_t N = 16, kSide = 4, K = 3;
  glm::dvec3 q(0.0);
  for (const glm::dvec3& v : ldmDirections(N)) q += glm::abs(v);
  q *= 2.0 / double(N);
  const double qMin = std::min({q.x, q.y, q.z}), qMax = std::max({q.x, q.y, q.z});
  for (const char* method : {"raytraced", "ldm"}) {
    SCOPED_TRACE(method);
    Renderer r(*ctx, scene,
               indirectSettings(48, 32,
                                {{"method", method},
                                 {"directions", N},
                                 {"photons", kSide},
                                 {"ldm_resolution", 64},
                                 {"ldm_list", "sbuffer"},
                                 {"bounces", K},
                                 {"bounce_directions", 2 * N}}));
    r.renderFrame(true);
    const IndirectPass& pass = *indirectPassOf(r);
    ASSERT_EQ(pass.bounceSlots(2), pass.bounceSlots(1) * N);
    ASSERT_EQ(pass.bounceSlots(3), pass.bounceSlots(2) * N);
    const std::vector<gpu::Photon> photons = pass.readPhotons();
    ASSERT_EQ(photons.size(), pass.slots());
    BounceFlux previous = bounceFlux(photons, 0, pass.bounceSlots(1));
    for (uint32_t b = 2; b <= K; ++b) {
      const BounceFlux f = bounceFlux(photons, pass.bounceFirstSlot(b), pass.bounceSlots(b));
      const double ratio = f.reflected / (0.5 * previous.landed);
      std::printf(
          "closed box, %s, N=%u: bounce %u reflects %.6g W of the %.6g W bounce %u landed: ratio %.6f "
          "(q in [%.5f, %.5f]), %llu slots escaped (%.3g of the flux), %llu empty\n",
          method, N, b, f.reflected, previous.landed, b - 1, ratio, qMin, qMax, (unsigned long long)f.escaped,
          f.escapedFlux / f.reflected, (unsigned long long)f.empty);
      EXPECT_GE(ratio, qMin - 1e-5);
      EXPECT_LE(ratio, qMax + 1e-5);
      previous = f;
    }
  }
}

// Each bounce only adds light: the splat sums every slot in slot order (bounce 1's first), so the
// K-bounce frame's irradiance is the (K − 1)-bounce frame's plus non-negative terms, and adding a
// non-negative float never lowers a sum: E_K >= E_{K−1} in every pixel and channel, exactly. The
// gathered reference follows its paths one bounce further (its total grows too). A K-bounce frame
// rendered twice is bit-for-bit the same (fixed slots; each thread retraces its own chain).
TEST_F(IndirectBouncesGpuTest, EachBounceAddsLightAndMultiBounceFramesAreDeterministic) {
  const Scene scene = diffuseBox("block-box", true);
  auto settings = [](const char* method, uint32_t k) {
    return indirectSettings(64, 40,
                            {{"method", method},
                             {"directions", 32},
                             {"photons", 4},
                             {"ldm_resolution", 64},
                             {"ldm_list", "sbuffer"},
                             {"samples", 64},
                             {"bounces", k},
                             {"bounce_directions", 4}});
  };
  for (const char* method : {"ldm", "raytraced", "reference"}) {
    SCOPED_TRACE(method);
    std::vector<float> previous;
    double previousTotal = 0;
    for (uint32_t k = 1; k <= 3; ++k) {
      Renderer r(*ctx, scene, settings(method, k));
      r.renderFrame(true);
      const std::vector<float> e = indirectPassOf(r)->readIrradiance();
      double total = 0;
      for (size_t i = 0; i < e.size(); i += 4) total += double(e[i]) + e[i + 1] + e[i + 2];
      std::printf("%s, K=%u: total irradiance %.6g\n", method, k, total);
      if (!previous.empty()) {
        EXPECT_GT(total, previousTotal);
        if (std::string(method) != "reference") {
          for (size_t i = 0; i < e.size(); ++i) {
            if ((i & 3) != 3) {
              ASSERT_GE(e[i], previous[i]) << "value " << i;
            }
          }
        }
      }
      if (k == 3 && std::string(method) != "reference") {
        r.renderFrame(true);
        EXPECT_EQ(indirectPassOf(r)->readIrradiance(), e) << "a second frame differs";
      }
      previous = e;
      previousTotal = total;
    }
  }
}

TEST(IndirectBounces, SettingsOutsideTheirRangesAreOneLineNamingTheSetting) {
  auto errorOf = [](const nlohmann::json& v) -> std::string {
    try {
      indirectSettingsOf(v);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(errorOf({{"method", "ldm"}, {"bounces", 2}, {"ldm_list", "sbuffer"}}), "");
  EXPECT_EQ(errorOf({{"method", "raytraced"}, {"bounces", 3}}), "");
  EXPECT_NE(errorOf({{"bounces", 5}}).find("indirect.bounces"), std::string::npos);
  EXPECT_NE(errorOf({{"bounce_directions", 0}}).find("indirect.bounce_directions"), std::string::npos);
  EXPECT_NE(errorOf({{"footprint", "round"}}).find("indirect.footprint"), std::string::npos);
  IndirectSettings s = indirectSettingsOf({{"directions", 64}, {"bounces", 4}, {"bounce_directions", 8}});
  EXPECT_EQ(s.directionsAtBounce(1), 64u);
  EXPECT_EQ(s.directionsAtBounce(2), 8u);
  EXPECT_EQ(s.directionsAtBounce(3), 4u);
  EXPECT_EQ(s.directionsAtBounce(4), 2u);
  s = indirectSettingsOf({{"directions", 4}, {"bounce_directions", 16}});
  EXPECT_EQ(s.directionsAtBounce(2), 4u);  // never more than N
  // later_bounce_stride (indirect_later_stride_gpu_test.cpp): a choice, within splat_bin/16, compute only.
  EXPECT_EQ(errorOf({{"bounces", 3}, {"later_bounce_stride", 4}}), "");
  EXPECT_EQ(indirectSettingsOf({{"bounces", 3}, {"later_bounce_stride", 8}}).laterBounceStride, 8u);
  for (const auto& [v, want] : std::vector<std::pair<nlohmann::json, std::string>>{
           {{{"later_bounce_stride", 3}}, "indirect.later_bounce_stride"},
           {{{"later_bounce_stride", 8}, {"splat_bin", 64}}, "needs splat_bin >= 128"},
           {{{"later_bounce_stride", 2}, {"splat", "raster"}}, "needs splat \"compute\""}}) {
    const std::string m = errorOf(v);
    EXPECT_NE(m.find(want), std::string::npos) << v.dump() << ": " << m;
    EXPECT_NE(m.find("later_bounce_stride"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

// The LDM lists that hold no triangle ids cannot carry a photon past its first bounce: the frame
// refuses them in one line naming the setting and the fix.
TEST_F(IndirectBouncesGpuTest, LdmBouncesWithoutSbufferListsAreRefusedNamingTheFix) {
  const Scene scene = diffuseBox("closed-box", false);
  for (const char* list : {"max64", "cas"}) {
    try {
      Renderer r(
          *ctx, scene,
          indirectSettings(16, 16,
                           {{"method", "ldm"}, {"directions", 4}, {"photons", 2}, {"bounces", 2}, {"ldm_list", list}}));
      ADD_FAILURE() << list << " was accepted";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("effects.indirect.bounces: 2 bounces with method ldm need ldm_list \"sbuffer\""),
                std::string::npos)
          << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
}

}  // namespace
}  // namespace hb
