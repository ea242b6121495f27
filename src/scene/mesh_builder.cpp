#include "scene/mesh_builder.h"

#include <cmath>
#include <limits>
#include <utility>

#include "base/errors.h"

namespace hb {

namespace {
constexpr double kTwoPi = 6.283185307179586;

Vertex makeVertex(glm::dvec3 p, glm::dvec3 n, glm::dvec2 uv) {
  return Vertex{glm::vec3(p), glm::vec3(glm::normalize(n)), glm::vec2(uv)};
}
}  // namespace

MeshBuilder::Bucket& MeshBuilder::bucket(uint32_t material) {
  if (material >= buckets_.size()) buckets_.resize(material + 1);
  return buckets_[material];
}

uint32_t MeshBuilder::vertex(uint32_t material, const Vertex& v) {
  Bucket& b = bucket(material);
  HB_ASSERT(b.vertices.size() < std::numeric_limits<uint32_t>::max());
  b.vertices.push_back(v);
  return uint32_t(b.vertices.size() - 1);
}

void MeshBuilder::triangle(uint32_t material, uint32_t a, uint32_t b, uint32_t c) {
  Bucket& bk = bucket(material);
  const Vertex& va = bk.vertices[a];
  const Vertex& vb = bk.vertices[b];
  const Vertex& vc = bk.vertices[c];
  // Counter-clockwise front faces: the geometric normal (b-a) x (c-a) must agree with the shading
  // normals. Computed in double so that tiny triangles far from the origin decide correctly.
  const glm::dvec3 pa(va.position);
  const glm::dvec3 g = glm::cross(glm::dvec3(vb.position) - pa, glm::dvec3(vc.position) - pa);
  const glm::dvec3 n = glm::dvec3(va.normal) + glm::dvec3(vb.normal) + glm::dvec3(vc.normal);
  if (glm::dot(g, n) < 0.0) std::swap(b, c);
  bk.indices.insert(bk.indices.end(), {a, b, c});
}

void MeshBuilder::quad(uint32_t material, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  triangle(material, a, b, c);
  triangle(material, a, c, d);
}

void MeshBuilder::reserve(uint32_t material, size_t vertices, size_t indices) {
  Bucket& b = bucket(material);
  b.vertices.reserve(b.vertices.size() + vertices);
  b.indices.reserve(b.indices.size() + indices);
}

uint64_t MeshBuilder::triangleCount() const {
  uint64_t n = 0;
  for (const Bucket& b : buckets_) n += b.indices.size() / 3;
  return n;
}

void MeshBuilder::appendTo(Scene& scene) {
  Mesh mesh;
  mesh.name = name_;
  for (uint32_t m = 0; m < buckets_.size(); ++m) {
    Bucket& b = buckets_[m];
    if (b.indices.empty()) continue;
    HB_ASSERT(scene.vertices.size() + b.vertices.size() <= std::numeric_limits<uint32_t>::max());
    HB_ASSERT(scene.indices.size() + b.indices.size() <= std::numeric_limits<uint32_t>::max());
    Primitive p;
    p.firstIndex = uint32_t(scene.indices.size());
    p.indexCount = uint32_t(b.indices.size());
    p.vertexOffset = uint32_t(scene.vertices.size());
    p.vertexCount = uint32_t(b.vertices.size());
    p.material = m;
    scene.vertices.insert(scene.vertices.end(), b.vertices.begin(), b.vertices.end());
    scene.indices.insert(scene.indices.end(), b.indices.begin(), b.indices.end());
    mesh.primitives.push_back(p);
  }
  buckets_.clear();
  scene.meshes.push_back(std::move(mesh));
  scene.instances.push_back(Instance{uint32_t(scene.meshes.size() - 1), glm::mat4(1.0f)});
}

void addQuad(MeshBuilder& mb, uint32_t material, glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2, glm::dvec3 p3,
             glm::dvec3 normal) {
  const double w = glm::length(p1 - p0), h = glm::length(p3 - p0);
  const uint32_t a = mb.vertex(material, makeVertex(p0, normal, {0, 0}));
  const uint32_t b = mb.vertex(material, makeVertex(p1, normal, {w, 0}));
  const uint32_t c = mb.vertex(material, makeVertex(p2, normal, {w, h}));
  const uint32_t d = mb.vertex(material, makeVertex(p3, normal, {0, h}));
  mb.quad(material, a, b, c, d);
}

void addBox(MeshBuilder& mb, uint32_t material, glm::dvec3 lo, glm::dvec3 hi, double uvPerMetre) {
  HB_ASSERT(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z);
  mb.reserve(material, 24, 36);
  // One face per axis and sign; (u, v) are the two other axes.
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      glm::dvec3 n(0.0);
      n[axis] = side ? 1.0 : -1.0;
      uint32_t idx[4];
      for (int k = 0; k < 4; ++k) {
        const bool hu = k == 1 || k == 2, hv = k >= 2;
        glm::dvec3 p;
        p[axis] = side ? hi[axis] : lo[axis];
        p[u] = hu ? hi[u] : lo[u];
        p[v] = hv ? hi[v] : lo[v];
        const glm::dvec2 uv(p[u] * uvPerMetre, p[v] * uvPerMetre);
        idx[k] = mb.vertex(material, makeVertex(p, n, uv));
      }
      mb.quad(material, idx[0], idx[1], idx[2], idx[3]);
    }
  }
}

void addLathe(MeshBuilder& mb, uint32_t material, const std::vector<std::vector<glm::dvec2>>& sections,
              uint32_t segments, const glm::dmat4& transform) {
  HB_ASSERT(segments >= 3);
  const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(transform)));
  // Ring directions, shared by every profile point; the seam is duplicated for the uv seam.
  std::vector<glm::dvec2> ring(segments + 1);
  for (uint32_t j = 0; j <= segments; ++j) {
    const double phi = kTwoPi * (j % segments) / segments;
    ring[j] = {std::cos(phi), std::sin(phi)};
  }
  double totalLength = 0.0;
  for (const auto& s : sections)
    for (size_t k = 1; k < s.size(); ++k) totalLength += glm::length(s[k] - s[k - 1]);
  double lengthSoFar = 0.0;

  for (const auto& s : sections) {
    HB_ASSERT(s.size() >= 2);
    const size_t m = s.size();
    // 2D outward normal of segment k (p_k -> p_{k+1}): the tangent turned clockwise, (dy, -dr).
    std::vector<glm::dvec2> segNormal(m - 1);
    for (size_t k = 0; k + 1 < m; ++k) {
      const glm::dvec2 t = s[k + 1] - s[k];
      HB_ASSERT(glm::length(t) > 0.0);
      segNormal[k] = glm::normalize(glm::dvec2(t.y, -t.x));
    }
    mb.reserve(material, m * (segments + 1), (m - 1) * segments * 6);
    std::vector<uint32_t> prevRing, curRing(segments + 1);
    for (size_t k = 0; k < m; ++k) {
      if (k > 0) lengthSoFar += glm::length(s[k] - s[k - 1]);
      glm::dvec2 n2 = k == 0 ? segNormal[0] : k == m - 1 ? segNormal[m - 2] : segNormal[k - 1] + segNormal[k];
      HB_ASSERT(glm::length(n2) > 1e-6);  // a turn of 180 degrees would cancel the normals
      n2 = glm::normalize(n2);
      const double r = s[k].x, y = s[k].y;
      for (uint32_t j = 0; j <= segments; ++j) {
        const glm::dvec3 p = glm::dvec3(transform * glm::dvec4(r * ring[j].x, y, r * ring[j].y, 1.0));
        const glm::dvec3 n = normalMatrix * glm::dvec3(n2.x * ring[j].x, n2.y, n2.x * ring[j].y);
        const glm::dvec2 uv(double(j) / segments, totalLength > 0 ? lengthSoFar / totalLength : 0.0);
        curRing[j] = mb.vertex(material, makeVertex(p, n, uv));
      }
      if (k > 0) {
        const bool poleA = s[k - 1].x == 0.0, poleB = r == 0.0;
        for (uint32_t j = 0; j < segments; ++j) {
          if (poleA && poleB) break;  // a segment along the axis sweeps nothing
          if (poleA)
            mb.triangle(material, prevRing[j], curRing[j], curRing[j + 1]);
          else if (poleB)
            mb.triangle(material, prevRing[j], prevRing[j + 1], curRing[j]);
          else
            mb.quad(material, prevRing[j], prevRing[j + 1], curRing[j + 1], curRing[j]);
        }
      }
      prevRing = curRing;
    }
  }
}

void addSphere(MeshBuilder& mb, uint32_t material, const glm::dmat4& transform, uint32_t segments, uint32_t bands) {
  HB_ASSERT(bands >= 2);
  std::vector<glm::dvec2> profile(bands + 1);
  for (uint32_t i = 0; i <= bands; ++i) {
    const double theta = -kTwoPi / 4 + kTwoPi / 2 * i / bands;  // south pole to north pole
    profile[i] = {i == 0 || i == bands ? 0.0 : std::cos(theta), std::sin(theta)};
  }
  addLathe(mb, material, {profile}, segments, transform);
}

void addCylinder(MeshBuilder& mb, uint32_t material, const glm::dmat4& transform, double radius, double height,
                 uint32_t segments, uint32_t rings) {
  HB_ASSERT(radius > 0 && height > 0 && rings >= 1);
  std::vector<glm::dvec2> side(rings + 1);
  for (uint32_t i = 0; i <= rings; ++i) side[i] = {radius, height * i / rings};
  addLathe(mb, material, {{{0, 0}, {radius, 0}}, side, {{radius, height}, {0, height}}}, segments, transform);
}

void addTorus(MeshBuilder& mb, uint32_t material, const glm::dmat4& transform, double major, double minor,
              uint32_t segments, uint32_t tubeSegments) {
  HB_ASSERT(major > minor && minor > 0 && tubeSegments >= 3);
  // Counter-clockwise round the tube's centre: the solid is on the left.
  std::vector<glm::dvec2> profile(tubeSegments + 1);
  for (uint32_t i = 0; i <= tubeSegments; ++i) {
    const double a = kTwoPi * (i % tubeSegments) / tubeSegments;
    profile[i] = {major + minor * std::cos(a), minor * std::sin(a)};
  }
  addLathe(mb, material, {profile}, segments, transform);
}

void addSheet(MeshBuilder& mb, uint32_t material, uint32_t nu, uint32_t nv,
              const std::function<Vertex(double u, double v)>& at) {
  HB_ASSERT(nu >= 1 && nv >= 1);
  mb.reserve(material, size_t(nu + 1) * (nv + 1), size_t(nu) * nv * 6);
  std::vector<uint32_t> prev(nu + 1), cur(nu + 1);
  for (uint32_t i = 0; i <= nv; ++i) {
    for (uint32_t j = 0; j <= nu; ++j) cur[j] = mb.vertex(material, at(double(j) / nu, double(i) / nv));
    if (i > 0)
      for (uint32_t j = 0; j < nu; ++j) mb.quad(material, prev[j], prev[j + 1], cur[j + 1], cur[j]);
    std::swap(prev, cur);
  }
}

}  // namespace hb
