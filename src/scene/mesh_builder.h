// Geometry helpers for scenes built in code (the atrium, the hard cases): a builder that collects
// one mesh as one primitive per material, and closed shapes (boxes, lathes: spheres, cylinders,
// tori, vases) plus open parametric sheets.
//
// Winding: every triangle is emitted counter-clockwise around the normals its vertices carry
// (MeshBuilder::triangle swaps two corners when the geometric normal disagrees with them). So the
// shapes only have to get their normals right; for the closed shapes the normals point out of the
// solid, which the tests check through the signed volume.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace hb {

class MeshBuilder {
 public:
  explicit MeshBuilder(std::string name) : name_(std::move(name)) {}

  // Adds a vertex to the primitive of `material`; returns its index within that primitive.
  uint32_t vertex(uint32_t material, const Vertex& v);
  // Adds triangle (a, b, c) of `material` (indices returned by vertex() for that material). The
  // winding is made counter-clockwise around the sum of the three vertex normals.
  void triangle(uint32_t material, uint32_t a, uint32_t b, uint32_t c);
  // Two triangles (a, b, c) and (a, c, d); a b c d go round a planar or nearly planar quad.
  void quad(uint32_t material, uint32_t a, uint32_t b, uint32_t c, uint32_t d);
  // Asks for room for `n` more vertices of `material` (only a speed hint).
  void reserve(uint32_t material, size_t vertices, size_t indices);

  uint64_t triangleCount() const;
  // Appends the mesh (a Primitive per material that has triangles, in material order) and one
  // identity instance to `scene`. The builder is empty afterwards.
  void appendTo(Scene& scene);

 private:
  struct Bucket {
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices;
  };
  Bucket& bucket(uint32_t material);
  std::string name_;
  std::vector<Bucket> buckets_;  // indexed by material
};

// Axis-aligned closed box [lo, hi] (lo < hi on every axis): 24 vertices, flat outward normals,
// uv = face coordinates in metres times `uvPerMetre`.
void addBox(MeshBuilder& mb, uint32_t material, glm::dvec3 lo, glm::dvec3 hi, double uvPerMetre = 1.0);

// Surface of revolution about the local y axis, then mapped by `transform` (any invertible affine
// map; normals use its inverse transpose). `sections` are polylines in the (r, y) half-plane
// (r >= 0), traversed with the solid on their left (counter-clockwise: a sphere goes from the
// south pole up to the north pole). Normals are smooth inside a section and not shared between
// sections (where a profile has a crease, start a new section at it). Consecutive points must
// differ and a section must not turn by 90 degrees or more between two segments. Points with
// r == 0 become poles (triangle fans), so no triangle is degenerate. `segments` >= 3 around.
// A profile whose sections start and end on the axis (or close on themselves) gives a closed solid.
void addLathe(MeshBuilder& mb, uint32_t material, const std::vector<std::vector<glm::dvec2>>& sections,
              uint32_t segments, const glm::dmat4& transform);

// Unit sphere mapped by `transform` (an ellipsoid under non-uniform scale): `segments` around,
// `bands` >= 2 from pole to pole; 2 * segments * (bands - 1) triangles.
void addSphere(MeshBuilder& mb, uint32_t material, const glm::dmat4& transform, uint32_t segments, uint32_t bands);

// Closed cylinder of `radius` from y = 0 to y = height in local space, mapped by `transform`:
// 2 * segments * (rings + 1) triangles.
void addCylinder(MeshBuilder& mb, uint32_t material, const glm::dmat4& transform, double radius, double height,
                 uint32_t segments, uint32_t rings);

// Torus about the local y axis (ring radius `major` > tube radius `minor` > 0), mapped by
// `transform`: 2 * segments * tubeSegments triangles.
void addTorus(MeshBuilder& mb, uint32_t material, const glm::dmat4& transform, double major, double minor,
              uint32_t segments, uint32_t tubeSegments);

// Open sheet: a grid of nu x nv quads over (u, v) in [0,1]^2; `at(u, v)` gives each vertex (its
// normal picks the front side). The caller makes sure no quad collapses.
void addSheet(MeshBuilder& mb, uint32_t material, uint32_t nu, uint32_t nv,
              const std::function<Vertex(double u, double v)>& at);

// A quad with flat normal `normal`; p0..p3 go round it (either direction).
void addQuad(MeshBuilder& mb, uint32_t material, glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2, glm::dvec3 p3,
             glm::dvec3 normal);

}  // namespace hb
