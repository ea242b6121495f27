// Test helper for the report writers: the thesis sweep they are held to, and the shape of one run.
#pragma once
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#ifndef HYBRIDBENCH_SOURCE_DIR
#error "HYBRIDBENCH_SOURCE_DIR must name the source tree (for tests/fixtures/)"
#endif

namespace hb::testing {

// tests/fixtures/results-fixture.json: H100, atrium, 1920x1080, 8 ok runs with 11 samples each;
// run names deliberately differ from the table labels and the runs are not in thesis order. Frame
// medians (ms): baseline_t8 4.000, lc_t8 2.880, lc_aabb_t8 2.732, lc_aabb_naive_t8 2.400,
// lc_aabb_improved_t8 2.420, improved_only_t8 3.380, lc_aabb_improved_t16 2.450, ..._t32 2.560.
inline nlohmann::json thesisResultsFixture() {
  std::ifstream in(HYBRIDBENCH_SOURCE_DIR "/tests/fixtures/results-fixture.json");
  EXPECT_TRUE(in.good()) << "fixture not found";
  return nlohmann::json::parse(in);
}

// A finished run of an effect study at 800x800: its frame median, its passes, and the effect's
// record under `effect` ("ambient_occlusion", "indirect", ...).
inline nlohmann::json effectRun(const char* name, double frameMs, const char* effect, nlohmann::json record,
                                nlohmann::json passes) {
  return {{"name", name},
          {"status", "ok"},
          {"params", {{"resolution", {800, 800}}}},
          {"passes", std::move(passes)},
          {"frame_ms", {{"median", frameMs}}},
          {effect, std::move(record)}};
}

}  // namespace hb::testing
