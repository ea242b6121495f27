#include "app/auto_scene.h"
#include "base/numbers.h"

#include <cmath>

#include <gtest/gtest.h>

#include "gltf/gltf_io.h"
#include "reference/bvh.h"
#include "scene/atrium.h"
#include "scene/hard_cases.h"
#include "scene/mesh_builder.h"

namespace hb {
namespace {

// One closed box [lo, hi] (outward faces, a solid) or, with `room`, the same box with every
// triangle's winding reversed (inward faces: the walls of a room seen from inside).
Scene boxScene(glm::dvec3 lo, glm::dvec3 hi, bool room) {
  Scene s;
  s.name = room ? "room" : "solid";
  s.materials.push_back(Material{});
  MeshBuilder mb("box");
  addBox(mb, 0, lo, hi);
  mb.appendTo(s);
  if (room)
    for (size_t i = 0; i + 2 < s.indices.size(); i += 3) std::swap(s.indices[i + 1], s.indices[i + 2]);
  return s;
}

// A room with interior [lo, hi] built as the atrium is: closed slabs 0.2 m thick (a floor below
// lo.y, four walls up to hi.y, and a ceiling above it when `ceiling`); `frontWall` false leaves
// the +z wall out (a room open on a side, as the Cornell box is).
Scene roomScene(glm::dvec3 lo, glm::dvec3 hi, bool ceiling, bool frontWall) {
  Scene s;
  s.name = "room";
  s.materials.push_back(Material{});
  MeshBuilder mb("room");
  const double w = 0.2;
  addBox(mb, 0, {lo.x - w, lo.y - w, lo.z - w}, {hi.x + w, lo.y, hi.z + w});
  if (ceiling) addBox(mb, 0, {lo.x - w, hi.y, lo.z - w}, {hi.x + w, hi.y + w, hi.z + w});
  addBox(mb, 0, {lo.x - w, lo.y, lo.z - w}, {lo.x, hi.y, hi.z + w});
  addBox(mb, 0, {hi.x, lo.y, lo.z - w}, {hi.x + w, hi.y, hi.z + w});
  addBox(mb, 0, {lo.x, lo.y, lo.z - w}, {hi.x, hi.y, lo.z});
  if (frontWall) addBox(mb, 0, {lo.x, lo.y, hi.z}, {hi.x, hi.y, hi.z + w});
  mb.appendTo(s);
  return s;
}

void corners(const Scene& s, std::vector<glm::dvec3>& out) {
  glm::vec3 lo, hi;
  s.bounds(lo, hi);
  for (int k = 0; k < 8; ++k) out.push_back({k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z});
}

// The exterior camera sees every corner of the bounds: each lies within the 30° half-angle cone
// round the view axis (so inside the vertical field of view, and the horizontal one at any aspect
// >= 1) and between the near and far planes. The bounds' sphere touches the cone, so a corner may
// sit on it: 1e-5 rad is float round-off of the view matrix (unit-scale rotation, translation of
// a few r) with room to spare, far below any real miss (a corner outside by a pixel at 1080 rows
// is 1e-3 rad).
TEST(AutoCamera, FromOutsideFramesTheWholeBoundsOfEveryScene) {
  for (const Scene& s : {makeBuiltinScene("cube"), makeAtrium(), makeBuiltinScene("far-origin"),
                         boxScene({0, 0, 0}, {1e-3, 2e-3, 1e-3}, false)}) {
    const Camera cam = exteriorCamera(s);
    EXPECT_EQ(cam.projection, CameraProjection::Perspective);
    EXPECT_NEAR(cam.yfov, kPi / 3, 1e-6);
    std::vector<glm::dvec3> pts;
    corners(s, pts);
    for (const glm::dvec3& p : pts) {
      const glm::dvec3 v = glm::dvec3(glm::dmat4(cam.view) * glm::dvec4(p, 1.0));
      const double depth = -v.z, offAxis = std::atan2(std::hypot(v.x, v.y), depth);
      EXPECT_LE(offAxis, kPi / 6 + 1e-5) << s.name;
      EXPECT_GT(depth, cam.znear) << s.name;
      EXPECT_LT(depth, cam.zfar) << s.name;
    }
  }
}

// An object scene (the cube on its ground square; far from the origin too), a solid filling its
// bounds, and a room open on a side (the Cornell box, and one built here) are not enclosed: the
// automatic camera is the exterior one, as before the inside camera existed.
TEST(AutoCamera, StaysOutsideWhereTheCentreIsNotEnclosed) {
  const Scene cornell = loadGltf(std::string(HYBRIDBENCH_SOURCE_DIR) + "/scenes/cornell-box.gltf");
  for (const Scene& s :
       {makeBuiltinScene("cube"), makeBuiltinScene("far-origin"), boxScene({-2, 0, -3}, {2, 3, 3}, false), cornell,
        roomScene({-2, 0, -3}, {2, 3, 3}, true, false)}) {
    const AutoCameraChoice c = chooseAutoCamera(s);
    EXPECT_FALSE(c.enclosed) << s.name;
    EXPECT_EQ(c.camera.view, exteriorCamera(s).view) << s.name;
    EXPECT_EQ(c.camera.znear, exteriorCamera(s).znear) << s.name;
    EXPECT_EQ(c.camera.zfar, exteriorCamera(s).zfar) << s.name;
    EXPECT_EQ(autoCamera(s).view, c.camera.view) << s.name;
    const std::string text = cameraChoiceText(c);
    EXPECT_NE(text.find("an automatic camera outside at"), std::string::npos) << text;
  }
  // The cube's centre is inside the cube: the probe is a free point beside it, in the open.
  const AutoCameraChoice cube = chooseAutoCamera(makeBuiltinScene("cube"));
  EXPECT_FALSE(cube.centreFree);
  EXPECT_TRUE(cube.probeFound);
  EXPECT_GT(cube.probeMisses, 0);
  // The solid has no free point at all.
  EXPECT_FALSE(chooseAutoCamera(boxScene({-2, 0, -3}, {2, 3, 3}, false)).probeFound);
}

// Checks an inside camera against the scene itself, with a BVH of its own and directions of its
// own (std::sin and std::cos, not the code's exact table): the eye is inside the bounds and in
// free space (14 rays and the 24 level ones find nothing nearer than 2 % of r), the camera stands
// there and looks level along `direction`, whose first hit is `freeDistance`, and no level
// direction every 15° runs farther. Tolerances: 1e-9 relative for distances (the code's tie rule;
// both sides compute the hits in double to about 1e-15 relative, and the two direction tables
// differ in the last bits only); 1e-5 for the float view matrix's position (relative to the
// scene's size) and axes.
void expectInsideAndLongest(const Scene& s, const AutoCameraChoice& c) {
  SCOPED_TRACE(s.name);
  ASSERT_TRUE(c.enclosed);
  glm::vec3 lo, hi;
  s.bounds(lo, hi);
  const double r = 0.5 * glm::length(glm::dvec3(hi) - glm::dvec3(lo));
  for (int a = 0; a < 3; ++a) {
    EXPECT_GT(c.eye[a], lo[a]);
    EXPECT_LT(c.eye[a], hi[a]);
  }
  const Bvh bvh = buildBvh(s);
  double t = 0.0;
  std::vector<glm::dvec3> rays = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int k = 0; k < 8; ++k) rays.push_back({k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1});
  for (const glm::dvec3& d : rays) {
    if (bvh.closestHit(c.eye, glm::normalize(d), 0.0, INFINITY, t)) {
      EXPECT_GE(t, 0.02 * r);
    }
  }
  EXPECT_EQ(c.direction.y, 0.0);
  EXPECT_NEAR(glm::length(c.direction), 1.0, 1e-15);
  ASSERT_TRUE(bvh.closestHit(c.eye, c.direction, 0.0, INFINITY, t));
  EXPECT_NEAR(t, c.freeDistance, 1e-9 * c.freeDistance);
  for (int k = 0; k < 24; ++k) {
    const double az = k * 15.0 * kPi / 180.0;
    if (!bvh.closestHit(c.eye, {std::sin(az), 0.0, std::cos(az)}, 0.0, INFINITY, t)) continue;
    EXPECT_GE(t, 0.02 * r) << k;
    EXPECT_LE(t, c.freeDistance * (1.0 + 1e-9)) << k;
  }
  const glm::dmat4 world = glm::inverse(glm::dmat4(c.camera.view));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(world[3][a], c.eye[a], 1e-5 * r);
    EXPECT_NEAR(-world[2][a], c.direction[a], 1e-5);
  }
  EXPECT_GT(c.camera.znear, 0.0f);
  std::vector<glm::dvec3> pts;
  corners(s, pts);
  for (const glm::dvec3& p : pts) EXPECT_LT(glm::length(p - c.eye), c.camera.zfar);
}

// The atrium exported bare (its geometry: the camera and lights play no part) is enclosed: from
// the centre of its bounds, (0, 6, 0), only the ray straight up leaves, through the open
// courtyard. The eye stands 1.7 m above the courtyard floor (y = 0) and looks along the longest
// level direction.
TEST(AutoCamera, StandsInsideTheAtriumAndLooksAlongItsLongestFreeDirection) {
  Scene s = makeAtrium();
  s.cameras.clear();
  s.lights.clear();
  const AutoCameraChoice c = chooseAutoCamera(s);
  EXPECT_TRUE(c.centreFree);
  EXPECT_EQ(c.probeMisses, 1);
  expectInsideAndLongest(s, c);
  EXPECT_NEAR(c.eye.y, 1.7, 1e-12);
  EXPECT_EQ(autoCamera(s).view, c.camera.view);
  const std::string text = cameraChoiceText(c);
  EXPECT_NE(text.find("the centre of its bounds is enclosed"), std::string::npos) << text;
  EXPECT_NE(text.find("an automatic camera inside at (0, 1.7, 0) looking along"), std::string::npos) << text;
}

// A closed room and a courtyard (no ceiling) are enclosed; in the closed room, 3 m high, the
// centre is lower than eye height above the floor and the eye stays there; in the 10 m courtyard
// it stands at 1.7 m.
TEST(AutoCamera, StandsInsideAClosedRoomAndACourtyard) {
  const Scene room = roomScene({-2, 0, -3}, {2, 3, 3}, true, true);
  const AutoCameraChoice inRoom = chooseAutoCamera(room);
  expectInsideAndLongest(room, inRoom);
  EXPECT_EQ(inRoom.probeMisses, 0);
  glm::vec3 lo, hi;
  room.bounds(lo, hi);  // y from -0.2 to 3.2, in float: the eye is at their mean
  EXPECT_NEAR(inRoom.eye.y, 0.5 * (double(lo.y) + double(hi.y)), 1e-12);
  const Scene court = roomScene({-4, 0, -6}, {4, 10, 6}, false, true);
  const AutoCameraChoice inCourt = chooseAutoCamera(court);
  expectInsideAndLongest(court, inCourt);
  EXPECT_EQ(inCourt.probeMisses, 1);
  EXPECT_NEAR(inCourt.eye.y, 1.7, 1e-12);
}

TEST(AutoLights, AreDeterministicAndAsManyAsAskedFor) {
  const Scene s = makeBuiltinScene("cube");
  for (uint32_t n : {0u, 1u, 10u, 33u}) {
    const AutoLights a = autoLights(s, n), b = autoLights(s, n);
    ASSERT_EQ(a.lights.size(), n);
    EXPECT_EQ(a.interior + a.shell, n);
    for (uint32_t i = 0; i < n; ++i) {
      EXPECT_EQ(a.lights[i].position, b.lights[i].position);
      EXPECT_EQ(a.lights[i].range, b.lights[i].range);
      EXPECT_EQ(a.lights[i].color, b.lights[i].color);
      EXPECT_GT(a.lights[i].range, 0.0f);
      EXPECT_GT(a.lights[i].intensity, 0.0f);
      EXPECT_TRUE(a.lights[i].castShadows);
    }
  }
  // A different seed draws different lights.
  EXPECT_NE(autoLights(s, 4, 1).lights[0].position, autoLights(s, 4, 2).lights[0].position);
}

// A solid filling its bounds has no free point inside them: every interior draw must be refused
// (64 per even-indexed light) and every light goes to the shell. A room of the same size (the
// walls facing in) is free space inside: every even-indexed light stays inside it.
TEST(AutoLights, AvoidTheInsideOfSolidsAndKeepToFreeSpaceInARoom) {
  const glm::dvec3 lo(-2, 0, -3), hi(2, 3, 3);
  const AutoLights solid = autoLights(boxScene(lo, hi, false), 10);
  EXPECT_EQ(solid.interior, 0u);
  EXPECT_EQ(solid.shell, 10u);
  EXPECT_EQ(solid.rejectedDraws, 5u * 64u);
  const AutoLights room = autoLights(boxScene(lo, hi, true), 10);
  EXPECT_EQ(room.interior, 5u);
  EXPECT_EQ(room.rejectedDraws, 0u);
  for (uint32_t i = 0; i < 10; i += 2) {
    const glm::dvec3 p(room.lights[i].position);
    // Inside, and at least 2 % of r = 0.5·|hi - lo| from every wall.
    const double clearance = 0.02 * 0.5 * glm::length(hi - lo);
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(p[a] - lo[a], clearance) << i;
      EXPECT_GE(hi[a] - p[a], clearance) << i;
    }
  }
}

// Shell lights sit outside the bounds' sphere and reach every corner of the bounds.
TEST(AutoLights, ShellLightsAreOutsideAndReachTheWholeScene) {
  const Scene s = boxScene({-2, 0, -3}, {2, 3, 3}, false);
  glm::vec3 lo, hi;
  s.bounds(lo, hi);
  const glm::dvec3 c = 0.5 * (glm::dvec3(lo) + glm::dvec3(hi));
  const double r = 0.5 * glm::length(glm::dvec3(hi) - glm::dvec3(lo));
  std::vector<glm::dvec3> pts;
  corners(s, pts);
  for (const Light& l : autoLights(s, 7).lights) {
    EXPECT_GT(glm::length(glm::dvec3(l.position) - c), r);
    EXPECT_GT(l.position.y, c.y);  // from above: elevations 20..65°
    for (const glm::dvec3& p : pts) EXPECT_LT(glm::length(p - glm::dvec3(l.position)), double(l.range));
  }
}

TEST(CompleteScene, LeavesAScenesOwnCameraAndLightsAlone) {
  Scene s = makeBuiltinScene("cube");
  const Scene before = s;
  EXPECT_TRUE(completeScene(s, {}).empty());
  EXPECT_EQ(s.cameraSource, "scene");
  EXPECT_EQ(s.lightsSource, "scene");
  ASSERT_EQ(s.lights.size(), before.lights.size());
  EXPECT_EQ(s.lights[0].position, before.lights[0].position);
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].view, before.cameras[0].view);
}

TEST(CompleteScene, GivesWhatIsMissingOrAskedForAndSaysSo) {
  Scene bare = makeBuiltinScene("cube");
  bare.cameras.clear();
  bare.lights.clear();
  const std::vector<std::string> lines = completeScene(bare, {});
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[0].find("has no camera"), std::string::npos) << lines[0];
  EXPECT_NE(lines[1].find("has no lights: 10 automatic"), std::string::npos) << lines[1];
  EXPECT_EQ(bare.cameraSource, "auto");
  EXPECT_EQ(bare.lightsSource, "auto");
  EXPECT_EQ(bare.lights.size(), kDefaultAutoLights);
  ASSERT_EQ(bare.cameras.size(), 1u);

  // A config that gives no lights on purpose ("lights": []) gets none.
  Scene dark = makeBuiltinScene("cube");
  dark.lights.clear();
  dark.lightsSource = "config";
  completeScene(dark, {});
  EXPECT_TRUE(dark.lights.empty());

  // camera=auto goes first and keeps the scene's own; light_count replaces the scene's lights.
  Scene asked = makeBuiltinScene("cube");
  completeScene(asked, AutoRequest{true, 33});
  ASSERT_EQ(asked.cameras.size(), 2u);
  EXPECT_EQ(asked.cameras[0].name, "auto");
  EXPECT_EQ(asked.lights.size(), 33u);
  EXPECT_EQ(asked.lightsSource, "auto");
  EXPECT_EQ(asked.cameraSource, "auto");
}

}  // namespace
}  // namespace hb
