// The in-memory scene every pass and every CPU reference works from: one vertex and one index
// array for all meshes, meshes made of primitives (one material each), instances with world
// transforms, materials, decoded textures, punctual lights and cameras.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace hb {

struct Vertex {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec2 uv;
};

// A run of triangles with one material. Indices are relative to vertexOffset.
struct Primitive {
  uint32_t firstIndex = 0;
  uint32_t indexCount = 0;
  uint32_t vertexOffset = 0;
  uint32_t vertexCount = 0;
  uint32_t material = 0;

  bool operator==(const Primitive&) const = default;
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;

  bool operator==(const Mesh&) const = default;
};

struct Instance {
  uint32_t mesh = 0;
  glm::mat4 transform{1.0f};  // object → world

  bool operator==(const Instance&) const = default;
};

struct Material {
  std::string name;
  glm::vec4 baseColorFactor{1.0f};
  float metallicFactor = 1.0f;  // glTF defaults
  float roughnessFactor = 1.0f;
  int baseColorTexture = -1;  // index into Scene::textures, -1 = none
  int metallicRoughnessTexture = -1;
  bool doubleSided = false;

  bool operator==(const Material&) const = default;
};

// Decoded 8-bit RGBA, row-major, top row first.
struct Texture {
  std::string name;
  uint32_t width = 0;
  uint32_t height = 0;
  bool srgb = false;  // base colour textures are sRGB, metallic-roughness linear
  std::vector<uint8_t> rgba;

  bool operator==(const Texture&) const = default;
};

enum class LightType : uint32_t { Point = 0, Spot = 1, Directional = 2 };

// KHR_lights_punctual, in world space. Intensity in candela (point/spot) or lux (directional).
struct Light {
  std::string name;
  LightType type = LightType::Point;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // unit; the direction the light points
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float range = 0.0f;  // > 0 always after loading: missing ranges come from thesis eq. 4.1
  bool rangeFromEq41 = false;
  float innerConeAngle = 0.0f;                // radians, spot only
  float outerConeAngle = 0.785398163397448f;  // radians, spot only (glTF default pi/4)
  bool castShadows = true;

  bool operator==(const Light&) const = default;
};

// Light from everywhere (the sky's, say) at radiance color·intensity, which reaches a point as its
// ambient occlusion lets it: a Lambertian surface of albedo a sends a·color·intensity·AO. A scene's
// extras.ambient or a config's "ambient": {"color": [r, g, b], "intensity": x}. It lights the frame
// only through the ambient_occlusion effect (effects/ambient_occlusion/ao_effect.h): without the effect the
// frame is the thesis's, direct light alone.
struct Ambient {
  glm::vec3 color{1.0f};
  float intensity = 0.0f;
  bool operator==(const Ambient&) const = default;
};

// Light from every direction that varies with direction: the radiance arriving along a unit
// direction d is intensity·color·image(R_y(−rotation)·d), image an equirectangular map (linear
// RGB, row 0 looks up +y, column u at azimuth φ = 2π(u + 0.5)/width − π measured from −z towards
// +x) or 1 everywhere for a uniform colour. It lights the frame only through the
// environment_light effect (effects/environment_light/env_effect.h), which traces its visibility.
// A scene's extras.environment or a config's "environment" (scene/environment.h).
struct Environment {
  std::string image;  // the .hdr file as resolved (absolute); "" for a uniform colour
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float rotationDegrees = 0.0f;  // about +y, counter-clockwise seen from above
  uint32_t width = 1, height = 1;
  std::vector<glm::vec3> texels{glm::vec3(1.0f)};  // width·height, linear RGB, row-major, top row first
};

// How a camera maps pixels to rays (shaders/camera_ray.glsl.inc is the one definition).
// Perspective and orthographic are planar (the hardware rasterizer can draw them); the paraboloid
// (a hemisphere in a disk, 3DR paper Section 3.5) and latlong (the full sphere, equirectangular)
// are not, and only the computed primary methods render them.
enum class CameraProjection { Perspective, Orthographic, Paraboloid, Latlong };
const char* toString(CameraProjection p);

struct Camera {
  std::string name;
  glm::mat4 view{1.0f};  // world → view (right-handed, looking down -z, y up in view space)
  CameraProjection projection = CameraProjection::Perspective;
  float yfov = 1.0471975512f;      // radians (perspective)
  float xmag = 1.0f, ymag = 1.0f;  // orthographic: half the view's width and height (glTF)
  float znear = 0.1f;
  float zfar = 1000.0f;  // reverse-Z: near → depth 1, far → depth 0

  bool operator==(const Camera&) const = default;
};

// The camera's position in world space (the inverse view's translation), in double.
inline glm::dvec3 eyeOf(const Camera& c) { return glm::dvec3(glm::inverse(glm::dmat4(c.view))[3]); }

struct Scene {
  std::string name;
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
  std::vector<Mesh> meshes;
  std::vector<Instance> instances;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Light> lights;
  std::vector<Camera> cameras;  // cameras[0] is the one a render uses unless told otherwise
  // Where cameras[0] and the lights came from: "scene" (the file or the built-in), "config" (a
  // config's camera or lights) or "auto" (app/auto_scene.h: the scene brought none, or
  // light_count / camera=auto asked for them). Results record both.
  std::string cameraSource = "scene";
  std::string lightsSource = "scene";
  // The effects the scene calls for (a glTF's scenes[s].extras.effects, checked against
  // plan/effects.h by the loader); null when it says nothing. effectsOrigin names the file.
  nlohmann::json effects;
  std::string effectsOrigin;
  std::optional<Ambient> ambient;          // none: nothing for ambient occlusion to darken
  std::optional<Environment> environment;  // none: no environment light
  // The glTF extensions its geometry was decoded from (KHR_draco_mesh_compression,
  // EXT_meshopt_compression, KHR_mesh_quantization), comma-joined; empty when none. Not hashed:
  // it says how the file was stored, not what renders.
  std::string compression;

  uint64_t triangleCount() const;                   // over instances (a mesh instanced twice counts twice)
  void bounds(glm::vec3& lo, glm::vec3& hi) const;  // world-space AABB over instances
  // Every triangle in world space, 3 vertices each, in draw order (instance × primitive, as
  // GpuScene draws them): triangle k is the k-th triangle drawn, the id the 3D rasterizer reports.
  // The transform runs in double and rounds once per coordinate.
  std::vector<glm::vec3> worldTriangles() const;
};

// Thesis eq. 4.1: the distance at which I/D^2 falls to 0.02, D = 50*sqrt(0.02*I) = sqrt(50*I).
double rangeFromIntensity(double intensity);

}  // namespace hb
