#include "gpu/trace_work.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <utility>

#include "base/parallel.h"

namespace hb {

namespace {

constexpr float kFarWiden = 1.0000004f;       // + 3 ulps (Ize 2013), as the shader
constexpr float kFarWidenFused = 1.0000006f;  // + 5 ulps: the fused form's (any-hit rays)
constexpr uint64_t kTriangleBytes = 48;       // 3 vec4

struct Ray {
  glm::vec3 o, d, inv;
  // The shader's SlabRay: `fused` (any-hit rays) o · inv widened by 2^-22 |o · inv| toward each plane's
  // side, for t = fma(p, inv, −slab); else o, for t = (p − o) · inv (closest hits).
  glm::vec3 slabLo, slabHi;
  bool fused;
  float tMin, tMax;
};

// shaders/compute_occluded.glsl.inc watertight() and inRange(), in float.
bool hitTriangle(const TraceBvhLayout& l, const Ray& r, uint32_t tri, float tMin, float tMax, float& t) {
  const glm::vec3 ad = glm::abs(r.d);
  int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
  if (r.d[kz] < 0.0f) std::swap(kx, ky);
  const float sx = r.d[kx] / r.d[kz], sy = r.d[ky] / r.d[kz], sz = 1.0f / r.d[kz];
  const glm::vec3 a = glm::vec3(l.triangles[3 * tri]) - r.o, b = glm::vec3(l.triangles[3 * tri + 1]) - r.o,
                  c = glm::vec3(l.triangles[3 * tri + 2]) - r.o;
  const float ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
  const float bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
  const float cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
  float u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
  if (u == 0.0f || v == 0.0f || w == 0.0f) {
    u = float(double(cx) * by - double(cy) * bx);
    v = float(double(ax) * cy - double(ay) * cx);
    w = float(double(bx) * ay - double(by) * ax);
  }
  if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
  const float det = u + v + w;
  if (det == 0.0f) return false;
  const float T = u * (sz * a[kz]) + v * (sz * b[kz]) + w * (sz * c[kz]);
  const bool in = det > 0.0f ? (T >= tMin * det && T <= tMax * det) : (T <= tMin * det && T >= tMax * det);
  t = T / det;
  return in;
}

bool hitBox(const glm::vec3& lo, const glm::vec3& hi, const Ray& r, float tMin, float tMax, float& entry) {
  glm::vec3 t0, t1;
  for (int a = 0; a < 3; ++a) {  // as the shader's slabT
    t0[a] = r.fused ? std::fma(lo[a], r.inv[a], -r.slabLo[a]) : (lo[a] - r.slabLo[a]) * r.inv[a];
    t1[a] = r.fused ? std::fma(hi[a], r.inv[a], -r.slabHi[a]) : (hi[a] - r.slabHi[a]) * r.inv[a];
  }
  const glm::vec3 tn = glm::min(t0, t1), tf = glm::max(t0, t1);
  entry = std::max(std::max(tn.x, tn.y), std::max(tn.z, tMin));
  const float far = std::min(std::min(tf.x, tf.y), std::min(tf.z, tMax)) * (r.fused ? kFarWidenFused : kFarWiden);
  return !(entry > far);
}

struct Counter {
  TraceWork w;
  std::vector<uint32_t>* events = nullptr;  // the current ray's fetches, where recorded
  std::vector<std::pair<uint32_t, float>> stack;
  bool found = false;  // the ray has a hit
  void push(uint32_t code, float entry) {
    stack.emplace_back(code, entry);
    ++w.pushes;
    w.maxStack = std::max<uint64_t>(w.maxStack, stack.size());
  }
  // A leaf's triangles [first, first + count), the interval shrinking to each hit; true when an
  // any-hit ray is done.
  bool leaf(const TraceBvhLayout& l, const Ray& r, uint32_t first, uint32_t count, bool anyHit, float& best) {
    for (uint32_t i = first; i < first + count; ++i) {
      ++w.triangles;
      w.triangleBytes += kTriangleBytes;
      if (events) events->push_back(kWideLeaf | i);
      float t;
      if (!hitTriangle(l, r, i, r.tMin, best, t)) continue;
      found = true;
      if (anyHit) return true;
      best = std::max(r.tMin, std::min(best, t));
    }
    return false;
  }
  // The next entry to visit, skipping those that start beyond the nearest hit; false when none is left.
  bool pop(bool anyHit, float best, uint32_t& code) {
    while (!stack.empty()) {
      const auto [popped, entry] = stack.back();
      stack.pop_back();
      if (!anyHit && found && entry > best * kFarWiden) continue;
      code = popped;
      return true;
    }
    return false;
  }
};

// One ray through the wide tree (width 4 or 8), as the shader's occluded() / closestHitBvh().
void wideRay(const TraceBvhLayout& l, const Ray& r, bool anyHit, Counter& c) {
  float best = r.tMax;
  uint32_t code = 0;
  c.stack.clear();
  c.found = false;
  for (;;) {
    bool descended = false;
    if ((code & kWideLeaf) == 0) {
      ++c.w.nodes;
      c.w.nodeBytes += 16 * wideNodeVec4s(l.width);
      if (c.events) c.events->push_back(code);
      uint32_t next = kWideEmpty;
      float nextEntry = 0.0f;
      const size_t base = c.stack.size();  // this node's pushes
      for (uint32_t k = 0; k < l.width; ++k) {
        const WideChild child = wideChild(l.wide, l.width, code, k);
        if (child.code == kWideEmpty) continue;
        ++c.w.boxes;
        float entry;
        if (!hitBox(child.lo, child.hi, r, r.tMin, best, entry)) continue;
        if (next == kWideEmpty) {
          next = child.code;
          nextEntry = entry;
        } else if (entry < nextEntry) {
          c.push(next, nextEntry);
          next = child.code;
          nextEntry = entry;
        } else {
          c.push(child.code, entry);
        }
      }
      // Closest hits: the pushed children sorted far to near by insertion, as the shader (an entry
      // moves below a nearer one only; equal entries keep their order).
      if (!anyHit)
        for (size_t i = base + 1; i < c.stack.size(); ++i) {
          const auto item = c.stack[i];
          size_t j = i;
          for (; j > base && c.stack[j - 1].second < item.second; --j) c.stack[j] = c.stack[j - 1];
          c.stack[j] = item;
        }
      if (next != kWideEmpty) {
        code = next;
        descended = true;
      }
    } else if (c.leaf(l, r, code & 0x0FFFFFFFu, ((code >> 28) & 7u) + 1u, anyHit, best)) {
      return;
    }
    if (!descended && !c.pop(anyHit, best, code)) return;
  }
}

// One ray through the binary tree (width 2).
void binaryRay(const TraceBvhLayout& l, const Ray& r, bool anyHit, Counter& c) {
  float best = r.tMax, entry;
  c.stack.clear();
  c.found = false;
  const auto& n = l.nodes;
  if (n.empty() || !hitBox(glm::vec3(n[0].lo), glm::vec3(n[0].hi), r, r.tMin, best, entry)) return;
  uint32_t node = 0;
  c.w.nodeBytes += sizeof(gpu::PrimaryBvhNode);
  for (;;) {
    bool descended = false;
    if (n[node].info.x != 0) {
      const uint32_t lc = node + 1, rc = n[node].info.x;
      ++c.w.nodes;
      c.w.boxes += 2;
      c.w.nodeBytes += 2 * sizeof(gpu::PrimaryBvhNode);
      float el, er;
      const bool hl = hitBox(glm::vec3(n[lc].lo), glm::vec3(n[lc].hi), r, r.tMin, best, el);
      const bool hr = hitBox(glm::vec3(n[rc].lo), glm::vec3(n[rc].hi), r, r.tMin, best, er);
      if (hl && hr) {
        const bool leftFirst = !(er < el);
        c.push(leftFirst ? rc : lc, leftFirst ? er : el);
        node = leftFirst ? lc : rc;
        descended = true;
      } else if (hl || hr) {
        node = hl ? lc : rc;
        descended = true;
      }
    } else if (c.leaf(l, r, n[node].info.y, n[node].info.z, anyHit, best)) {
      return;
    }
    if (descended) continue;
    if (!c.pop(anyHit, best, node)) return;
    c.w.nodeBytes += 16;  // the popped node's links again (the shader reloads info)
  }
}

}  // namespace

TraceWork traceWork(const TraceBvhLayout& layout, const std::vector<RayRecord>& rays, bool anyHit,
                    std::vector<std::vector<uint32_t>>* events, std::vector<uint8_t>* missed) {
  constexpr size_t kChunk = 4096;
  if (events) events->assign(rays.size(), {});
  if (missed) missed->assign(rays.size(), 0);
  const size_t chunks = (rays.size() + kChunk - 1) / kChunk;
  TraceWork total;
  std::mutex m;
  parallelFor(chunks, [&](size_t k) {
    Counter c;
    for (size_t i = k * kChunk; i < std::min(rays.size(), (k + 1) * kChunk); ++i) {
      const RayRecord& rr = rays[i];
      Ray r;
      r.o = glm::vec3(rr.origin[0], rr.origin[1], rr.origin[2]);
      r.d = glm::vec3(rr.dir[0], rr.dir[1], rr.dir[2]);
      for (int a = 0; a < 3; ++a) {
        // safeInverse: a component below 1e-30 in magnitude becomes ±1e-30 (a zero one +1e-30)
        const float d0 = std::fabs(r.d[a]) < 1e-30f ? (r.d[a] < 0.0f ? -1e-30f : 1e-30f) : r.d[a];
        r.inv[a] = 1.0f / d0;
        // slabRay: lo is the near plane where inv > 0
        const float q = r.o[a] * r.inv[a], d = std::fabs(q) * (1.0f / 4194304.0f), s = r.inv[a] > 0.0f ? 1.0f : -1.0f;
        r.slabLo[a] = anyHit ? q + s * d : r.o[a];
        r.slabHi[a] = anyHit ? q - s * d : r.o[a];
      }
      r.fused = anyHit;
      r.tMin = rr.tMin;
      r.tMax = rr.tMax;
      ++c.w.rays;
      c.events = events && layout.width != 2 ? &(*events)[i] : nullptr;
      if (layout.width == 2)
        binaryRay(layout, r, anyHit, c);
      else
        wideRay(layout, r, anyHit, c);
      if (missed) (*missed)[i] = c.found ? 0 : 1;
    }
    std::lock_guard<std::mutex> lock(m);
    total.rays += c.w.rays;
    total.nodes += c.w.nodes;
    total.boxes += c.w.boxes;
    total.triangles += c.w.triangles;
    total.pushes += c.w.pushes;
    total.maxStack = std::max(total.maxStack, c.w.maxStack);
    total.nodeBytes += c.w.nodeBytes;
    total.triangleBytes += c.w.triangleBytes;
  });
  return total;
}

}  // namespace hb
