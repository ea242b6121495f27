// Transcodes an OFF mesh (as OpenSCAD exports one) into a binary glTF 2.0 file, vertex for vertex
// and triangle for triangle: the positions as written (millimetres, scaled to metres), the shared
// vertices kept shared through the index buffer, nothing added (no normals, no material, no
// camera: what a CAD export looks like; hybridbench's automatic camera and lights frame it).
// Usage: node scenes/external/off-to-glb.mjs IN.off OUT.glb
import { readFileSync, writeFileSync } from "node:fs";

const [input, output] = process.argv.slice(2);
if (!input || !output) {
  console.error("usage: node off-to-glb.mjs IN.off OUT.glb");
  process.exit(2);
}
const words = readFileSync(input, "utf8")
  .split("\n")
  .map((line) => line.replace(/#.*/, "").trim())
  .filter((line) => line.length > 0)
  .join(" ")
  .split(/\s+/);
if (words[0] !== "OFF") throw new Error(`${input}: not an OFF file (first word "${words[0]}")`);
const vertexCount = Number(words[1]),
  faceCount = Number(words[2]);
let at = 4;
const positions = new Float32Array(3 * vertexCount);
for (let i = 0; i < 3 * vertexCount; ++i) positions[i] = Number(words[at++]) * 0.001;
const indices = [];
for (let f = 0; f < faceCount; ++f) {
  const n = Number(words[at++]);
  const face = [];
  for (let k = 0; k < n; ++k) face.push(Number(words[at++]));
  for (let k = 1; k + 1 < n; ++k) indices.push(face[0], face[k], face[k + 1]);  // a fan (OpenSCAD writes triangles)
}
for (const i of indices) if (!(i >= 0 && i < vertexCount)) throw new Error(`${input}: index ${i} out of range`);

const min = [Infinity, Infinity, Infinity],
  max = [-Infinity, -Infinity, -Infinity];
for (let i = 0; i < vertexCount; ++i)
  for (let c = 0; c < 3; ++c) {
    min[c] = Math.min(min[c], positions[3 * i + c]);
    max[c] = Math.max(max[c], positions[3 * i + c]);
  }
const wide = vertexCount > 65535;
const indexArray = wide ? new Uint32Array(indices) : new Uint16Array(indices);
const pad4 = (n) => (n + 3) & ~3;
const positionBytes = positions.byteLength,
  indexBytes = indexArray.byteLength;
const bin = Buffer.alloc(pad4(positionBytes) + pad4(indexBytes));
Buffer.from(positions.buffer).copy(bin, 0);
Buffer.from(indexArray.buffer).copy(bin, pad4(positionBytes));

const name = output.replace(/^.*\//, "").replace(/\.glb$/, "");
const doc = {
  asset: { version: "2.0", generator: "OpenSCAD OFF export, transcoded by scenes/external/off-to-glb.mjs" },
  scene: 0,
  scenes: [{ nodes: [0] }],
  nodes: [{ mesh: 0, name }],
  meshes: [{ name, primitives: [{ attributes: { POSITION: 0 }, indices: 1 }] }],
  buffers: [{ byteLength: bin.length }],
  bufferViews: [
    { buffer: 0, byteOffset: 0, byteLength: positionBytes, target: 34962 },
    { buffer: 0, byteOffset: pad4(positionBytes), byteLength: indexBytes, target: 34963 },
  ],
  accessors: [
    { bufferView: 0, componentType: 5126, count: vertexCount, type: "VEC3", min, max },
    { bufferView: 1, componentType: wide ? 5125 : 5123, count: indices.length, type: "SCALAR" },
  ],
};
let json = Buffer.from(JSON.stringify(doc), "utf8");
json = Buffer.concat([json, Buffer.alloc(pad4(json.length) - json.length, 0x20)]);
const header = Buffer.alloc(12);
header.writeUInt32LE(0x46546c67, 0);
header.writeUInt32LE(2, 4);
header.writeUInt32LE(12 + 8 + json.length + 8 + bin.length, 8);
const chunk = (type, data) => {
  const h = Buffer.alloc(8);
  h.writeUInt32LE(data.length, 0);
  h.writeUInt32LE(type, 4);
  return Buffer.concat([h, data]);
};
writeFileSync(output, Buffer.concat([header, chunk(0x4e4f534a, json), chunk(0x004e4942, bin)]));
// What the README's table gives: each triangle's longest edge over its altitude to it (how thin it
// is), and how many triangles share a vertex at most.
const aspects = [],
  valence = new Uint32Array(vertexCount);
const at3 = (i) => [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const len = (v) => Math.hypot(v[0], v[1], v[2]);
for (let t = 0; t < indices.length; t += 3) {
  const [a, b, c] = [at3(indices[t]), at3(indices[t + 1]), at3(indices[t + 2])];
  for (let k = 0; k < 3; ++k) valence[indices[t + k]]++;
  const ab = sub(b, a),
    ac = sub(c, a);
  const area2 = len([ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]]);
  const longest = Math.max(len(ab), len(ac), len(sub(c, b)));
  aspects.push(area2 > 0 ? (longest * longest) / area2 : Infinity);
}
aspects.sort((x, y) => x - y);
const pick = (q) => aspects[Math.min(aspects.length - 1, Math.floor(q * aspects.length))];
console.log(
  `${output}: ${vertexCount} vertices, ${indices.length / 3} triangles; longest edge over its altitude: ` +
    `median ${pick(0.5).toPrecision(3)}, p90 ${pick(0.9).toPrecision(3)}, max ${aspects[aspects.length - 1].toPrecision(3)}; ` +
    `a vertex shared by up to ${Math.max(...valence)} triangles`,
);
