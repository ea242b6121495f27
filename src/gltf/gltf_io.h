// glTF 2.0 scenes in and out (tinygltf), plus a summary and a content hash of any hb::Scene.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace hb {

// What loadGltf skipped without failing. Each kind of skip is counted, and one line per kind
// says what was skipped and where it first happened.
struct GltfLoadWarnings {
  uint32_t skippedPrimitives = 0;  // points and lines (modes 0-3); strips and fans are converted
  uint32_t skippedCameras = 0;     // cameras neither perspective nor orthographic
  uint32_t skippedBroken = 0;      // triangle primitives whose data is broken (truncated, out of range)
  std::vector<std::string> messages;
};

// Loads a .gltf (JSON, external or data-URI buffers) or .glb file; the container is recognised by
// its first bytes, not its extension. Reads the default scene (or, with no scenes, every root
// node): each glTF mesh becomes one hb::Mesh whose TRIANGLES primitives (and strips and fans,
// converted to triangle lists) append to the shared Scene::vertices/indices; each node with a mesh
// becomes an Instance with its world transform; perspective and orthographic cameras and
// KHR_lights_punctual lights attached to nodes take the node's world
// transform (camera view = inverse world; light position = world translation, direction = world
// -Z). Missing NORMALs are computed (area-weighted), missing TEXCOORD_0 is (0,0), missing indices
// are 0..n-1, a point/spot light with no range gets rangeFromIntensity(intensity) (thesis eq.
// 4.1), a directional light gets range 0. Light extras {"castShadows": false} turn its shadows off.
// Textures (PNG, JPEG, WebP, AVIF) are decoded to RGBA8; the ones used as base colour are flagged
// sRGB. Primitives with
// no material use a "default" material appended to Scene::materials.
// Points and lines are skipped, and so are triangle primitives whose data is broken (truncated,
// an index past its vertices, an accessor past its buffer: a scene of nothing else is refused with
// the first one's fault) and cameras of an unknown type: they are counted in *warnings if given,
// otherwise one line per kind goes to stderr, as does one line naming the optional extensions the
// loader ignores, one naming the skins, morph targets and animations it does not read, one counting
// names that are not strings, and one counting the textures it cannot decode (KTX2 / Basis
// Universal: their materials keep their factors). docs/usage.md "Loader strictness" lists which
// faults are refused and which skipped. Compressed
// geometry is decoded (Draco, meshopt: gltf_compression.cpp; Scene::compression names it),
// quantized attributes read as KHR_mesh_quantization defines them and KHR_texture_transform
// applied to the texture coordinates; an unknown required extension is refused by name.
// Throws InputError (one line: file, field, what would fix it) on a missing or unreadable file (or
// a folder), malformed JSON or not glTF, glTF 1.0 (with how to convert it), a buffer's external
// file that is not there, a truncated or corrupt compressed stream (naming the mesh
// and the extension), a field of the wrong JSON type (gltf_structure.h), a file
// with nothing to draw (no scene and no nodes, a scene without nodes, no node with a mesh), an index that points past
// its array, an accessor that does not fit its bufferView or buffer, an unsupported component type or accessor type, a
// vertex index past the primitive's vertex count, non-finite positions, a light range <= 0, a cycle in the node graph,
// an extension it cannot read, a number in a transform, camera or light that a float cannot hold (beyond 3.4e38), a
// camera node with no inverse, an external URI that is not a regular file.
Scene loadGltf(const std::string& path, GltfLoadWarnings* warnings = nullptr);

// loadGltf on a file's bytes already in memory (the fuzz targets' entry; loadGltf reads the file
// and calls it): `path` names the file in every message and its stem names a scene that has no
// name; external buffer and image URIs resolve against baseDir (against the working directory
// when empty). Throws as loadGltf.
Scene loadGltfFromMemory(std::span<const uint8_t> bytes, const std::string& path, const std::string& baseDir,
                         GltfLoadWarnings* warnings = nullptr);

// Writes `scene` as glTF 2.0: a .glb if path ends in ".glb" (case-insensitive), else a .gltf with
// its one buffer embedded as a base64 data URI. Every texture is embedded as PNG; every instance,
// camera and light is a root node of the one scene; lights are KHR_lights_punctual (listed in
// extensionsUsed) with their range always written for point/spot, and extras {castShadows,
// rangeFromEq41} so that loading gives back the same hb::Light. Loading the file gives the same
// scene back when its primitives are laid out mesh by mesh in vertex and index order (what
// loadGltf produces); camera views and light directions come back to within a float ulp (they go
// through a matrix inverse and a normalisation). Throws InputError if the file cannot be written
// and HB_ASSERT's logic_error if the scene is inconsistent (an index past its array).
void exportGltf(const Scene& scene, const std::string& path);

// A summary for people: counts (triangles over instances, vertices, meshes, instances, materials,
// textures, cameras), lights by type with their ranges, world bounds and size in metres.
std::string sceneInfoText(const Scene& scene);

// The same summary as JSON: {name, triangles, vertices, indices, meshes, instances, materials,
// textures, cameras, compression (null or the extensions), lights: {total, point, spot, directional, range_min,
// range_max, ranges_from_eq41, list: [{name, type, range, range_from_eq41, intensity, cast_shadows}]}, bounds: {min:
// [x,y,z], max: [x,y,z], size_m: [x,y,z]} or null for a scene with no instances}.
nlohmann::json sceneInfoJson(const Scene& scene);

// SHA-256 (hex) of the scene's content: vertices, indices, meshes' primitives, instances,
// materials, textures (size, sRGB flag, pixels), lights and cameras, in a fixed little-endian
// layout. Names are not hashed: renaming changes nothing that renders. Deterministic across runs.
std::string sceneSha256(const Scene& scene);
// SHA-256 (hex) of what a ray meets: the world-space triangles (Scene::worldTriangles), in draw
// order. Two scenes that differ only in lights, materials, textures or cameras share it.
std::string sceneGeometrySha256(const Scene& scene);

}  // namespace hb
