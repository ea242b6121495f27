#include "scene/ambient_json.h"

#include <limits>

namespace hb {

Ambient readAmbient(const nlohmann::ordered_json& value, const json_reader::Where& where) {
  using namespace json_reader;
  requireObjectWithKeys(value, where, {"color", "intensity"});
  if (!value.contains("intensity")) where.fail("has no \"intensity\"; give the sky's radiance scale, e.g. 0.5");
  Ambient a;
  const double inf = std::numeric_limits<double>::infinity();
  a.intensity = readFloat(value["intensity"], where.key("intensity"), 0.0, inf, false);
  if (value.contains("color")) {
    const std::vector<float> c = readFloats(value["color"], where.key("color"), 3, "[r, g, b]");
    for (int i = 0; i < 3; ++i) {
      if (!(c[i] >= 0.0f)) where.key("color").fail("has a negative component; give linear RGB >= 0");
      a.color[i] = c[i];
    }
  }
  return a;
}

nlohmann::json toJson(const Ambient& a) {
  return {{"color", {a.color.r, a.color.g, a.color.b}}, {"intensity", a.intensity}};
}

}  // namespace hb
