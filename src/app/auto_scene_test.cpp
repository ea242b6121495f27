#include "app/auto_scene.h"
#include "base/numbers.h"

#include <cmath>

#include <gtest/gtest.h>

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

void corners(const Scene& s, std::vector<glm::dvec3>& out) {
  glm::vec3 lo, hi;
  s.bounds(lo, hi);
  for (int k = 0; k < 8; ++k) out.push_back({k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z});
}

// The automatic camera sees every corner of the bounds: each lies within the 30° half-angle cone
// round the view axis (so inside the vertical field of view, and the horizontal one at any aspect
// >= 1) and between the near and far planes. The bounds' sphere touches the cone, so a corner may
// sit on it: 1e-5 rad is float round-off of the view matrix (unit-scale rotation, translation of
// a few r) with room to spare, far below any real miss (a corner outside by a pixel at 1080 rows
// is 1e-3 rad).
TEST(AutoCamera, FramesTheWholeBoundsOfEveryScene) {
  for (const Scene& s : {makeBuiltinScene("cube"), makeAtrium(), makeBuiltinScene("far-origin"),
                         boxScene({0, 0, 0}, {1e-3, 2e-3, 1e-3}, false)}) {
    const Camera cam = autoCamera(s);
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
