// CPU reference of world-position and normal reconstruction from a reverse-Z depth image (thesis
// 4.3.1, 4.3.2). Instantiate with T = float to mirror the GPU shader op for op, T = double for
// the reference. The depth image is row-major, width × height, top row first; depth 0 = sky.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace hb {

template <typename T>
struct ReconstructionCamera {
  glm::mat<4, 4, T> viewInv;      // view → world
  glm::mat<4, 4, T> viewProjInv;  // inverse(proj * view), for the plain variant
  T a, b, c, d;                   // proj[0][0], proj[1][1], proj[2][2], proj[3][2]
  uint32_t width, height;
};
// From a world → view matrix and a reverseZProjection matrix; the inverses are taken in T.
template <typename T>
ReconstructionCamera<T> reconstructionCamera(const glm::mat<4, 4, T>& view, const glm::mat<4, 4, T>& proj,
                                             uint32_t width, uint32_t height);

// Thesis Algorithm 4.1: ndc = fma((p + 0.5)/extent, 2, -1); v = (ndc.x/A, ndc.y/B, -1,
// (depth + C)/D); v /= v.w; world = viewInv * v. Precondition: depth > 0 (not sky).
template <typename T>
glm::vec<3, T> worldFromDepth(const ReconstructionCamera<T>& cam, uint32_t x, uint32_t y, T depth);
// The plain variant: inverse(viewProj) * (ndc.x, ndc.y, depth, 1), divided by w.
template <typename T>
glm::vec<3, T> worldFromDepthPlain(const ReconstructionCamera<T>& cam, uint32_t x, uint32_t y, T depth);

enum class NormalMethod { Naive, Improved };

struct ReconstructedPixel {
  glm::dvec3 position{0.0};  // world; 0 for sky
  glm::dvec3 normal{0.0};    // unit, facing the camera; 0 for sky or when no neighbour exists
  bool sky = false;
  bool hasNormal = false;
};

// Normal at (x, y), unit and facing the camera (dot(n, eye - P) >= 0), or 0 with *ok = false when
// the pixel is sky or no neighbour sample exists along an axis. Sky neighbours count as missing.
//  Naive: per axis the current and next sample (previous at the last column/row); n =
//    cross(dP/dx, dP/dy).
//  Improved [Wu; thesis 4.3.1]: per axis samples at -2..+2. Each outer pair is extrapolated
//    linearly to the centre in RAW depth: e_left = 2 d(-1) - d(-2), e_right = 2 d(+1) - d(+2).
//    Under reverse-Z, depth = C + D/(-z) is affine in 1/z, and for a plane 1/z is affine in screen
//    space, so the extrapolation is exact on planes. The side whose e lands closer to d(0) gives
//    the derivative: left P(0) - P(-1), right P(+1) - P(0); ties go left. A side needs both its
//    samples; with one side complete it is used; with neither, the naive rule applies.
template <typename T>
glm::vec<3, T> reconstructNormal(const std::vector<float>& depth, const ReconstructionCamera<T>& cam, uint32_t x,
                                 uint32_t y, NormalMethod method, bool* ok = nullptr);

// Every pixel, in double (the reference). Precondition: depth.size() == width*height.
std::vector<ReconstructedPixel> reconstructImage(const std::vector<float>& depth,
                                                 const ReconstructionCamera<double>& cam, NormalMethod method);

}  // namespace hb
