// backend=auto's rule (ray_backend.h): the driver's unless the device's measured rates say ours is
// faster by the margin on both kinds of ray; a set backend always runs; the reason says why.
#include "frame/ray_backend.h"

#include <gtest/gtest.h>

namespace hb {
namespace {

DeviceInfo gpu(bool rayQuery) {
  DeviceInfo d;
  d.name = "test GPU";
  d.type = "discrete";
  d.rayQuery = rayQuery;
  d.rayTracingPipeline = true;
  return d;
}

RayRates rates(double occlusionRatio, double closestRatio) {
  RayRates r;
  r.driver = "pipeline";
  r.driverOcclusion = 2e9;
  r.computeOcclusion = 2e9 * occlusionRatio;
  r.driverClosest = 1e9;
  r.computeClosest = 1e9 * closestRatio;
  r.source = "peaks on test";
  return r;
}

TEST(RayBackend, AutoTakesComputeOnlyWhenBothRatesBeatTheMargin) {
  EXPECT_EQ(chooseBackend(RtBackend::Auto, gpu(false), rates(1.8, 1.5)).ran, RtBackend::Compute);
  EXPECT_EQ(chooseBackend(RtBackend::Auto, gpu(false), rates(1.8, 1.05)).ran, RtBackend::Pipeline);
  EXPECT_EQ(chooseBackend(RtBackend::Auto, gpu(true), rates(1.05, 1.8)).ran, RtBackend::RayQuery);
  const double m = kAutoComputeMargin;
  EXPECT_EQ(chooseBackend(RtBackend::Auto, gpu(false), rates(m, m)).ran, RtBackend::Compute);  // at the margin
  const BackendChoice c = chooseBackend(RtBackend::Auto, gpu(false), rates(1.8, 1.5));
  EXPECT_NE(c.reason.find("1.80x"), std::string::npos) << c.reason;
  EXPECT_NE(c.reason.find("peaks on test"), std::string::npos) << c.reason;
}

TEST(RayBackend, AutoKeepsTheDriversWithoutMeasurementsOrOnACpuDevice) {
  EXPECT_EQ(chooseBackend(RtBackend::Auto, gpu(true), std::nullopt).ran, RtBackend::RayQuery);
  EXPECT_EQ(chooseBackend(RtBackend::Auto, gpu(false), std::nullopt).ran, RtBackend::Pipeline);
  RayRates partial = rates(2, 2);
  partial.computeClosest = 0;  // not measured
  EXPECT_EQ(chooseBackend(RtBackend::Auto, gpu(false), partial).ran, RtBackend::Pipeline);
  DeviceInfo cpu = gpu(true);
  cpu.type = "cpu";
  const BackendChoice c = chooseBackend(RtBackend::Auto, cpu, rates(3, 3));
  EXPECT_EQ(c.ran, RtBackend::RayQuery);
  EXPECT_NE(c.reason.find("CPU"), std::string::npos) << c.reason;
}

TEST(RayBackend, ASetBackendRunsWhateverTheRates) {
  for (RtBackend b : {RtBackend::RayQuery, RtBackend::Pipeline, RtBackend::Compute}) {
    const BackendChoice c = chooseBackend(b, gpu(true), rates(b == RtBackend::Compute ? 0.5 : 3, 3));
    EXPECT_EQ(c.ran, b);
    EXPECT_EQ(c.requested, b);
  }
  const nlohmann::json j = toJson(chooseBackend(RtBackend::Auto, gpu(false), rates(2, 2)), rates(2, 2));
  EXPECT_EQ(j["requested"], "auto");
  EXPECT_EQ(j["ran"], "compute");
  EXPECT_EQ(j["rates"]["compute_occlusion_per_s"], 4e9);
}

}  // namespace
}  // namespace hb
