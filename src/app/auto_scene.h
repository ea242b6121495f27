// A camera and lights for a scene that brings none (issue #18): most glTF assets have neither, and
// a user should still get a meaningful run without writing a config. Everything here is
// deterministic (splitmix64, fixed seeds): the same scene gets the same camera and lights on every
// machine, so results of two GPUs compare.
//
// Automatic camera (autoCamera): perspective, yfov 60° (the atrium's), inside the scene when the
// centre c of its world bounds is enclosed, else outside.
//  - The probe: c when it is in free space (the lights' test below, clearance 2 % of r), else the
//    free point nearest c among 64 draws from the interior lights' region (a seed of its own).
//    No free point (a solid filling its bounds): not enclosed.
//  - Enclosed: the probe's 14 free-space rays all hit the scene, except perhaps the one straight
//    up. A room has walls all round and a floor below; an open roof over a courtyard (the atrium,
//    Sponza) leaves it a room, and the 4 upward diagonals, at 35° elevation, still have to hit: a
//    level view of yfov 60° reaches 30° up, so what it sees is surrounded. A ray escaping sideways
//    or down means the probe is in the open (beside an object) or in a room open on a side (the
//    Cornell box, open towards its camera), which is a stage looked into from outside. A probe
//    inside a solid is not free, so it never counts as a room: the test's back-face rule.
//  - Inside: the eye stands 1.7 m (glTF's unit is the metre: a person's eye height; the atrium's
//    own camera is at 1.8 m) above what the probe's ray straight down hits, when the probe is
//    higher than that and the standing point is free and some level ray from it hits; else the eye
//    is the probe. It looks level (verticals stay vertical: the view people expect of a room)
//    along the longest of the 24 level directions every 15° of azimuth (from +z towards +x) whose
//    first hit is the scene (a miss would look out at the background); lengths equal to 1e-9
//    relative go to the first in azimuth order. znear = 0.5 % of r (a quarter of the clearance,
//    for geometry between the rays; reverse-Z keeps it precise), zfar = the distance to the
//    bounds' farthest corner + 2 % of r (nothing in the bounds is farther from a point inside).
//  - Outside: looking at c from azimuth 30° (from +z towards +x) and elevation 20° (glTF's +y is
//    up), at distance d = r / sin(30°) = 2r, r the radius of the bounds' sphere (half the box
//    diagonal): the whole sphere fits the vertical field of view, and the horizontal one at any
//    aspect ≥ 1 (a portrait image may crop the sides). znear = (d - r)/2 = r/2 (half the distance
//    to the sphere's nearest point), zfar = d + 2r = 4r (beyond its farthest by r).
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

// What the automatic camera chose and why (the stderr line and the tests read it).
struct AutoCameraChoice {
  Camera camera;
  bool enclosed = false;
  bool centreFree = false;  // else the probe is the free point nearest the centre, if probeFound
  bool probeFound = false;
  glm::dvec3 probe{0.0};
  int probeMisses = 0;  // how many of the probe's 14 rays escape the scene
  // Inside only: where the eye stands, the unit level direction it looks along and that
  // direction's first hit from the eye.
  glm::dvec3 eye{0.0}, direction{0.0};
  double freeDistance = 0.0;
};
AutoCameraChoice chooseAutoCamera(const Scene& scene);
Camera autoCamera(const Scene& scene);  // chooseAutoCamera(scene).camera
// The outside camera, whatever the scene: what autoCamera gives where the centre is not enclosed.
Camera exteriorCamera(const Scene& scene);
// The stderr line's account of a choice: "the centre of its bounds is enclosed (...), so an
// automatic camera inside at ..." or "... is open (...), so an automatic camera outside at ...".
std::string cameraChoiceText(const AutoCameraChoice& c);

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
