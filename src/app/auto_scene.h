// A camera and lights for a scene that brings none (issue #18): most glTF assets have neither, and
// a user should still get a meaningful run without writing a config. Everything here is
// deterministic (splitmix64, fixed seeds): the same scene gets the same camera and lights on every
// machine, so results of two GPUs compare.
//
// Automatic camera (autoCamera): perspective, yfov 60° (the atrium's), looking at the centre c of
// the scene's world bounds from azimuth 30° (from +z towards +x) and elevation 20° (glTF's +y is
// up), at distance d = r / sin(30°) = 2r, r the radius of the bounds' sphere (half the box
// diagonal): the whole sphere fits the vertical field of view, and the horizontal one at any
// aspect ≥ 1 (a portrait image may crop the sides). znear = (d - r)/2 = r/2 (half the distance
// to the sphere's nearest point), zfar = d + 2r = 4r (beyond its farthest by r).
//
// Automatic lights (autoLights): the atrium's procedure (point lights drawn in turn among
// regions, pale colours) applied to the scene's bounds, alternating
//  - interior lights (even indices): a point drawn in the bounds shrunk by 5 % on each side in x
//    and z and at 15–75 % of their height, kept only where it is in free space — 14 rays (6 axes,
//    8 diagonals) against the scene's triangles (CPU BVH, double) all find their first hit at
//    ≥ 2 % of r, and at most half of them hit a back face (more would mean the point is inside a
//    closed solid); up to 64 draws, then the light becomes a shell light. Range 0.15–0.6 r (the
//    atrium's 3–12 m in its 18.4 m-radius bounds are 0.16–0.65 r); intensity 0.5·range² cd (the
//    atrium's mean I/R², 32.5 cd over a mean square range of 63 m²).
//  - shell lights (odd indices, and interior lights with no free point): on the sphere of radius
//    1.25 r around c, at golden-angle azimuths and elevations 20–65°, outside every triangle;
//    range 2.3 r, so every point of the bounds is within reach; intensity 0.6·(1.25 r)² cd, half
//    a lux at the centre from each (auto_scene.cpp derives it).
// An object scene (one closed model) thus gets a studio ring and an interior scene (Sponza) lights
// in its halls as well as from above.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace hb {

// The number of automatic lights a scene with none gets (the thesis's light count).
constexpr uint32_t kDefaultAutoLights = 10;

Camera autoCamera(const Scene& scene);

struct AutoLights {
  std::vector<Light> lights;
  uint32_t interior = 0, shell = 0;  // how many of each kind
  uint32_t rejectedDraws = 0;        // interior draws not in free space
};
AutoLights autoLights(const Scene& scene, uint32_t count, uint32_t seed = 1);

// What a run asks for beyond the scene's own: an automatic camera even if the scene has one
// (camera=auto), and `lightCount` automatic lights in place of the scene's (light_count=N on a
// scene other than the atrium, whose own procedure takes the count).
struct AutoRequest {
  bool camera = false;
  std::optional<uint32_t> lightCount;
};

// Gives `scene` an automatic camera (as cameras[0]) when it has none or the request asks, and
// automatic lights when it has none and none were configured (lightsSource "scene"), or when the
// request gives a count; sets cameraSource/lightsSource to "auto" for what it made. Returns one
// line per thing made, for stderr ("scene X has no camera: automatic camera at ...").
std::vector<std::string> completeScene(Scene& scene, const AutoRequest& request);

}  // namespace hb
