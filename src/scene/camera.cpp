#include "scene/camera.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace hb {

template <typename T>
static glm::mat<4, 4, T> projection(T aspect, T yfov, T zn, T zf) {
  const T t = std::tan(yfov / T(2));
  glm::mat<4, 4, T> p(T(0));
  p[0][0] = T(1) / (aspect * t);  // A
  p[1][1] = T(-1) / t;            // B: Vulkan's y points down
  p[2][2] = zn / (zf - zn);       // C
  p[3][2] = zf * zn / (zf - zn);  // D
  p[2][3] = T(-1);                // w = -z_view
  return p;
}

glm::mat4 reverseZProjection(float aspect, float yfov, float znear, float zfar) {
  return projection<float>(aspect, yfov, znear, zfar);
}
glm::dmat4 reverseZProjectionD(double aspect, double yfov, double znear, double zfar) {
  return projection<double>(aspect, yfov, znear, zfar);
}

template <typename T>
static glm::mat<4, 4, T> orthographic(T xmag, T ymag, T zn, T zf) {
  glm::mat<4, 4, T> p(T(0));
  p[0][0] = T(1) / xmag;
  p[1][1] = T(-1) / ymag;  // Vulkan's y points down
  p[2][2] = T(1) / (zf - zn);
  p[3][2] = zf / (zf - zn);
  p[3][3] = T(1);
  return p;
}

glm::mat4 reverseZOrthographic(float xmag, float ymag, float znear, float zfar) {
  return orthographic<float>(xmag, ymag, znear, zfar);
}
glm::dmat4 reverseZOrthographicD(double xmag, double ymag, double znear, double zfar) {
  return orthographic<double>(xmag, ymag, znear, zfar);
}

glm::mat4 lookAt(glm::vec3 eye, glm::vec3 target, glm::vec3 up) { return glm::lookAtRH(eye, target, up); }

}  // namespace hb
