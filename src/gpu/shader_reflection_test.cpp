#include "gpu/shader_reflection.h"

#include <gtest/gtest.h>

#include "gpu/vk_pipeline.h"

namespace hb {
namespace {

std::vector<std::string> namesOf(const std::vector<ShaderBinding>& bindings) {
  std::vector<std::string> names;
  for (const ShaderBinding& b : bindings) names.push_back(b.name);
  return names;
}

TEST(ShaderReflection, ReadsTheBlocksAndSamplerALightCullingShaderDeclaresInDeclarationOrder) {
  const std::vector<ShaderBinding> b = reflectBindings("light_cull.comp", embeddedSpirv("light_cull.comp"));
  EXPECT_EQ(namesOf(b), (std::vector<std::string>{"Frame", "Lights", "Frustums", "Grid", "Indices", "depthTex",
                                                  "ViewLights", "ViewSpheres"}));
  for (uint32_t i = 0; i < b.size(); ++i) {
    EXPECT_EQ(b[i].binding, i) << b[i].name;
    EXPECT_EQ(b[i].set, 0u) << b[i].name;
    EXPECT_EQ(b[i].count, 1u) << b[i].name;
    EXPECT_EQ(b[i].stages, VkShaderStageFlags(VK_SHADER_STAGE_COMPUTE_BIT)) << b[i].name;
  }
  EXPECT_EQ(b[0].type, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
  EXPECT_EQ(b[1].type, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  EXPECT_EQ(b[5].type, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
}

TEST(ShaderReflection, AProgramMergesItsShadersByNameAndRewritesTheNumbersOfTheLaterOnes) {
  // tile_frustums reads Frame, Frustums; zbin_bins Frame, Indices, Extents (each from 0).
  const ShaderProgram p({"tile_frustums.comp", "zbin_bins.comp"});
  EXPECT_EQ(p.label(), "tile_frustums.comp + zbin_bins.comp");
  EXPECT_EQ(namesOf(p.bindings()), (std::vector<std::string>{"Frame", "Frustums", "Indices", "Extents"}));
  for (uint32_t i = 0; i < p.bindings().size(); ++i) EXPECT_EQ(p.bindings()[i].binding, i);
  EXPECT_EQ(p.find("Extents")->binding, 3u);
  EXPECT_EQ(p.find("Lights"), nullptr);
  // The rewritten SPIR-V says the program's numbers: Indices 1 -> 2, Extents 2 -> 3.
  const std::vector<ShaderBinding> bins = reflectBindings("zbin_bins.comp", p.spirv(1));
  ASSERT_EQ(namesOf(bins), (std::vector<std::string>{"Frame", "Indices", "Extents"}));
  EXPECT_EQ(bins[0].binding, 0u);
  EXPECT_EQ(bins[1].binding, 2u);
  EXPECT_EQ(bins[2].binding, 3u);
}

TEST(ShaderReflection, TheBindlessTexturesAreTheLastBindingOfTheForwardShadingProgram) {
  // shading.frag declares `textures[]` second; a variable-count array must be the set's last binding.
  const ShaderProgram p({"shading.vert", "shading.frag"});
  ASSERT_FALSE(p.bindings().empty());
  const ShaderBinding& last = p.bindings().back();
  EXPECT_EQ(last.name, "textures");
  EXPECT_EQ(last.count, 0u);
  EXPECT_EQ(last.type, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  EXPECT_EQ(last.binding, uint32_t(p.bindings().size() - 1));
  for (const ShaderBinding& b : reflectBindings("shading.frag", p.spirv("shading.frag")))
    EXPECT_EQ(b.binding, p.find(b.name)->binding)
        << b.name << ": the fragment shader's SPIR-V says the program's number";
}

TEST(ShaderReflection, NamesTheShaderWhoseSpirvCannotBeRead) {
  std::vector<uint32_t> spirv = embeddedSpirv("tile_frustums.comp");
  spirv[0] = 0;  // the magic number
  try {
    reflectBindings("tile_frustums.comp", spirv);
    FAIL() << "no error";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("shader tile_frustums.comp"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hb
