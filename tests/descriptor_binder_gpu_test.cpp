// A pass binds its resources by the names its shaders declare (gpu/descriptor_binder.h): the set's
// layout comes from the shader's reflection, and a binding nobody provides, or a name nobody
// reads, fails when the pass is built, with a message naming the pass, the shader and the name.
#include <cstring>
#include <string>

#include "bind_double_comp.h"
#include "bind_mismatch_frag.h"
#include "bind_mismatch_vert.h"
#include "gpu/descriptor_binder.h"
#include "gpu/sync.h"
#include "gpu_fixture.h"

namespace hb {
namespace {

void registerTestShaders() {
  static const bool registered =
      (registerSpirv("bind_double.comp", kSpirv_bind_double_comp, sizeof kSpirv_bind_double_comp),
       registerSpirv("bind_mismatch.vert", kSpirv_bind_mismatch_vert, sizeof kSpirv_bind_mismatch_vert),
       registerSpirv("bind_mismatch.frag", kSpirv_bind_mismatch_frag, sizeof kSpirv_bind_mismatch_frag), true);
  (void)registered;
}

// The message of the std::logic_error fn throws; empty (and a failure) if it throws none.
template <typename Fn>
std::string errorOf(Fn fn) {
  try {
    fn();
  } catch (const std::logic_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

class DescriptorBinderTest : public testing::GpuTest {
 protected:
  void SetUp() override {
    testing::GpuTest::SetUp();
    registerTestShaders();
  }
  static constexpr uint32_t kCount = 256;
  Buffer buffer() const { return Buffer(*ctx, kCount * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true); }
};

TEST_F(DescriptorBinderTest, ASetWrittenByTheShadersNamesRunsThePass) {
  Buffer source = buffer(), doubled = buffer();
  auto* in = static_cast<uint32_t*>(source.mapped());
  for (uint32_t i = 0; i < kCount; ++i) in[i] = i * 7 + 1;
  std::memset(doubled.mapped(), 0, kCount * 4);
  DescriptorBinder binder("bind_double");
  binder.provide("Doubled", doubled);  // in another order than the shader declares them
  binder.provide("Source", source);
  Pipeline pipeline(*ctx);
  pipeline.createCompute(binder, "bind_double.comp", 0);
  binder.checkEveryNameRead();
  ctx->submitAndWait([&](VkCommandBuffer cmd) {
    Sync sync;
    sync.use(cmd, {{source, access::kComputeRead}, {doubled, access::kComputeWrite}});
    VkDescriptorSet set = pipeline.set();
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0, 1, &set, 0, nullptr);
    vkCmdDispatch(cmd, kCount / 64, 1, 1);
    sync.use(cmd, {{doubled, Access{VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT}}});  // read back mapped
  });
  const auto* out = static_cast<const uint32_t*>(doubled.mapped());
  for (uint32_t i = 0; i < kCount; ++i) ASSERT_EQ(out[i], 2 * (i * 7 + 1)) << "element " << i;
}

TEST_F(DescriptorBinderTest, AShaderBindingThePassDoesNotProvideFailsNamingTheShaderAndTheBinding) {
  Buffer doubled = buffer();
  DescriptorBinder binder("bind_double");
  binder.provide("Doubled", doubled);
  Pipeline pipeline(*ctx);
  const std::string error = errorOf([&] { pipeline.createCompute(binder, "bind_double.comp", 0); });
  EXPECT_EQ(error, "pass bind_double: shader bind_double.comp reads binding Source, which the pass does not provide");
}

TEST_F(DescriptorBinderTest, ANameThePassProvidesThatNoShaderReadsFailsNamingThePassAndTheName) {
  Buffer source = buffer(), doubled = buffer(), extra = buffer();
  DescriptorBinder binder("bind_double");
  binder.provide("Source", source);
  binder.provide("Doubled", doubled);
  binder.provide("Halved", extra);
  Pipeline pipeline(*ctx);
  pipeline.createCompute(binder, "bind_double.comp", 0);
  const std::string error = errorOf([&] { binder.checkEveryNameRead(); });
  EXPECT_EQ(error, "pass bind_double provides Halved, which none of its shaders (bind_double.comp) reads");
}

TEST_F(DescriptorBinderTest, AnImageProvidedForABufferFailsNamingTheBinding) {
  Buffer source = buffer();
  Image image(*ctx, 16, 16, VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_STORAGE_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
  DescriptorBinder binder("bind_double");
  binder.provide("Source", source);
  binder.provide("Doubled", image, VK_IMAGE_LAYOUT_GENERAL);
  Pipeline pipeline(*ctx);
  const std::string error = errorOf([&] { pipeline.createCompute(binder, "bind_double.comp", 0); });
  EXPECT_EQ(error,
            "pass bind_double: shader bind_double.comp reads binding Doubled, which the pass provides as another kind "
            "of resource");
}

TEST(ShaderProgram, ANameTwoStagesDeclareAsDifferentKindsIsAnErrorNamingBothShaders) {
  registerTestShaders();
  const std::string error = errorOf([] { ShaderProgram({"bind_mismatch.vert", "bind_mismatch.frag"}); });
  EXPECT_EQ(error,
            "shaders bind_mismatch.vert and bind_mismatch.frag declare binding Params as a uniform buffer and as a "
            "storage buffer");
}

}  // namespace
}  // namespace hb
