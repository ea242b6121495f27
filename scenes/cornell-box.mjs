#!/usr/bin/env node
// Writes scenes/cornell-box.gltf: a room after the Cornell box (white floor, ceiling and back
// wall, a red left and a green right wall, the front open), a tall and a short white box turned
// about the vertical, one warm point light under the ceiling and a camera in front of the opening.
// Its scene's extras call for shadows, ambient occlusion and single-bounce indirect light, with a
// sky ambient term that enters through the opening: the room's corners, the floor under and
// between the boxes and the walls facing them are where those effects show.
//
//   node scenes/cornell-box.mjs            (re)writes scenes/cornell-box.gltf
//   node scenes/cornell-box.mjs --check    exit 1 when the committed file differs from what this
//                                          script writes (a test runs this)
//
// Deterministic: no randomness, positions rounded once to float32, the JSON written with a fixed
// key order; the same script gives the same bytes on every machine.
// Units are metres, y is up (glTF). The room's inside is x, z in [-2, 2] and y in [0, 4].
import { readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const out = path.join(path.dirname(fileURLToPath(import.meta.url)), 'cornell-box.gltf');

// Diffuse albedos of the original Cornell box's paints (linear RGB, as in the usual renderings).
const kWhite = [0.73, 0.73, 0.73, 1];
const kRed = [0.63, 0.065, 0.05, 1];
const kGreen = [0.14, 0.45, 0.091, 1];

// A quad: corner p and edges u, v; its normal is u x v normalised (counter-clockwise seen from it).
function quad(p, u, v) {
  const n = normalize(cross(u, v));
  const corners = [p, add(p, u), add(add(p, u), v), add(p, v)];
  return { positions: corners, normals: corners.map(() => n), indices: [0, 1, 2, 0, 2, 3] };
}
function merge(parts) {
  const m = { positions: [], normals: [], indices: [] };
  for (const q of parts) {
    const base = m.positions.length;
    m.positions.push(...q.positions);
    m.normals.push(...q.normals);
    m.indices.push(...q.indices.map((i) => i + base));
  }
  return m;
}
// A closed box of size (sx, sy, sz) standing on y = 0, centred on the vertical axis; normals out.
function box(sx, sy, sz) {
  const [x, z] = [sx / 2, sz / 2];
  return merge([
    quad([-x, 0, z], [sx, 0, 0], [0, sy, 0]),     // front  +z
    quad([x, 0, -z], [-sx, 0, 0], [0, sy, 0]),    // back   -z
    quad([x, 0, z], [0, 0, -sz], [0, sy, 0]),     // right  +x
    quad([-x, 0, -z], [0, 0, sz], [0, sy, 0]),    // left   -x
    quad([-x, sy, z], [sx, 0, 0], [0, 0, -sz]),   // top    +y
    quad([-x, 0, -z], [sx, 0, 0], [0, 0, sz]),    // bottom -y
  ]);
}
const add = (a, b) => a.map((x, i) => x + b[i]);
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalize = (a) => { const l = Math.hypot(...a); return a.map((x) => x / l); };

// Rotation by `deg` about +y as a glTF quaternion [x, y, z, w].
const yaw = (deg) => [0, Math.sin((deg * Math.PI) / 360), 0, Math.cos((deg * Math.PI) / 360)];

// Walls face into the room.
const room = {
  white: merge([
    quad([-2, 0, 2], [4, 0, 0], [0, 0, -4]),    // floor,   normal +y
    quad([-2, 4, -2], [4, 0, 0], [0, 0, 4]),    // ceiling, normal -y
    quad([-2, 0, -2], [4, 0, 0], [0, 4, 0]),    // back,    normal +z
  ]),
  red: quad([-2, 0, 2], [0, 0, -4], [0, 4, 0]),    // left,  normal +x
  green: quad([2, 0, -2], [0, 0, 4], [0, 4, 0]),   // right, normal -x
};

// --- glTF assembly: one buffer, a bufferView per accessor, 4-byte aligned ---------------------
const chunks = [];
let byteLength = 0;
const bufferViews = [], accessors = [];
function view(typedArray, target) {
  const bytes = new Uint8Array(typedArray.buffer, typedArray.byteOffset, typedArray.byteLength);
  bufferViews.push({ buffer: 0, byteOffset: byteLength, byteLength: bytes.length, target });
  chunks.push(bytes);
  byteLength += bytes.length;
  const pad = (4 - (byteLength % 4)) % 4;
  if (pad) { chunks.push(new Uint8Array(pad)); byteLength += pad; }
  return bufferViews.length - 1;
}
function vec3Accessor(vectors, withBounds) {
  const data = Float32Array.from(vectors.flat());
  const accessor = { bufferView: view(data, 34962), componentType: 5126, count: vectors.length, type: 'VEC3' };
  if (withBounds) {  // the spec requires POSITION's min/max: of the float32 values as stored
    accessor.min = [0, 1, 2].map((c) => Math.min(...vectors.map((_, i) => data[3 * i + c])));
    accessor.max = [0, 1, 2].map((c) => Math.max(...vectors.map((_, i) => data[3 * i + c])));
  }
  accessors.push(accessor);
  return accessors.length - 1;
}
function primitive(mesh, material) {
  const position = vec3Accessor(mesh.positions, true);
  const normal = vec3Accessor(mesh.normals, false);
  accessors.push({ bufferView: view(Uint16Array.from(mesh.indices), 34963), componentType: 5123,
                   count: mesh.indices.length, type: 'SCALAR' });
  return { attributes: { POSITION: position, NORMAL: normal }, indices: accessors.length - 1, material, mode: 4 };
}

const material = (name, baseColorFactor) =>
  ({ name, pbrMetallicRoughness: { baseColorFactor, metallicFactor: 0, roughnessFactor: 0.9 } });
const materials = [material('white', kWhite), material('red', kRed), material('green', kGreen)];
const meshes = [
  { name: 'room', primitives: [primitive(room.white, 0), primitive(room.red, 1), primitive(room.green, 2)] },
  { name: 'tall box', primitives: [primitive(box(1.2, 2.4, 1.2), 0)] },
  { name: 'short box', primitives: [primitive(box(1.2, 1.2, 1.2), 0)] },
];
const nodes = [
  { name: 'room', mesh: 0 },
  { name: 'tall box', mesh: 1, translation: [-0.85, 0, -0.75], rotation: yaw(18) },
  { name: 'short box', mesh: 2, translation: [0.85, 0, 0.65], rotation: yaw(-17) },
  // The camera looks down -z into the opening; at 4:3 the opening fills the height of the view.
  { name: 'camera', camera: 0, translation: [0, 2, 7.4] },
  // A warm bulb 0.9 m under the ceiling; range 12 m reaches every corner (at most 4.3 m away).
  { name: 'ceiling light', translation: [0, 3.1, 0], extensions: { KHR_lights_punctual: { light: 0 } } },
];

const buffer = Buffer.concat(chunks);
const gltf = {
  asset: { version: '2.0', generator: 'hybridbench scenes/cornell-box.mjs' },
  extensionsUsed: ['KHR_lights_punctual'],
  extensions: {
    KHR_lights_punctual: {
      lights: [{ name: 'ceiling light', type: 'point', color: [1, 0.85, 0.7], intensity: 10, range: 12 }],
    },
  },
  scene: 0,
  scenes: [{
    name: 'cornell-box',
    nodes: nodes.map((_, i) => i),
    extras: {
      // README "Effects": what this scene calls for (a config or --set can still override it).
      effects: {
        shadows: true,
        ambient_occlusion: { method: 'ldm', directions: 64, ldm_resolution: 128 },
        // 128 split directions: at 64 the photons' splats leave visible swirls on the walls.
        indirect: { method: 'ldm', directions: 128, photons: 16 },
      },
      // A pale sky seen through the opening (scene.h Ambient; lights only through the AO effect).
      ambient: { color: [0.75, 0.85, 1], intensity: 0.35 },
    },
  }],
  nodes,
  cameras: [{ name: 'camera', type: 'perspective', perspective: { yfov: (40 * Math.PI) / 180, znear: 0.1, zfar: 50 } }],
  meshes,
  materials,
  accessors,
  bufferViews,
  buffers: [{ byteLength: buffer.length, uri: `data:application/octet-stream;base64,${buffer.toString('base64')}` }],
};
const text = `${JSON.stringify(gltf, null, 2)}\n`;

if (process.argv.includes('--check')) {
  let committed = '';
  try { committed = readFileSync(out, 'utf8'); } catch { /* missing: differs */ }
  if (committed !== text) {
    console.error(`${out} differs from what scenes/cornell-box.mjs writes; rerun: node scenes/cornell-box.mjs`);
    process.exit(1);
  }
  console.log(`${out} is what scenes/cornell-box.mjs writes`);
} else {
  writeFileSync(out, text);
  console.log(`wrote ${out} (${text.length} bytes)`);
}
