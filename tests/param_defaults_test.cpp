// One owner per parameter: a parameter the config has gets its default once (config.h
// VariantParams, paramDefaults), its check once (its schema row, config.h checkParam), and every
// consumer's settings are views of it. These tests hold the frame's settings and the passes' to
// that, so a second default typed into a consumer fails here.
#include <gtest/gtest.h>

#include <tuple>

#include "analysis/culling_analysis.h"
#include "app/scene_setup.h"
#include "base/errors.h"
#include "config/config.h"
#include "effects/shadows/shadow_pass.h"
#include "frame/passes/light_culling.h"
#include "frame/render_settings.h"

namespace hb {
namespace {

// The frame's settings left at their defaults are the frame the config's defaults describe: every
// field renderSettingsFor copies from a VariantParams is compared.
TEST(ParamDefaults, RenderSettingsDefaultsAreTheConfigsDefaults) {
  const RenderSettings bare;
  const RenderSettings fromConfig = renderSettingsFor(VariantParams{}, EffectsRequest{});
#define HB_SAME(field) EXPECT_EQ(bare.field, fromConfig.field) << #field
  HB_SAME(width);
  HB_SAME(height);
  HB_SAME(tileSize);
  HB_SAME(lightCulling);
  HB_SAME(aabb);
  HB_SAME(backend);
  HB_SAME(normals);
  HB_SAME(worldPos);
  HB_SAME(rangeTest);
  HB_SAME(depthSlices);
  HB_SAME(lightLists);
  HB_SAME(tMin);
  HB_SAME(primary);
  HB_SAME(raster3dThreadBox);
  HB_SAME(raster3dListPerTile);
  HB_SAME(raster3dFrustum);
  HB_SAME(raster3dMinFrustum);
  HB_SAME(raster3dEarlyZ);
  HB_SAME(bvhWidth);
  HB_SAME(aa);
  HB_SAME(shading);
  HB_SAME(projection);
#undef HB_SAME
}

// The passes' and the CPU reference's settings: tile_size and the culling switches have no
// default of their own.
TEST(ParamDefaults, ThePassesSettingsTakeTheConfigsDefaults) {
  const VariantParams& d = paramDefaults();
  const CullingSettings culling;
  const ShadowSettings shadows;
  const CullingInputs reference;
  const auto cullingSwitches = std::tuple{d.tileSize, d.lightCulling, d.aabb, d.depthSlices};
  EXPECT_EQ(std::tuple(culling.tileSize, culling.lightCulling, culling.aabb, culling.depthSlices), cullingSwitches);
  EXPECT_EQ(culling.lists, d.lightLists);
  EXPECT_EQ(std::tuple(reference.tileSize, reference.lightCulling, reference.aabb, reference.depthSlices),
            cullingSwitches);
  EXPECT_EQ(std::tuple(shadows.tileSize, shadows.normals, shadows.worldPos, shadows.rangeTest, shadows.bvhWidth),
            std::tuple(d.tileSize, d.normalCulling, d.worldPos, d.rangeTest, d.bvhWidth));
}

// One check: a consumer given settings built without a config refuses what the config would, in
// the config's words.
TEST(ParamDefaults, ConsumersCheckByTheSchemaRow) {
  try {
    checkParam("tile_size", 12);
    FAIL() << "tile_size 12 was accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "tile_size: 12 is not one of 8, 16, 32");
  }
  for (int ok : {8, 16, 32}) EXPECT_NO_THROW(checkParam("tile_size", ok));
  EXPECT_THROW(checkParam("bvh_width", 3), InputError);
}

}  // namespace
}  // namespace hb
