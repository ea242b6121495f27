// The compute photon splat of IndirectPass (effects.indirect.splat=compute): its buffers, constants
// and pipelines. Internal to src/effects/indirect: indirect_pass.cpp sets up the pass,
// indirect_splat.cpp the splat's part of it (its set-up, recording, statistics and test hooks).
#pragma once
#include <memory>
#include <vector>

#include "effects/indirect/indirect_pass.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "shared/gpu_types.h"

namespace hb {

// splat=compute (photon_splat_bin.comp.glsl, photon_splat.comp.glsl): per slot its pixel box and
// coarse box, per (bin, chunk) a count and then its start, per bin its list's range, and the list.
// With later_bounce_stride f > 1 the boxes step covers every slot (`all`), the later bounces' slots
// are binned and gathered at stride f into the target's `late` image (`late`), then the first
// bounce's (`constants`), whose gather adds `late` interpolated.
struct IndirectPass::ComputeSplat {
  gpu::SplatConstants constants{}, all{}, late{};
  bool hasLate = false;
  uint32_t stride = 1;  // the later run's (later_bounce_stride)
  uint32_t parts = 1;   // the later run's gather: workgroups a tile (photon_splat.comp.glsl PARTS)
  Buffer boxes, coarse, counts, bins, list;
  Buffer work;  // analysis frames: each gather tile's (tests, terms), the later run's tiles first
  std::vector<std::unique_ptr<Pipeline>> bin;  // MODE 0..5
  // The gathers: [run][COUNT], run 0 the first bounce's (or every bounce's), 1 the later bounces';
  // COUNT 0 in timed frames, 1 in analysis frames.
  std::unique_ptr<Pipeline> gather[2][2];
  explicit ComputeSplat(const VulkanContext&) {}
  uint64_t bytes() const {
    return boxes.size() + coarse.size() + counts.size() + bins.size() + list.size() + work.size();
  }
};

}  // namespace hb
