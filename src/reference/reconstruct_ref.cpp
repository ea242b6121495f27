#include "reference/reconstruct_ref.h"

#include <cmath>

#include "base/errors.h"

namespace hb {

template <typename T>
ReconstructionCamera<T> reconstructionCamera(const glm::mat<4, 4, T>& view, const glm::mat<4, 4, T>& proj,
                                             uint32_t width, uint32_t height) {
  HB_ASSERT(width > 0 && height > 0);
  return {glm::inverse(view), glm::inverse(proj * view), proj[0][0], proj[1][1], proj[2][2], proj[3][2], width, height};
}

// Pixel centre → NDC with the fma form Herbie suggested (thesis 4.3.2).
template <typename T>
static glm::vec<2, T> ndcOf(const ReconstructionCamera<T>& cam, uint32_t x, uint32_t y) {
  return {std::fma((T(x) + T(0.5)) / T(cam.width), T(2), T(-1)),
          std::fma((T(y) + T(0.5)) / T(cam.height), T(2), T(-1))};
}

template <typename T>
glm::vec<3, T> worldFromDepth(const ReconstructionCamera<T>& cam, uint32_t x, uint32_t y, T depth) {
  const glm::vec<2, T> ndc = ndcOf(cam, x, y);
  // Thesis eq. 4.3: the inverse projection applied to (ndc, depth, 1), inlined.
  glm::vec<4, T> v(ndc.x / cam.a, ndc.y / cam.b, T(-1), (depth + cam.c) / cam.d);
  v /= v.w;
  return glm::vec<3, T>(cam.viewInv * v);
}

template <typename T>
glm::vec<3, T> worldFromDepthPlain(const ReconstructionCamera<T>& cam, uint32_t x, uint32_t y, T depth) {
  const glm::vec<2, T> ndc = ndcOf(cam, x, y);
  const glm::vec<4, T> w = cam.viewProjInv * glm::vec<4, T>(ndc, depth, T(1));
  return glm::vec<3, T>(w) / w.w;
}

namespace {

template <typename T>
struct Sampler {
  const std::vector<float>& depth;
  const ReconstructionCamera<T>& cam;

  // Missing = outside the image or sky (depth 0, or anything not > 0).
  bool has(int64_t x, int64_t y) const {
    if (x < 0 || y < 0 || x >= int64_t(cam.width) || y >= int64_t(cam.height)) return false;
    return depth[size_t(y) * cam.width + size_t(x)] > 0.0f;
  }
  T d(int64_t x, int64_t y) const { return T(depth[size_t(y) * cam.width + size_t(x)]); }
  glm::vec<3, T> p(int64_t x, int64_t y) const { return worldFromDepth(cam, uint32_t(x), uint32_t(y), d(x, y)); }

  // Derivative of the world position along (sx, sy), or false when no neighbour exists.
  bool derivative(int64_t x, int64_t y, int sx, int sy, NormalMethod method, glm::vec<3, T>& out) const {
    const bool r1 = has(x + sx, y + sy), l1 = has(x - sx, y - sy);
    if (method == NormalMethod::Improved) {
      const bool leftOk = l1 && has(x - 2 * sx, y - 2 * sy);
      const bool rightOk = r1 && has(x + 2 * sx, y + 2 * sy);
      if (leftOk || rightOk) {
        bool useLeft = leftOk;
        if (leftOk && rightOk) {
          // Linear extrapolation of raw depth to the centre; exact on planes (header).
          const T d0 = d(x, y);
          const T eLeft = std::abs(T(2) * d(x - sx, y - sy) - d(x - 2 * sx, y - 2 * sy) - d0);
          const T eRight = std::abs(T(2) * d(x + sx, y + sy) - d(x + 2 * sx, y + 2 * sy) - d0);
          useLeft = eLeft <= eRight;
        }
        out = useLeft ? p(x, y) - p(x - sx, y - sy) : p(x + sx, y + sy) - p(x, y);
        return true;
      }
    }
    // Naive: the next sample, or the previous one at the last column/row (or beside sky).
    if (r1)
      out = p(x + sx, y + sy) - p(x, y);
    else if (l1)
      out = p(x, y) - p(x - sx, y - sy);
    else
      return false;
    return true;
  }
};

}  // namespace

template <typename T>
glm::vec<3, T> reconstructNormal(const std::vector<float>& depth, const ReconstructionCamera<T>& cam, uint32_t x,
                                 uint32_t y, NormalMethod method, bool* ok) {
  HB_ASSERT(depth.size() == size_t(cam.width) * cam.height && x < cam.width && y < cam.height);
  if (ok) *ok = false;
  const Sampler<T> s{depth, cam};
  if (!s.has(x, y)) return glm::vec<3, T>(0);
  glm::vec<3, T> dx, dy;
  if (!s.derivative(x, y, 1, 0, method, dx) || !s.derivative(x, y, 0, 1, method, dy)) return glm::vec<3, T>(0);
  glm::vec<3, T> n = glm::cross(dx, dy);
  const T len2 = glm::dot(n, n);
  if (!(len2 > T(0)) || !std::isfinite(len2)) return glm::vec<3, T>(0);  // collinear samples
  n /= std::sqrt(len2);
  const glm::vec<3, T> eye(cam.viewInv[3]);
  if (glm::dot(n, eye - s.p(x, y)) < T(0)) n = -n;  // face the camera
  if (ok) *ok = true;
  return n;
}

std::vector<ReconstructedPixel> reconstructImage(const std::vector<float>& depth,
                                                 const ReconstructionCamera<double>& cam, NormalMethod method) {
  HB_ASSERT(depth.size() == size_t(cam.width) * cam.height);
  std::vector<ReconstructedPixel> out(depth.size());
  for (uint32_t y = 0; y < cam.height; ++y)
    for (uint32_t x = 0; x < cam.width; ++x) {
      ReconstructedPixel& px = out[size_t(y) * cam.width + x];
      const float d = depth[size_t(y) * cam.width + x];
      px.sky = !(d > 0.0f);
      if (px.sky) continue;
      px.position = worldFromDepth(cam, x, y, double(d));
      px.normal = reconstructNormal(depth, cam, x, y, method, &px.hasNormal);
    }
  return out;
}

#define HB_RECONSTRUCT_INSTANTIATE(T)                                                                                 \
  template ReconstructionCamera<T> reconstructionCamera(const glm::mat<4, 4, T>&, const glm::mat<4, 4, T>&, uint32_t, \
                                                        uint32_t);                                                    \
  template glm::vec<3, T> worldFromDepth(const ReconstructionCamera<T>&, uint32_t, uint32_t, T);                      \
  template glm::vec<3, T> worldFromDepthPlain(const ReconstructionCamera<T>&, uint32_t, uint32_t, T);                 \
  template glm::vec<3, T> reconstructNormal(const std::vector<float>&, const ReconstructionCamera<T>&, uint32_t,      \
                                            uint32_t, NormalMethod, bool*);
HB_RECONSTRUCT_INSTANTIATE(float)
HB_RECONSTRUCT_INSTANTIATE(double)
#undef HB_RECONSTRUCT_INSTANTIATE

}  // namespace hb
