#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "app/commands.h"
#include "base/errors.h"
#include "base/text_format.h"
#include "gltf/gltf_io.h"
#include "plan/effects.h"
#include "scene/atrium.h"
#include "scene/hard_cases.h"

namespace hb {

Scene loadSceneArg(const std::string& nameOrPath) {
  for (const std::string& n : allSceneNames())
    if (n == nameOrPath) return makeBuiltinScene(n);
  std::filesystem::path p(nameOrPath);
  std::string ext = p.extension().string();
  if (ext == ".gltf" || ext == ".glb" || std::filesystem::exists(p)) return loadGltf(nameOrPath);
  throw InputError("scene \"" + nameOrPath + "\": not a built-in scene (" + unknownSceneHint(nameOrPath) +
                   ") nor a .gltf/.glb file");
}

int cmdSceneExport(const std::string& name, const std::string& out, bool noCamera, bool noLights) {
  Scene scene = loadSceneArg(name);
  if (noCamera) scene.cameras.clear();
  if (noLights) scene.lights.clear();
  exportGltf(scene, out);
  std::printf("wrote %s (%s, %s)\n", out.c_str(), countOf(scene.triangleCount(), "triangle").c_str(),
              countOf(scene.lights.size(), "light").c_str());
  return kExitOk;
}

int cmdSceneInfo(const std::string& path, bool json) {
  Scene scene = loadSceneArg(path);
  if (json)
    std::cout << sceneInfoJson(scene).dump(2) << "\n";
  else
    std::cout << sceneInfoText(scene);
  return kExitOk;
}

namespace {

namespace fs = std::filesystem;

// One row of `scene list`: a built-in scene or a file.
struct ListedScene {
  std::string name;         // built-in name, or the file's path as the listing shows it
  std::string description;  // built-ins; "" if none
  uint64_t triangles = 0;
  size_t lights = 0;
  nlohmann::json effects;  // the scene's extras.effects (null when it calls for nothing)
  bool ambient = false;    // it has an ambient term (extras.ambient)
  uintmax_t bytes = 0;     // files
  std::string error;       // files that do not load: the loader's one line
};

ListedScene describe(const Scene& scene, ListedScene row) {
  row.triangles = scene.triangleCount();
  row.lights = scene.lights.size();
  row.effects = scene.effects;
  row.ambient = scene.ambient.has_value();
  return row;
}

// The effects a scene's extras.effects asks for (a value other than false), comma-separated in
// allEffects() order.
std::string callsFor(const nlohmann::json& effects) {
  std::string names;
  if (effects.is_object())
    for (const EffectDef* effect : allEffects())
      if (effects.contains(effect->name) && effects[effect->name] != false)
        names += (names.empty() ? "" : ", ") + std::string(effect->name);
  return names.empty() ? "-" : names;
}

bool isGltfPath(const fs::path& p) {
  const std::string ext = asciiLower(p.extension().string());
  return ext == ".gltf" || ext == ".glb";
}

// The folder `scene list` reads (see cmdSceneList) and how the listing names its files: relative
// to the current directory when the folder is ./scenes or was given, else absolute.
std::optional<fs::path> findScenesDir(const std::string& given) {
  std::error_code ec;
  if (!given.empty()) {
    if (!fs::is_directory(given, ec))
      throw InputError("--dir " + given + ": not a directory; name a folder of .gltf/.glb files");
    return fs::path(given);
  }
  if (fs::is_directory("scenes", ec)) return fs::path("scenes");
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return std::nullopt;
  for (fs::path dir = exe.parent_path(); !dir.empty(); dir = dir.parent_path()) {
    if (fs::is_directory(dir / "scenes", ec) && fs::is_regular_file(dir / "CMakeLists.txt", ec)) return dir / "scenes";
    if (dir == dir.root_path()) break;
  }
  return std::nullopt;
}

nlohmann::json rowJson(const ListedScene& row, bool file) {
  nlohmann::json j;
  j[file ? "path" : "name"] = row.name;
  if (file) j["bytes"] = row.bytes;
  if (!row.error.empty()) {
    j["error"] = row.error;
    return j;
  }
  j["triangles"] = row.triangles;
  j["lights"] = row.lights;
  if (!file) j["description"] = row.description;
  j["effects"] = row.effects;
  j["ambient"] = row.ambient;
  return j;
}

}  // namespace

int cmdSceneList(const std::string& dir, bool json) {
  std::vector<ListedScene> builtins;
  for (const std::string& name : allSceneNames()) {
    ListedScene row;
    row.name = name;
    row.description = builtinSceneDescription(name);
    builtins.push_back(describe(makeBuiltinScene(name), row));
  }

  const std::optional<fs::path> scenesDir = findScenesDir(dir);
  std::vector<ListedScene> files;
  if (scenesDir) {
    std::vector<fs::path> paths;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(*scenesDir, fs::directory_options::skip_permission_denied, ec), end;
         !ec && it != end; it.increment(ec))
      if (it->is_regular_file(ec) && isGltfPath(it->path())) paths.push_back(it->path());
    std::sort(paths.begin(), paths.end());
    for (const fs::path& path : paths) {
      ListedScene row;
      row.name = path.string();
      row.bytes = fs::file_size(path, ec);
      try {
        GltfLoadWarnings warnings;  // collected, not printed: a listing is not a load report
        row = describe(loadGltf(path.string(), &warnings), row);
      } catch (const InputError& e) {
        row.error = e.what();
      }
      files.push_back(row);
    }
  }

  if (json) {
    nlohmann::json out;
    out["builtin"] = nlohmann::json::array();
    for (const ListedScene& row : builtins) out["builtin"].push_back(rowJson(row, false));
    out["scenes_dir"] = scenesDir ? nlohmann::json(scenesDir->string()) : nlohmann::json(nullptr);
    out["files"] = nlohmann::json::array();
    for (const ListedScene& row : files) out["files"].push_back(rowJson(row, true));
    std::cout << out.dump(2) << "\n";
    return kExitOk;
  }

  size_t width = 4;
  for (const ListedScene& row : builtins) width = std::max(width, row.name.size());
  for (const ListedScene& row : files) width = std::max(width, row.name.size());
  const int w = static_cast<int>(width);
  std::printf("built-in scenes (render --scene NAME):\n  %-*s %10s %7s  %s\n", w, "NAME", "TRIANGLES", "LIGHTS",
              "DESCRIPTION");
  for (const ListedScene& row : builtins)
    std::printf("  %-*s %10llu %7zu  %s\n", w, row.name.c_str(), (unsigned long long)row.triangles, row.lights,
                row.description.c_str());
  if (!scenesDir) {
    std::printf(
        "\nno scenes folder: none in the current directory nor in the repository of this executable; "
        "name one with --dir DIR\n");
    return kExitOk;
  }
  std::printf("\nfiles in %s/ (render --scene PATH):\n", scenesDir->string().c_str());
  if (files.empty()) {
    std::printf("  none (.gltf or .glb)\n");
    return kExitOk;
  }
  std::printf("  %-*s %10s %7s  %s\n", w, "PATH", "TRIANGLES", "LIGHTS", "CALLS FOR");
  for (const ListedScene& row : files) {
    if (!row.error.empty())
      std::printf("  %-*s %10s %7s  does not load: %s\n", w, row.name.c_str(), "-", "-", row.error.c_str());
    else
      std::printf("  %-*s %10llu %7zu  %s\n", w, row.name.c_str(), (unsigned long long)row.triangles, row.lights,
                  callsFor(row.effects).c_str());
  }
  return kExitOk;
}

void parseSize(const std::string& text, uint32_t& width, uint32_t& height, const std::string& what) {
  unsigned w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%u%c%u%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w == 0 || h == 0 ||
      w > 16384 || h > 16384)
    throw InputError(what + " \"" + text + "\": expected WIDTHxHEIGHT with each 1..16384, e.g. 1920x1080");
  width = w;
  height = h;
}

}  // namespace hb
