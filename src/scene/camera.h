// Camera matrices. The projection has the structure of thesis eq. 2.1 (Vulkan clip space, y down,
// right-handed view space looking down -z) with reverse-Z: the near plane maps to depth 1 and the
// far plane to depth 0, as the thesis's text (section 2.6) says.
//
// Erratum: eq. 2.1 as printed has C = -zf/(zn-zf), D = -zf*zn/(zn-zf). With w = -z that maps the
// near plane to depth 0 and the far plane to depth -1 (outside Vulkan's [0,1]), i.e. it is not a
// reverse-Z matrix. The reverse-Z matrix with the same structure swaps the roles of the planes:
// C = zn/(zf-zn), D = zf*zn/(zf-zn). camera_test.cpp checks both facts.
#pragma once
#include <glm/glm.hpp>

namespace hb {

// glm is column-major: m[col][row]. Returns
//   | 1/(a*tan(fov/2))  0              0   0 |
//   | 0                -1/tan(fov/2)    0   0 |
//   | 0                 0               C   D |
//   | 0                 0              -1   0 |
// with a = width/height, C = zn/(zf-zn), D = zf*zn/(zf-zn).
glm::mat4 reverseZProjection(float aspect, float yfov, float znear, float zfar);
glm::dmat4 reverseZProjectionD(double aspect, double yfov, double znear, double zfar);

// The orthographic counterpart (glTF's xmag/ymag: half the view's width and height), reverse-Z
// and affine in view depth t = -z: depth = (zf - t)/(zf - zn), 1 at the near plane, 0 at the far.
//   | 1/xmag   0       0   0 |
//   | 0       -1/ymag  0   0 |
//   | 0        0       C   D |    C = 1/(zf-zn), D = zf/(zf-zn)
//   | 0        0       0   1 |
// Depth is then D - C·t, and t = (D - depth)/C inverts it.
glm::mat4 reverseZOrthographic(float xmag, float ymag, float znear, float zfar);
glm::dmat4 reverseZOrthographicD(double xmag, double ymag, double znear, double zfar);

// Right-handed look-at (view space looks down -z, y up).
glm::mat4 lookAt(glm::vec3 eye, glm::vec3 target, glm::vec3 up);

}  // namespace hb
