#!/usr/bin/env node
// Writes scenes/environments/sky.hdr: a small equirectangular sky (128 x 64, Radiance RGBE,
// uncompressed scanlines) for the environment light (scene.h Environment): above the horizon a
// gradient from a pale horizon to a deeper blue zenith and a soft sun (a Gaussian lobe of 12°
// at elevation 35°, azimuth 60° from -z towards +x) about six times the sky; below, a uniform
// brownish ground. Soft on purpose: the converged reference (1024 cosine-weighted rays a pixel)
// must converge on it; a sharp sun is a case for importance sampling, which the reference lacks.
//
//   node scenes/environments/sky.mjs           (re)writes sky.hdr
//   node scenes/environments/sky.mjs --check   exit 1 when the committed file differs (a test runs this)
//
// Deterministic: the same bytes on every machine. Layout (scene.h Environment): row 0 looks up
// +y; column u is at azimuth phi = 2*pi*(u + 0.5)/width - pi from -z towards +x, so the direction of
// texel (u, v) is (sin(phi) sin(theta), cos(theta), -cos(phi) sin(theta)), theta = pi*(v + 0.5)/height.
import { readFileSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const out = path.join(path.dirname(fileURLToPath(import.meta.url)), 'sky.hdr');
const W = 128, H = 64;
const deg = Math.PI / 180;
const sunElevation = 35 * deg, sunAzimuth = 60 * deg, sunSigma = 12 * deg, sunPeak = [6.0, 5.4, 4.4];
const sun = [Math.sin(sunAzimuth) * Math.cos(sunElevation), Math.sin(sunElevation),
             -Math.cos(sunAzimuth) * Math.cos(sunElevation)];
const horizon = [1.0, 1.05, 1.15], zenith = [0.25, 0.42, 0.85], ground = [0.32, 0.27, 0.21];

function radiance(d) {
  if (d[1] < 0) return ground;
  const t = Math.pow(d[1], 0.6);  // elevation's weight: the horizon band is wide
  const sky = horizon.map((h, i) => h * (1 - t) + zenith[i] * t);
  const cosAngle = Math.min(1, d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2]);
  const a = Math.acos(cosAngle);
  const lobe = Math.exp(-0.5 * (a / sunSigma) * (a / sunSigma));
  return sky.map((s, i) => s + sunPeak[i] * lobe);
}

// Radiance's RGBE: a shared exponent e with mantissas m = floor(c·256/2^e) (Ward, Graphics Gems II).
function rgbe([r, g, b]) {
  const v = Math.max(r, g, b);
  if (v < 1e-32) return [0, 0, 0, 0];
  const e = Math.ceil(Math.log2(v) + 1e-12);
  const f = 256 / Math.pow(2, e);
  return [Math.min(255, Math.floor(r * f)), Math.min(255, Math.floor(g * f)), Math.min(255, Math.floor(b * f)), e + 128];
}

const header = Buffer.from(`#?RADIANCE\n# scenes/environments/sky.mjs\nFORMAT=32-bit_rle_rgbe\n\n-Y ${H} +X ${W}\n`, 'latin1');
const pixels = Buffer.alloc(W * H * 4);
for (let v = 0; v < H; ++v) {
  const theta = Math.PI * (v + 0.5) / H;
  for (let u = 0; u < W; ++u) {
    const phi = 2 * Math.PI * (u + 0.5) / W - Math.PI;
    const d = [Math.sin(phi) * Math.sin(theta), Math.cos(theta), -Math.cos(phi) * Math.sin(theta)];
    const p = rgbe(radiance(d));
    pixels.set(p, 4 * (v * W + u));
  }
  // A flat scanline must not start like a run-length one (2, 2, hi, lo), or readers take it as one.
  const first = pixels.subarray(4 * v * W, 4 * v * W + 2);
  if (first[0] === 2 && first[1] === 2) throw new Error(`row ${v} starts like an RLE scanline`);
}
const bytes = Buffer.concat([header, pixels]);
if (process.argv.includes('--check')) {
  let committed;
  try { committed = readFileSync(out); } catch { committed = Buffer.alloc(0); }
  if (!committed.equals(bytes)) {
    console.error(`${out} differs from what scenes/environments/sky.mjs writes; run: node scenes/environments/sky.mjs`);
    process.exit(1);
  }
} else {
  writeFileSync(out, bytes);
}
