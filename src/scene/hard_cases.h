// Small scenes built in code for the numerical tests: each isolates one thing that breaks
// depth reconstruction, normal reconstruction, light culling or shadow rays. Every scene has one
// camera (cameras[0]), at least one point light and only a grey dielectric material unless said
// otherwise. Unless said otherwise the camera is meant for 1920x1080 (yfov 60 degrees), y is up
// and geometry is closed or single quads. Only makeDegenerate holds degenerate triangles.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace hb {

// "plane": one 10 x 10 m quad in the plane z = 0 facing +z; camera at (0, 0, 5) looking at the
// origin; one point light at (1, 1, 3), 20 cd, range 10.
Scene makePlane();

// "depth-step": two quads facing +z, x in [-5, 0] at z = 0 and x in [0, 5] at z = -1, so a 1 m
// depth step runs down the middle of the image; camera at (0, 0, 5) looking down -z; light at
// (0, 1, 3).
Scene makeDepthStep();

// "cube": a closed 1 m cube [-0.5, 0.5] x [0.5, 1.5] x [-0.5, 0.5] (24 vertices with bit-identical
// shared corner positions, so edges and vertices are exactly shared) floating above a ground quad
// at y = 0 (x, z in [-4, 4]). Light at (2, 4, 1.5). `offset` moves everything (the far-origin case).
Scene makeCube(glm::dvec3 offset = glm::dvec3(0.0));

// "tiny-triangles": against empty sky (no background geometry), at z = -10 in front of a camera
// at the origin looking down -z: a 40 x 40 field of right triangles with 2 cm legs (1.9 px at
// 1920x1080, where a pixel at 10 m is 2*10*tan(30 deg)/1080 = 1.07 cm) and 10 vertical strips
// 1 px (1.07 cm) wide and 4 m tall. All face +z; light at (0, 2, -5).
Scene makeTinyTriangles();

// "grazing": a 200 x 200 m ground quad (y = 0, facing +y); one light 500 m away in the direction
// (sqrt(1 - 0.01^2), 0.01, 0) from the origin, so N.L = 0.01 at the origin; 1e6 cd, range 1000.
// Camera at (0, 2, 6) looking at the origin.
Scene makeGrazing();

// "grazing-far": the same grazing light far away and seen nearly head-on, where depth
// reconstruction errs along the surface normal: a 1400 x 700 m quad centred kGrazingFarDepth =
// 500 m in front of a camera at the origin looking down -z (znear 0.1, zfar 1000), turned 30
// degrees about the vertical so that its depth varies (normal grazingFarNormal() = (sin 30, 0,
// cos 30); at least 433 m away, it fills the view but for sky on the right). One light 10 m
// above the plane's surface (along the normal), 1000 m from its centre along the plane: N.L =
// 0.01 at the centre (about 0.006 at the far edge, 0.02 at the near one); 4e6 cd, range 2000.
inline constexpr double kGrazingFarDepth = 500.0;
glm::dvec3 grazingFarNormal();
Scene makeGrazingFar();

// "thin-gap": a receiver quad at y = 0 (2 x 2 m) and a closed occluder box 40 x 1 x 40 cm whose
// underside is kThinGap = 1 mm above it, seen from a camera 0.5 m above, 0.8 m away (znear 0.01).
// Light at (0.5, 2, 0.3): the receiver under the box is in shadow.
inline constexpr double kThinGap = 0.001;
Scene makeThinGap();

// "degenerate": a 4 x 4 m quad at y = 0 of 16 x 16 cells (512 good triangles) with degenerate
// triangles mixed into the same primitive: zero-area triangles with three collinear vertices,
// triangles that repeat an index (a, a, b) and triangles of three distinct vertices at one
// position. kDegenerateCount of them; all positions and normals finite. Camera above, light above.
inline constexpr uint32_t kDegenerateCount = 48;
Scene makeDegenerate();

// "open-occluder": a single quad (x in [-1, 1], y in [0.5, 1.5], z = 0, normal +z) with a
// double-sided material (materials[1]), over a ground quad at y = 0 (x, z in [-4, 4]). The light
// at (0, 6, 3) is on its front side; the camera at (0, 2.5, -4) sees its back and the shadow it
// casts on the ground behind it (z in [-1, -0.27]).
Scene makeOpenOccluder();

// "far-origin": makeCube moved kFarOriginOffset = 10 km along x, in vertex positions (identity
// instance), camera and light moved with it. float spacing there is 2^-10 m ~ 1 mm.
inline constexpr double kFarOriginOffset = 10000.0;
Scene makeFarOrigin();

// "far-planes": three quads facing +z at distances kFarPlaneDepths from a camera at the origin
// looking down -z (znear 0.05, zfar 1000); each covers a third of the image (left: 0.1 m, middle:
// 100 m, right: 900 m) and overhangs its third by 5 %. One light in front of each.
inline constexpr double kFarPlaneDepths[3] = {0.1, 100.0, 900.0};
Scene makeFarPlanes();

// Names of the built-in scenes: "atrium" and the hard cases above, in that order.
// "microbench-262144", "microbench-144": the 3D rasterization paper's microbenchmark (Davidovic et
// al. 2012, Sect. 5: 262,144 and 144 triangles): random triangles of random orientation at depths
// 4..12 m in front of a camera at the origin looking down -z, sized to cover a 1920x1080 screen
// about 4 times over (fixed seed); one light at (0, 3, -2).
// The same construction makes the scenes `configs/ceilings.json` measures ceilings on
// (docs/methods/3d-rasterization.md "Measured ceilings"):
// - "microbench-dense": 4,096 triangles covering the screen about 64 times over (layers = 64), so
//   that every 8x8 tile's list is long and launching a tile and reading its setups are spread over
//   many steps of the tile pass's loop;
// - "microbench-tiny": 262,144 triangles covering it about a quarter over, legs of about 2 pixels,
//   so that the per-triangle pass does the least work a triangle can ask of it.
Scene makeMicrobench(uint32_t triangles, double layers = 4);

std::vector<std::string> builtinSceneNames();
// Built-in scenes for benchmarks only (the microbenchmarks): loadable by name like the others, but
// not in builtinSceneNames(), which the numerical tests iterate (262,144 random, intersecting
// triangles take minutes per CPU shadow reference on lavapipe).
std::vector<std::string> benchmarkSceneNames();
// builtinSceneNames() then benchmarkSceneNames(): every name makeBuiltinScene accepts.
std::vector<std::string> allSceneNames();

// What follows an unknown scene name in its one-line error: `did you mean "atrium"?` when the
// name is close to a built-in one (a typo, as json_reader's closestKey judges it), else their list
// "atrium, plane, ...".
std::string unknownSceneHint(const std::string& name);

// One line for people (`hybridbench scene list`): what the built-in scene `name` is and what it
// isolates; "" for a name that is not built in.
std::string builtinSceneDescription(const std::string& name);

// Builds a built-in scene by name ("atrium" uses the default AtriumParams). Throws InputError
// naming the valid names when `name` is not one of them.
Scene makeBuiltinScene(const std::string& name);

}  // namespace hb
