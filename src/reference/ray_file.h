// Ray files (docs/results-format.md "Ray files"): a set of rays another tracer can trace, and that
// `hybridbench raybench` traces with every backend. Two files side by side:
//   NAME.bin   little-endian records of 8 float32: origin xyz, tmin, direction xyz, tmax (32 bytes);
//   NAME.json  what they are: format version, count, query (closest | any), kind, the scene (name
//              and content sha256), the camera, the seed, the launch grid and the units.
// The rays are in the scene's world space (metres for glTF). A direction need not be unit length;
// tmin and tmax are in units of its length.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hb {

inline constexpr uint32_t kRayFileVersion = 1;

struct RayRecord {
  float origin[3];
  float tMin;
  float dir[3];
  float tMax;
};
static_assert(sizeof(RayRecord) == 32, "a ray file record is 8 float32");

struct RayFileInfo {
  uint32_t version = kRayFileVersion;
  uint64_t count = 0;
  std::string query = "closest";  // closest: the nearest hit; any: whether anything is hit
  std::string kind;               // camera | ao | shadow | ... (rays export --kind)
  std::string sceneName, sceneSha256;
  // What the rays meet (gltf_io.h sceneGeometrySha256); empty in files written before it. raybench
  // takes a scene whose geometry matches: lights and materials change no hit.
  std::string sceneGeometrySha256;
  nlohmann::json camera;               // {eye, forward, up, yfov_deg, width, height}: the view the rays came from
  uint64_t seed = 0;                   // the random rays' seed (0: none drawn)
  std::array<uint32_t, 2> grid{0, 0};  // rays are row-major over width x height (a launch's shape)
  std::string units = "scene units (glTF: metres); t in units of the direction's length";
  std::string madeBy;     // "hybridbench 0.1.0 at <git>"
  nlohmann::json params;  // what the kind was made with (offset, t_max, light, ...)
};

struct RayFile {
  RayFileInfo info;
  std::vector<RayRecord> rays;
};

// "dir/NAME.bin" -> "dir/NAME.json".
std::string rayFileJsonPath(const std::string& binPath);

nlohmann::json toJson(const RayFileInfo& info);

// Writes NAME.bin and NAME.json (binPath ends in .bin). Throws InputError if either cannot be
// written. Precondition: info.count == rays.size(), info.grid covers the rays.
void writeRayFile(const std::string& binPath, const RayFileInfo& info, const std::vector<RayRecord>& rays);

// Reads and checks both files; a missing or unreadable file, a version this build does not read, a
// count that disagrees with the .bin's size, an unknown query or a grid too small is an InputError
// of one line naming the file and what to do. A non-finite origin or direction, or tmin > tmax, names
// the first such ray.
RayFile readRayFile(const std::string& binPath);

}  // namespace hb
