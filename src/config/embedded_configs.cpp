// configs/thesis.json, embedded so that `hybridbench` with no arguments runs the thesis sweep from
// any directory. Keep it byte-identical to the file (config_test.cpp checks): after editing the
// file, paste its whole content between the delimiters below.
#include "config/config.h"

namespace hb {

namespace {
constexpr char kThesisConfig[] = R"json({
  "name": "thesis",
  "description": "Tables 5.1 and 5.2 of the thesis in one sweep. The 5.1 row 'light culling + AABB + improved shadow ray culling' and the 5.2 row '8x8' are the same configuration; both are kept so that each table is built from its own rows, and the pair shows the run-to-run noise.",
  "scene": "atrium",
  "scene_params": {"triangle_scale": 1.0, "lights": 10, "seed": 1},
  "camera": {"index": 0},
  "lights": "scene",
  "resolution": [1920, 1080],
  "effects": {"shadows": true},
  "frames": {"warmup": 50, "measured": 300},
  "defaults": {"backend": "auto", "world_pos": "alg41", "range_test": false, "depth_slices": 0, "max_lights_per_tile": 32},
  "variants": [
    {
      "name": "no optimisations",
      "params": {"tile_size": 8, "light_culling": false, "aabb": false, "normal_culling": "off"}
    },
    {
      "name": "light culling",
      "params": {"tile_size": 8, "light_culling": true, "aabb": false, "normal_culling": "off"}
    },
    {
      "name": "light culling + AABB",
      "params": {"tile_size": 8, "light_culling": true, "aabb": true, "normal_culling": "off"}
    },
    {
      "name": "light culling + AABB + shadow ray culling",
      "params": {"tile_size": 8, "light_culling": true, "aabb": true, "normal_culling": "naive"}
    },
    {
      "name": "light culling + AABB + improved shadow ray culling",
      "params": {"tile_size": 8, "light_culling": true, "aabb": true, "normal_culling": "improved"}
    },
    {
      "name": "improved shadow ray culling",
      "params": {"tile_size": 8, "light_culling": false, "aabb": false, "normal_culling": "improved"}
    },
    {
      "name": "8x8",
      "params": {"tile_size": 8, "light_culling": true, "aabb": true, "normal_culling": "improved"}
    },
    {
      "name": "16x16",
      "params": {"tile_size": 16, "light_culling": true, "aabb": true, "normal_culling": "improved"}
    },
    {
      "name": "32x32",
      "params": {"tile_size": 32, "light_culling": true, "aabb": true, "normal_culling": "improved"}
    }
  ]
}
)json";
}  // namespace

std::string_view embeddedDefaultConfigText() { return {kThesisConfig, sizeof kThesisConfig - 1}; }

}  // namespace hb
