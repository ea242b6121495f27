// A pass declares what it reads and writes (named frame resources, with their formats and sizes),
// the timer entries it records, and how it records its commands; the Renderer builds, checks,
// orders and times the frame from these declarations alone (docs/frame.md "Passes declare").
//
// A FramePart is what one effect, or one part of the base frame (primary visibility, light lists,
// shading), builds: the GPU state it owns and its passes. It publishes what it writes into the
// frame's FrameResources under the declared names; a later part finds its inputs there by name.
#pragma once
#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <typeindex>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include <nlohmann/json.hpp>

#include "gpu/sync.h"

namespace hb {

class Buffer;
class Image;
class GpuTimer;

// What a recording pass may need from the frame.
struct PassFrame {
  bool analysis = false;      // an analysis frame (counters, readback images); never timed in a sweep
  GpuTimer* timer = nullptr;  // for sub-passes (FramePass::subPasses); open: the pass's own interval
  Sync* sync = nullptr;       // the frame's: a pass declares the accesses of its own steps through it
};

// The work of one timed entry (a pass or one of its sub-passes) in the analysis frame, in the units
// of what could bound it (report/roofline.h divides it by the entry's time and the device's peak).
// unit: "bytes" (DRAM traffic), "atomics", "atomics64", "fma" (FMA issue slots), "triangles" and
// "fragments" (the hardware rasterizer), "rays" (the frame's own shadow rays: against raybench),
// "rays_coherent" (camera rays), "rays_random" and "rays_occlusion" (incoherent rays to the
// closest hit, or ended by the first), "rays_ao" (occlusion rays from visible surfaces: gpu/peaks.h
// addRayPeaks; each against the rate of the backend the frame traced with). source says how the amount was found:
// "counted" (a GPU counter of the analysis frame, as the run's record reports it) or "derived: <how>" (from sizes; a
// lower bound unless it says otherwise).
struct WorkItem {
  std::string unit;
  double amount = 0;
  std::string source;
};
struct PassWork {
  std::string entry;  // the timer entry: the pass's name or a sub-pass's ("raster3d.tiles")
  std::vector<WorkItem> items;
};

struct FramePass {
  std::string name;                    // the plan's name of the pass and its timer entry
  std::vector<std::string> reads;      // frame resources it reads (FrameResources names)
  std::vector<std::string> writes;     // frame resources it writes
  std::vector<std::string> subPasses;  // timer entries it records inside its own ("raster3d.tiles")
  // How it touches the buffers and images it reads and writes (docs/frame.md "Barriers"): its
  // shaders run in `stages`, where they read what it reads and read and write what it writes, an
  // image in the layout it is published in; `access` names the exceptions (an attachment, a copy).
  // Before the pass, outside its timed interval, the Renderer records the barriers these need
  // (gpu/sync.h). A resource in `syncedInside` is the pass's to declare: its steps declare their
  // accesses to it through PassFrame::sync as they record. A pass never records a barrier itself.
  VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  std::map<std::string, Access> access;
  std::vector<std::string> syncedInside;
  std::function<void(VkCommandBuffer, const PassFrame&)> record;
  // The work of the pass and of each of its sub-passes, after an analysis frame; `analysis` is the
  // run's record of that frame (render.json's fields: "rays", "primary", "ambient_occlusion", ...),
  // where the counted figures are. Every timed entry has one (tests/peaks_roofline_test.cpp).
  std::function<std::vector<PassWork>(const nlohmann::json& analysis)> work;
};

// A named resource of the frame: who owns it (a part, or the Renderer), its format and size in
// words a reader can check, and the object itself.
struct NamedResource {
  std::string name;
  std::string format;  // "D32_SFLOAT", "RGBA32F", "u32 x 4 per tile", ...
  std::string size;    // "1920 x 1080", "8160 tiles", ...
  uint64_t bytes = 0;
  const Buffer* buffer = nullptr;
  const Image* image = nullptr;
  VkAccelerationStructureKHR tlas = VK_NULL_HANDLE;
  VkSampler sampler = VK_NULL_HANDLE;
  VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL;  // an image's layout for the frame's shaders and readbacks
};

// A resource built from the scene and the settings rather than written by a pass each frame: our
// BVH, the driver's acceleration structures, an LDM set (its objects and node pool; its build pass
// still draws the lists each frame). Built once per frame (per Renderer) for its key, by whoever
// asks first, and shared with every later part that asks for the same key (docs/frame.md "Keyed
// resources"); frame_resources reports it with its key, build time and users.
struct BuiltResource {
  std::string name;     // the frame resource it is published as ("trace_bvh", "tlas", "ambient_occlusion.ldm")
  std::string key;      // everything that decides its content, as text
  std::string builtBy;  // the part or pass that asked first
  uint64_t bytes = 0;
  double buildMs = 0;  // CPU wall clock around the build; GPU work it waits for (uploads, a counting build) included
  std::shared_ptr<void> object;
  std::type_index type = typeid(void);
};

// What an effect adds to shading's light, declared by the effect's part when it is built
// (FrameResources::addShadingTerm) rather than named by shading (docs/frame.md "Shading terms"):
// shading reads the published resource `resource` per pixel and adds to each pixel's colour
//   weight · scale · value,  weight = the diffuse albedo base·(1 − metallic) (DiffuseAlbedo) or 1 (AsIs),
// after the direct light, in the order the terms were declared (shaders/shading_terms.glsl.inc).
struct ShadingTerm {
  enum class Storage : uint32_t {
    FloatPerPixel = 1,  // a buffer of one float per pixel (row-major): value = (v, v, v); none where not v >= 0
    Vec4PerPixel = 2,   // a buffer of one vec4 per pixel: value = rgb; none where not w > 0
    Rgba32fImage = 3,   // an RGBA32F storage image in GENERAL layout: value = rgb; never none
  };
  enum class Weight : uint32_t { DiffuseAlbedo, AsIs };
  std::string resource;
  Storage storage = Storage::FloatPerPixel;
  std::array<float, 3> scale = {1.0f, 1.0f, 1.0f};
  Weight weight = Weight::DiffuseAlbedo;
  // What a pixel without a value counts as, in every channel; 0: nothing is added there.
  float none = 0.0f;
};

class FrameResources {
 public:
  // The resource of `key`: built by make() (a std::unique_ptr<T>) the first time the key is asked
  // for, timed and counted, and reported under `name` as built by `who` (a part or pass); later
  // calls return the same object. bytesOf(const T&): its memory. Its users are the passes that
  // declare reading `name` (the Renderer adds them) and those use() adds.
  template <typename T, typename Make, typename BytesOf>
  T& build(const std::string& name, const std::string& key, const std::string& who, Make&& make, BytesOf&& bytesOf) {
    if (BuiltResource* e = findBuilt(key)) {
      checkType(*e, typeid(T));
      return *static_cast<T*>(e->object.get());
    }
    const auto start = std::chrono::steady_clock::now();
    std::shared_ptr<T> object(make());
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const uint64_t bytes = bytesOf(*object);
    addBuilt({name, key, who, bytes, ms, object, typeid(T)});
    return *object;
  }
  // The keyed resource of `key`, or null when no part asked for it.
  const BuiltResource* built(std::string_view key) const;
  const std::vector<BuiltResource>& builtResources() const { return built_; }
  // Records that `who` (a pass, or raybench) uses the resource `name` (frame_resources "users").
  void use(const std::string& name, const std::string& who);

  // Publishes a resource under `name` (a name is published once: HB_ASSERT).
  void publish(const std::string& name, const Buffer& buffer, std::string format, std::string size);
  void publish(const std::string& name, const Image& image, std::string format,
               VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL);
  // A pass that rewrites a published image into its own (an effect on the shaded colour, say)
  // makes its image the one later passes and readbacks see under `name`. Precondition: `name`
  // is a published image.
  void replace(const std::string& name, const Image& image, VkImageLayout layout);
  void publishTlas(const std::string& name, VkAccelerationStructureKHR tlas, uint64_t bytes);
  void publishSampler(const std::string& name, VkSampler sampler);

  bool has(std::string_view name) const { return find(name) != nullptr; }
  // The resource, or null when no part of this frame publishes it (an optional input).
  const Buffer* buffer(std::string_view name) const;
  const Image* image(std::string_view name) const;
  VkAccelerationStructureKHR tlas(std::string_view name) const;
  VkSampler sampler(std::string_view name) const;
  // The resource; HB_ASSERT that it is published (a required input).
  const Buffer& requireBuffer(std::string_view name) const;
  const Image& requireImage(std::string_view name) const;
  VkImageLayout imageLayout(std::string_view name) const;  // precondition: a published image

  // Declares that shading adds `term` (its resource published already, as a buffer or, for
  // Rgba32fImage, an image: HB_ASSERT). Parts built after shading declare none.
  void addShadingTerm(ShadingTerm term);
  const std::vector<ShadingTerm>& shadingTerms() const { return terms_; }

  // {"depth": {"format": "D32_SFLOAT", "size": "1920 x 1080", "bytes": 8294400, "users": [...]}, ...};
  // a keyed resource adds "key", "built_bytes" (all of it), "build_ms", "build_clock" ("cpu") and
  // "built_by", and is listed even where no pass of the frame reads it (raybench's own BVH).
  nlohmann::json toJson() const;

 private:
  const NamedResource* find(std::string_view name) const;
  BuiltResource* findBuilt(std::string_view key);
  void addBuilt(BuiltResource r);
  static void checkType(const BuiltResource& r, std::type_index type);
  std::vector<NamedResource> resources_;
  std::vector<BuiltResource> built_;
  std::map<std::string, std::vector<std::string>> users_;  // by resource name, in the order they came
  std::vector<ShadingTerm> terms_;
};

// What an effect or a base part builds. Derived classes own the GPU state and fill passes_ in
// frame order with the passes of this frame (those the plan runs).
class FramePart {
 public:
  virtual ~FramePart() = default;
  const std::vector<FramePass>& passes() const { return passes_; }
  // Passes of the plan this part did not build, with the reason: an LDM build whose set an earlier
  // part's pass builds (the same key). The Renderer lists them as skipped.
  const std::vector<std::pair<std::string, std::string>>& skipped() const { return skipped_; }
  // Work recorded once, before the first frame's timed passes (the tile frustums, say), declaring
  // its accesses through `sync` (the frame's).
  virtual void recordOnce(VkCommandBuffer /*cmd*/, Sync& /*sync*/) const {}
  // After each frame (its submission waited on): what the part adapts to what the frame found (a
  // work list that was too small grows); true when the frame must be rendered again for its work
  // and counts to be what they will be on every later frame.
  virtual bool afterFrame() { return false; }

 protected:
  std::vector<FramePass> passes_;
  std::vector<std::pair<std::string, std::string>> skipped_;
};

}  // namespace hb
