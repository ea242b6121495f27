// The settings both layered-depth-map effects share (ambient occlusion, indirect light), as the
// frame and the shaders take them: how the maps are rasterized and how their per-pixel lists are
// built. LdmList's values are the shaders' kLdmList* (gpu_types.h).
#pragma once
#include <cstdint>

#include "shared/gpu_types.h"

namespace hb {

enum class LdmBuildMethod : uint32_t { Hardware, Raster3d };  // "hardware" | "3dr"
// "max64" (64-bit atomicMax insertion) | "cas" (the paper's compare-and-swap) | "sbuffer"
// (count, scan, fill, sort): ldm_insert.glsl.inc, ldm_sbuffer.comp.glsl.
enum class LdmList : uint32_t { Max64 = gpu::kLdmListMax64, Cas = gpu::kLdmListCas, Sbuffer = gpu::kLdmListSbuffer };

inline const char* toString(LdmBuildMethod m) { return m == LdmBuildMethod::Hardware ? "hardware" : "3dr"; }
inline const char* toString(LdmList l) { return l == LdmList::Max64 ? "max64" : l == LdmList::Cas ? "cas" : "sbuffer"; }

}  // namespace hb
