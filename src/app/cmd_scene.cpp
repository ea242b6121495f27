#include <cstdio>
#include <filesystem>
#include <iostream>

#include "scene/atrium.h"
#include "app/commands.h"
#include "base/errors.h"
#include "scene/gltf/gltf_io.h"
#include "scene/hard_cases.h"

namespace hb {

Scene loadSceneArg(const std::string& nameOrPath) {
  for (const std::string& n : allSceneNames())
    if (n == nameOrPath) return makeBuiltinScene(n);
  std::filesystem::path p(nameOrPath);
  std::string ext = p.extension().string();
  if (ext == ".gltf" || ext == ".glb" || std::filesystem::exists(p)) return loadGltf(nameOrPath);
  std::string names;
  for (const std::string& n : allSceneNames()) names += (names.empty() ? "" : ", ") + n;
  throw InputError("scene \"" + nameOrPath + "\": not a built-in scene (" + names + ") nor a .gltf/.glb file");
}

int cmdSceneExport(const std::string& name, const std::string& out) {
  Scene scene = loadSceneArg(name);
  exportGltf(scene, out);
  std::printf("wrote %s (%llu triangles, %zu lights)\n", out.c_str(), (unsigned long long)scene.triangleCount(),
              scene.lights.size());
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
