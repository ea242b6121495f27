#include "reference/ray_file.h"

#include <cmath>
#include <fstream>
#include <iterator>

#include "base/errors.h"

namespace hb {

std::string rayFileJsonPath(const std::string& binPath) {
  const bool bin = binPath.size() > 4 && binPath.compare(binPath.size() - 4, 4, ".bin") == 0;
  return (bin ? binPath.substr(0, binPath.size() - 4) : binPath) + ".json";
}

nlohmann::json toJson(const RayFileInfo& i) {
  nlohmann::json scene = {{"name", i.sceneName}, {"sha256", i.sceneSha256}};
  if (!i.sceneGeometrySha256.empty()) scene["geometry_sha256"] = i.sceneGeometrySha256;
  return {{"format", "hybridbench rays"},
          {"version", i.version},
          {"count", i.count},
          {"record", "8 float32 little-endian: origin x y z, tmin, direction x y z, tmax (32 bytes)"},
          {"query", i.query},
          {"kind", i.kind},
          {"scene", scene},
          {"camera", i.camera},
          {"seed", i.seed},
          {"grid", {i.grid[0], i.grid[1]}},
          {"units", i.units},
          {"made_by", i.madeBy},
          {"params", i.params}};
}

void writeRayFile(const std::string& binPath, const RayFileInfo& info, const std::vector<RayRecord>& rays) {
  HB_ASSERT(info.count == rays.size());
  HB_ASSERT(uint64_t(info.grid[0]) * info.grid[1] >= rays.size());
  {
    std::ofstream bin(binPath, std::ios::binary);
    bin.write(reinterpret_cast<const char*>(rays.data()), std::streamsize(rays.size() * sizeof(RayRecord)));
    if (!bin) throw InputError(binPath + ": cannot write the ray file; check the folder exists and is writable");
  }
  std::ofstream json(rayFileJsonPath(binPath));
  json << toJson(info).dump(2) << "\n";
  if (!json) throw InputError(rayFileJsonPath(binPath) + ": cannot write the ray file's description; check the folder");
}

RayFile readRayFile(const std::string& binPath) {
  const std::string jsonPath = rayFileJsonPath(binPath);
  std::ifstream jf(jsonPath);
  if (!jf)
    throw InputError(jsonPath +
                     ": no such file; a ray file is NAME.bin with NAME.json beside it (hybridbench rays export "
                     "writes both)");
  nlohmann::json j = nlohmann::json::parse(jf, nullptr, false);
  if (j.is_discarded() || !j.is_object())
    throw InputError(jsonPath + ": not a JSON object; write it again with hybridbench rays export");
  const auto need = [&](const char* key) -> const nlohmann::json& {
    if (!j.contains(key))
      throw InputError(jsonPath + ": no \"" + key + "\"; write it again with hybridbench rays export");
    return j[key];
  };
  RayFile f;
  RayFileInfo& i = f.info;
  if (!need("version").is_number_unsigned() || need("version").get<uint32_t>() != kRayFileVersion)
    throw InputError(jsonPath + ": ray file version " + need("version").dump() + ", this build reads version " +
                     std::to_string(kRayFileVersion) + "; export the rays again with this build");
  i.version = kRayFileVersion;
  if (!need("count").is_number_unsigned()) throw InputError(jsonPath + ": \"count\" must be a whole number");
  i.count = j["count"].get<uint64_t>();
  i.query = need("query").is_string() ? j["query"].get<std::string>() : "";
  if (i.query != "closest" && i.query != "any")
    throw InputError(jsonPath + ": query " + j["query"].dump() + " is not closest or any");
  i.kind = j.value("kind", "");
  const nlohmann::json& scene = need("scene");
  if (!scene.is_object() || !scene.contains("sha256") || !scene["sha256"].is_string())
    throw InputError(jsonPath + ": \"scene\" must name the scene's sha256 (hybridbench scene info prints it)");
  i.sceneName = scene.value("name", "");
  i.sceneSha256 = scene["sha256"].get<std::string>();
  if (scene.contains("geometry_sha256")) {
    if (!scene["geometry_sha256"].is_string())
      throw InputError(jsonPath +
                       ": \"scene\".\"geometry_sha256\" must be a string (hybridbench rays export writes it)");
    i.sceneGeometrySha256 = scene["geometry_sha256"].get<std::string>();
  }
  i.camera = j.value("camera", nlohmann::json());
  i.seed = j.value("seed", uint64_t(0));
  const nlohmann::json& grid = need("grid");
  if (!grid.is_array() || grid.size() != 2 || !grid[0].is_number_unsigned() || !grid[1].is_number_unsigned())
    throw InputError(jsonPath + ": \"grid\" must be [width, height]");
  i.grid = {grid[0].get<uint32_t>(), grid[1].get<uint32_t>()};
  if (uint64_t(i.grid[0]) * i.grid[1] < i.count || i.grid[0] == 0)
    throw InputError(jsonPath + ": the grid " + grid.dump() + " holds fewer than its " + std::to_string(i.count) +
                     " rays");
  i.units = j.value("units", "");
  i.madeBy = j.value("made_by", "");
  i.params = j.value("params", nlohmann::json());

  std::ifstream bin(binPath, std::ios::binary | std::ios::ate);
  if (!bin) throw InputError(binPath + ": no such file; a ray file is NAME.bin with NAME.json beside it");
  const uint64_t bytes = uint64_t(bin.tellg());
  if (bytes != i.count * sizeof(RayRecord))
    throw InputError(binPath + ": " + std::to_string(bytes) + " bytes, but " + jsonPath + " says " +
                     std::to_string(i.count) + " rays of 32 bytes (" + std::to_string(i.count * sizeof(RayRecord)) +
                     "); the two files do not belong together");
  f.rays.resize(i.count);
  bin.seekg(0);
  bin.read(reinterpret_cast<char*>(f.rays.data()), std::streamsize(bytes));
  if (!bin) throw InputError(binPath + ": could not be read to its end");
  for (uint64_t k = 0; k < f.rays.size(); ++k) {
    const RayRecord& r = f.rays[k];
    bool finite = std::isfinite(r.tMin) && !std::isnan(r.tMax);
    for (int c = 0; c < 3; ++c) finite = finite && std::isfinite(r.origin[c]) && std::isfinite(r.dir[c]);
    if (!finite || !(r.tMin <= r.tMax) || (r.dir[0] == 0 && r.dir[1] == 0 && r.dir[2] == 0))
      throw InputError(binPath + ": ray " + std::to_string(k) +
                       " has a non-finite origin or direction, a zero direction, or tmin > tmax");
  }
  return f;
}

}  // namespace hb
