#include "report/noise_model.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "base/errors.h"
#include "base/input_file.h"
#include "report/compare.h"

namespace hb {
namespace {

using nlohmann::json;

json committed(const std::string& path) {
  return json::parse(readInputText(std::string(HYBRIDBENCH_SOURCE_DIR "/results/") + path + "/results.json.gz",
                                   "a committed results file"));
}

// The committed A/A pairs (docs/usage.md "Between-run noise"): one revision swept twice.
std::vector<AaPair> committedPairs() {
  const std::vector<std::pair<std::string, std::string>> names = {
      {"h200/concurrent/thesis-aa/0-nvidia-h200", "h200/concurrent/thesis-aa/1-nvidia-h200"},  // one H200, 2 at once
      {"h200/fleet-35/thesis-whole", "h200/fleet-35/thesis-merged"},        // whole, and three parts merged
      {"h200/fleet-35-x4/thesis-whole", "h200/fleet-35-x4/thesis-merged"},  // the same on a 4-GPU host
      {"h100/thesis", "h100/thesis-run2"}};                                 // H100, twice
  std::vector<AaPair> pairs;
  for (const auto& [a, b] : names) pairs.push_back({committed(a), committed(b), a, b});
  return pairs;
}

// results/noise/noise.json: the model `hybridbench noise` wrote from the committed pairs.
NoiseModel committedModel() {
  const std::string path = HYBRIDBENCH_SOURCE_DIR "/results/noise/noise.json";
  return noiseModelFromJson(json::parse(readInputText(path, "the committed noise file")), path);
}

size_t gates(const CompareReport& r) {
  return size_t(std::count_if(r.rows.begin(), r.rows.end(), [](const CompareRow& row) { return row.gates; }));
}

// Two sweeps at once on one H200 (`sweep --device 0,0`) with the driver's ray-tracing pipeline differ
// by up to 2x in shading (each sweep's times hold the other's work): within-run noise alone gates 9
// rows of that A/A pair.
// The model of the pairs holds every row of every pair, and says which noise it used.
TEST(NoiseModel, TheCommittedAaPairsRaiseNoFalseAlarmWithTheirModel) {
  const std::vector<AaPair> pairs = committedPairs();
  const NoiseModel model = buildNoiseModel(pairs);
  CompareOptions within, between;
  within.gate = between.gate = CompareGate::All;
  between.noise = &model;
  EXPECT_GT(gates(compareResults(pairs[0].a, pairs[0].b, within)), 0u);
  for (const AaPair& p : pairs) {
    const CompareReport r = compareResults(p.a, p.b, between);
    EXPECT_EQ(gates(r), 0u) << p.nameA;
    EXPECT_EQ(r.noise.rfind("between-run (a noise model: 4 A/A pairs)", 0), 0u) << r.noise;
  }
  // Keys are per device model and ray tracer: the H200's compute runs are quiet, its pipeline's swept
  // on a device shared with another sweep are not, and the H100's pipeline is quiet.
  const NoisePass* computeShading = model.find("NVIDIA H200", "compute", "shading");
  const NoisePass* pipelineShading =
      model.find("NVIDIA H200", std::string("pipeline") + kSweptOnSharedDevice, "shading");
  ASSERT_NE(computeShading, nullptr);
  ASSERT_NE(pipelineShading, nullptr);
  EXPECT_EQ(computeShading->n, 18u);  // 9 variants, 2 pairs
  EXPECT_LT(computeShading->rmsLog, 0.01);
  EXPECT_GT(pipelineShading->rmsLog, 0.1);
}

// A 10 % slowdown of a quiet pass still gates with the model, and the same slowdown of a pass whose
// A/A spread is wider is held, naming the band.
TEST(NoiseModel, AChangeGatesOnlyBeyondItsPassesBand) {
  const NoiseModel model = buildNoiseModel(committedPairs());
  CompareOptions o;
  o.gate = CompareGate::All;
  o.noise = &model;
  std::vector<double> a, b;
  for (int i = 0; i < 40; ++i) {
    a.push_back(2.0 + 0.001 * (i % 7));
    b.push_back(1.1 * a.back());
  }
  const CompareRow quiet = compareSampleSets("v", "shading", a, b, o, {"NVIDIA H200", "compute", 1e-6, 1e-6});
  EXPECT_TRUE(quiet.gates) << quiet.held;
  EXPECT_LT(quiet.bandPct, 1.0);
  const std::string shared = std::string("pipeline") + kSweptOnSharedDevice;
  const CompareRow noisy = compareSampleSets("v", "shading", a, b, o, {"NVIDIA H200", shared, 1e-6, 1e-6});
  EXPECT_EQ(noisy.verdict, "slower");
  EXPECT_FALSE(noisy.gates);
  EXPECT_EQ(noisy.held.rfind("within the between-run band", 0), 0u) << noisy.held;
  // Without a model nothing is held: within-run noise only.
  o.noise = nullptr;
  EXPECT_TRUE(compareSampleSets("v", "shading", a, b, o, {"NVIDIA H200", shared, 1e-6, 1e-6}).gates);
}

// The floor: a 20 % slowdown of a 0.5 us pass is one step of a 0.1 us timer; twice the resolution
// (each median a difference of two quantized timestamps) holds it, and three steps gate.
TEST(NoiseModel, TheFloorIsTwiceTheTimestampsResolution) {
  CompareOptions o;
  o.gate = CompareGate::All;
  std::vector<double> a(30, 0.0005), b(30, 0.0006);
  for (size_t i = 0; i < a.size(); i += 3) {  // a spread of one tick on each side
    a[i] += 0.0001;
    b[i] += 0.0001;
  }
  const CompareRow tiny = compareSampleSets("v", "light_culling", a, b, o, {"d", "compute", 1e-6, 1e-6});
  EXPECT_EQ(tiny.verdict, "slower");
  EXPECT_NEAR(tiny.floorMs, 0.0002, 1e-12);  // the samples step by 0.1 us: the resolution they show
  EXPECT_FALSE(tiny.gates);
  EXPECT_EQ(tiny.held.rfind("under the floor", 0), 0u) << tiny.held;
  for (double& v : b) v += 0.0002;
  EXPECT_TRUE(compareSampleSets("v", "light_culling", a, b, o, {"d", "compute", 1e-6, 1e-6}).gates);
}

// Detection on the quiet pairs (the H200's compute runs): a planted 10 % slowdown of every pass
// over 0.1 ms gates in every trial, and the smallest slowdown gated in 95 % lies just above the
// 5 % threshold. The bound 5.5 %: the A/A rows' largest |log(B/A)| there is under 0.2 % and the
// resampled medians move by about the CV / sqrt(n) of a run (0.3 % / sqrt(60)), so a slowdown of
// 5 % + a few tenths of a percent clears the threshold in nearly every trial.
TEST(NoiseModel, APlantedSlowdownBeyondTheThresholdIsDetected) {
  std::vector<AaPair> pairs = committedPairs();
  pairs = {pairs[1], pairs[2]};  // the H200's compute tracer
  const NoiseModel model = buildNoiseModel(pairs);
  const NoiseCheck check = checkNoiseModel(pairs, model, 10, 5, 4);
  ASSERT_FALSE(check.detection.empty());
  for (const NoiseDetection& d : check.detection) {
    EXPECT_EQ(d.detected, 1.0) << d.pass;
    EXPECT_LT(d.smallest95, 0.055) << d.pass;
    EXPECT_GT(d.smallest95, 0.05) << d.pass;
  }
  for (const NoiseCheckPair& p : check.pairs) {
    EXPECT_EQ(p.gatesModel, 0u);
    EXPECT_EQ(p.gatesLeaveOut, 0u);
    EXPECT_TRUE(p.leaveOutCovers);
  }
  // Deterministic: the same trials give the same figures.
  const NoiseCheck again = checkNoiseModel(pairs, model, 10, 5, 4);
  for (size_t i = 0; i < check.detection.size(); ++i)
    EXPECT_EQ(check.detection[i].smallest95, again.detection[i].smallest95);
}

// The committed noise file holds the committed pairs: its H200 keys are the ones its H200 pairs
// give (its H100 keys pool more pairs: the bisect's and 2b33675's repeats).
TEST(NoiseModel, TheCommittedNoiseFileIsWhatItsPairsGive) {
  // Every H200 pair of the file (the H100's are left out for the test's time): each of its H200 keys
  // (compute; pipeline alone, beside other devices, on a device shared with another sweep) is rebuilt
  // from them.
  std::vector<AaPair> pairs = committedPairs();
  pairs.pop_back();
  for (const char* run : {"run1", "run2"}) {
    const std::string d = std::string("h200/aa-pipeline-concurrent-53/") + run;
    pairs.push_back({committed(d + "/0-nvidia-h200"), committed(d + "/1-nvidia-h200"), d + "/0", d + "/1"});
  }
  pairs.push_back({committed("h200/aa-pipeline-53/run1"), committed("h200/aa-pipeline-53/run2"),
                   "h200/aa-pipeline-53/run1", "h200/aa-pipeline-53/run2"});
  const NoiseModel built = buildNoiseModel(pairs);
  const NoiseModel file = committedModel();
  EXPECT_EQ(file.pairs.size(), 12u);
  size_t h200Keys = 0;
  for (const NoisePass& f : file.passes) h200Keys += f.device == "NVIDIA H200";
  EXPECT_EQ(built.passes.size(), h200Keys);
  for (const NoisePass& p : built.passes) {
    const NoisePass* f = file.find(p.device, p.tracer, p.pass);
    ASSERT_NE(f, nullptr) << p.device << " " << p.tracer << " " << p.pass;
    EXPECT_EQ(f->n, p.n) << p.tracer << " " << p.pass;
    EXPECT_DOUBLE_EQ(f->rmsLog, p.rmsLog) << p.tracer << " " << p.pass;
  }
}

// Runs swept at the same time as other sweeps are noise classes of their own (compare.h). The H200
// pipeline's pairs: two sweeps at once on one GPU (context.timing_caveat_shared_device; shading
// differs by up to 2x), each GPU of a 2-GPU host swept at once (context.concurrent_with), and one
// GPU swept alone, twice. Pooling the two concurrent kinds narrowed the band below the shared pair's
// spread, and one of its rows gated with the committed pairs' model; pooling them with the lone
// pair would do the same.
TEST(NoiseModel, RunsSweptBesideOtherSweepsAreNoiseClassesOfTheirOwn) {
  const AaPair shared = committedPairs()[0];
  const AaPair beside{committed("h200/aa-pipeline-concurrent-53/run1/0-nvidia-h200"),
                      committed("h200/aa-pipeline-concurrent-53/run1/1-nvidia-h200"), "run1/0", "run1/1"};
  const AaPair besideAgain{committed("h200/aa-pipeline-concurrent-53/run2/0-nvidia-h200"),
                           committed("h200/aa-pipeline-concurrent-53/run2/1-nvidia-h200"), "run2/0", "run2/1"};
  const AaPair alone{committed("h200/aa-pipeline-53/run1"), committed("h200/aa-pipeline-53/run2"),
                     "h200/aa-pipeline-53/run1", "h200/aa-pipeline-53/run2"};
  const NoiseModel all = buildNoiseModel({shared, beside, besideAgain, alone});
  // The gates first: without the shared device's class, its pair's rows are held by the quieter
  // two-GPU pairs' band, and one gates.
  CompareOptions o;
  o.gate = CompareGate::All;
  o.noise = &all;
  for (const AaPair* p : {&shared, &beside, &besideAgain, &alone})
    EXPECT_EQ(gates(compareResults(p->a, p->b, o)), 0u) << p->nameA;
  const NoisePass* s = all.find("NVIDIA H200", std::string("pipeline") + kSweptOnSharedDevice, "shading");
  const NoisePass* b = all.find("NVIDIA H200", std::string("pipeline") + kSweptBesideOthers, "shading");
  const NoisePass* a = all.find("NVIDIA H200", "pipeline", "shading");
  ASSERT_NE(s, nullptr);
  ASSERT_NE(b, nullptr);
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(s->n, 9u);
  EXPECT_EQ(b->n, 18u);
  EXPECT_GT(s->rmsLog, 0.1);
  EXPECT_LT(b->rmsLog, 0.01);
  EXPECT_LT(a->rmsLog, 0.01);
}

TEST(NoiseModel, TheFileRoundTripsAndANonNoiseFileIsNamed) {
  std::vector<AaPair> pairs = committedPairs();
  pairs.resize(1);
  const NoiseModel model = buildNoiseModel(pairs);
  const NoiseModel back = noiseModelFromJson(toJson(model), "n.json");
  ASSERT_EQ(back.passes.size(), model.passes.size());
  EXPECT_EQ(back.passes[2].rmsLog, model.passes[2].rmsLog);
  EXPECT_EQ(back.source, "n.json");
  try {
    noiseModelFromJson(pairs[0].a, "results.json");
    FAIL() << "a results file was read as a noise file";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("results.json: not a noise file", 0), 0u) << e.what();
  }
  // A version 1 file did not key a shared device's runs apart: refused, naming the command that
  // rebuilds it.
  json v1 = toJson(model);
  v1["schema_version"] = 1;
  try {
    noiseModelFromJson(v1, "old.json");
    FAIL() << "a version 1 noise file was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("old.json: noise file schema_version 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("hybridbench noise"), std::string::npos) << e.what();
  }
  json broken = toJson(model);
  broken["passes"][0].erase("rms_log");
  EXPECT_THROW(noiseModelFromJson(broken, "n.json"), InputError);
  // An A/A pair of two device models is refused, naming the pair.
  std::vector<AaPair> mixed = {{committed("h100/thesis"), committed("h200/fleet-35/thesis-whole"), "x", "y"}};
  try {
    buildNoiseModel(mixed);
    FAIL() << "a pair of two device models was taken as A/A";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("A/A pair x and y: the devices differ", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace hb
