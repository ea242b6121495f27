// The descriptor bindings a shader reads, read back from its SPIR-V: a binding is written once, in
// the shader, by name. The GLSL declares no binding numbers; glslangValidator --auto-map-bindings
// numbers the resources each shader uses in declaration order, and a pipeline's stages are merged
// by name into one set (ShaderProgram), renumbered where the stages disagree.
//
// The reflection is SPIRV-Cross's C API (Debian's libspirv-cross-c-shared-dev), not glslang's:
// it reads the SPIR-V the build already embeds, so the reflection is of exactly the words the
// device gets (and of a test's registerSpirv shaders alike), with no GLSL compiled at start-up;
// it also gives the word offset of each Binding decoration, which renumbering needs.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

namespace hb {

struct ShaderBinding {
  // The GLSL name: the variable's (`depthTex`, `tlas`), or for a block without an instance name the
  // block's (`Lights` in `readonly buffer Lights { GpuLight lights[]; };`).
  std::string name;
  uint32_t set = 0;
  uint32_t binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
  uint32_t count = 1;  // array elements; 0: a runtime-sized array (bindless textures)
  VkShaderStageFlags stages = 0;
};

// The bindings `shader` statically uses (reachable from its entry point; a declared but unused
// resource is no binding), in binding order. `spirv` is its SPIR-V; throws std::logic_error naming
// the shader if it cannot be read or uses a descriptor kind the passes do not (texel buffers,
// input attachments).
std::vector<ShaderBinding> reflectBindings(const std::string& shader, const std::vector<uint32_t>& spirv);

// The shaders of one pipeline and the one descriptor set (set 0) they read, merged by name: a
// name read by several stages is one binding, its stage flags OR-ed. Bindings are numbered 0..n-1
// in the order of the first stage that reads them, a runtime-sized array last (Vulkan's variable
// descriptor count must be the set's last binding); the SPIR-V of a stage whose numbers differ is
// rewritten to these. Throws std::logic_error naming the shaders and the binding when a name has two
// types or array sizes, or a shader reads a set other than 0.
class ShaderProgram {
 public:
  explicit ShaderProgram(std::vector<std::string> shaders);
  const std::vector<std::string>& shaders() const { return shaders_; }
  std::string label() const;  // "shading.vert + shading.frag", for messages
  const std::vector<ShaderBinding>& bindings() const { return bindings_; }
  const ShaderBinding* find(std::string_view name) const;  // null: no shader reads it
  // The SPIR-V of shaders()[i], or of the shader named `shader` (one of shaders()), with this
  // program's binding numbers.
  const std::vector<uint32_t>& spirv(size_t i) const { return spirv_[i]; }
  const std::vector<uint32_t>& spirv(std::string_view shader) const;

 private:
  std::vector<std::string> shaders_;
  std::vector<std::vector<uint32_t>> spirv_;
  std::vector<ShaderBinding> bindings_;
};

}  // namespace hb
