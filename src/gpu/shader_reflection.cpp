#include "gpu/shader_reflection.h"

#include <spirv_cross_c.h>

#include <algorithm>
#include <memory>
#include <stdexcept>

#include "gpu/vk_pipeline.h"

namespace hb {

namespace {

// A reflected binding and where its Binding decoration's number sits in the SPIR-V.
struct Reflected {
  ShaderBinding binding;
  uint32_t bindingWord = 0;
};

VkShaderStageFlags stageOf(SpvExecutionModel model, const std::string& shader) {
  switch (model) {
    case SpvExecutionModelVertex: return VK_SHADER_STAGE_VERTEX_BIT;
    case SpvExecutionModelFragment: return VK_SHADER_STAGE_FRAGMENT_BIT;
    case SpvExecutionModelGLCompute: return VK_SHADER_STAGE_COMPUTE_BIT;
    case SpvExecutionModelRayGenerationKHR: return VK_SHADER_STAGE_RAYGEN_BIT_KHR;
    case SpvExecutionModelMissKHR: return VK_SHADER_STAGE_MISS_BIT_KHR;
    case SpvExecutionModelClosestHitKHR: return VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR;
    case SpvExecutionModelAnyHitKHR: return VK_SHADER_STAGE_ANY_HIT_BIT_KHR;
    default: throw std::logic_error("shader " + shader + ": a stage the passes do not use");
  }
}

std::vector<Reflected> reflect(const std::string& shader, const std::vector<uint32_t>& spirv) {
  spvc_context context = nullptr;
  if (spvc_context_create(&context) != SPVC_SUCCESS) throw std::logic_error("SPIRV-Cross: no context");
  std::unique_ptr<spvc_context_s, void (*)(spvc_context)> owner(context, spvc_context_destroy);
  auto check = [&](spvc_result r) {
    if (r != SPVC_SUCCESS)
      throw std::logic_error("shader " + shader + ": SPIRV-Cross: " + spvc_context_get_last_error_string(context));
  };
  spvc_parsed_ir ir = nullptr;
  check(spvc_context_parse_spirv(context, spirv.data(), spirv.size(), &ir));
  spvc_compiler compiler = nullptr;  // no backend: reflection only
  check(spvc_context_create_compiler(context, SPVC_BACKEND_NONE, ir, SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &compiler));
  spvc_set active = nullptr;  // the variables the entry point reaches: a resource declared, unused, is no binding
  check(spvc_compiler_get_active_interface_variables(compiler, &active));
  spvc_resources resources = nullptr;
  check(spvc_compiler_create_shader_resources_for_active_variables(compiler, &resources, active));
  const VkShaderStageFlags stage = stageOf(spvc_compiler_get_execution_model(compiler), shader);

  struct Kind {
    spvc_resource_type resource;
    VkDescriptorType descriptor;
  };
  const Kind kinds[] = {
      {SPVC_RESOURCE_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
      {SPVC_RESOURCE_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
      {SPVC_RESOURCE_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE},
      {SPVC_RESOURCE_TYPE_SAMPLED_IMAGE, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER},
      {SPVC_RESOURCE_TYPE_SEPARATE_IMAGE, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE},
      {SPVC_RESOURCE_TYPE_SEPARATE_SAMPLERS, VK_DESCRIPTOR_TYPE_SAMPLER},
      {SPVC_RESOURCE_TYPE_ACCELERATION_STRUCTURE, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR},
      {SPVC_RESOURCE_TYPE_SUBPASS_INPUT, VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT},
  };
  std::vector<Reflected> out;
  for (const Kind& kind : kinds) {
    const spvc_reflected_resource* list = nullptr;
    size_t count = 0;
    check(spvc_resources_get_resource_list_for_type(resources, kind.resource, &list, &count));
    for (size_t i = 0; i < count; ++i) {
      const spvc_reflected_resource& r = list[i];
      Reflected b;
      b.binding.name = spvc_compiler_get_name(compiler, r.id);
      if (b.binding.name.empty()) b.binding.name = spvc_compiler_get_name(compiler, r.base_type_id);
      b.binding.set = spvc_compiler_get_decoration(compiler, r.id, SpvDecorationDescriptorSet);
      b.binding.binding = spvc_compiler_get_decoration(compiler, r.id, SpvDecorationBinding);
      b.binding.type = kind.descriptor;
      b.binding.stages = stage;
      spvc_type type = spvc_compiler_get_type_handle(compiler, r.type_id);
      const bool texelBuffer =
          (kind.resource == SPVC_RESOURCE_TYPE_STORAGE_IMAGE || kind.resource == SPVC_RESOURCE_TYPE_SAMPLED_IMAGE) &&
          spvc_type_get_image_dimension(type) == SpvDimBuffer;
      if (texelBuffer || kind.descriptor == VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT)
        throw std::logic_error("shader " + shader + ": binding " + b.binding.name +
                               " is a texel buffer or input attachment, which no pass binds");
      const unsigned dims = spvc_type_get_num_array_dimensions(type);
      if (dims > 1 || (dims == 1 && !spvc_type_array_dimension_is_literal(type, 0)))
        throw std::logic_error("shader " + shader + ": binding " + b.binding.name +
                               " is an array of arrays or sized by a specialization constant");
      b.binding.count = dims == 1 ? spvc_type_get_array_dimension(type, 0) : 1u;  // 0: runtime-sized
      unsigned word = 0;
      if (!spvc_compiler_get_binary_offset_for_decoration(compiler, r.id, SpvDecorationBinding, &word))
        throw std::logic_error("shader " + shader + ": binding " + b.binding.name +
                               " has no binding number (compile with glslangValidator --auto-map-bindings)");
      b.bindingWord = word;
      out.push_back(std::move(b));
    }
  }
  std::sort(out.begin(), out.end(), [](const Reflected& a, const Reflected& b) {
    return std::pair(a.binding.set, a.binding.binding) < std::pair(b.binding.set, b.binding.binding);
  });
  return out;
}

const char* typeName(VkDescriptorType t) {
  switch (t) {
    case VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER: return "a uniform buffer";
    case VK_DESCRIPTOR_TYPE_STORAGE_BUFFER: return "a storage buffer";
    case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE: return "a storage image";
    case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER: return "a sampler";
    case VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE: return "a texture";
    case VK_DESCRIPTOR_TYPE_SAMPLER: return "a separate sampler";
    case VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR: return "an acceleration structure";
    default: return "another descriptor";
  }
}

}  // namespace

std::vector<ShaderBinding> reflectBindings(const std::string& shader, const std::vector<uint32_t>& spirv) {
  std::vector<ShaderBinding> out;
  for (Reflected& r : reflect(shader, spirv)) out.push_back(std::move(r.binding));
  return out;
}

ShaderProgram::ShaderProgram(std::vector<std::string> shaders) : shaders_(std::move(shaders)) {
  std::vector<std::vector<Reflected>> reflected;
  std::vector<std::string> firstReader;  // per merged binding, the shader that read it first
  for (const std::string& shader : shaders_) {
    spirv_.push_back(embeddedSpirv(shader));
    reflected.push_back(reflect(shader, spirv_.back()));
    for (const Reflected& r : reflected.back()) {
      const ShaderBinding& b = r.binding;
      if (b.set != 0)
        throw std::logic_error("shader " + shader + ": binding " + b.name + " is in set " + std::to_string(b.set) +
                               "; a pass's shaders read one set, set 0 (declare no set)");
      auto same =
          std::find_if(bindings_.begin(), bindings_.end(), [&](const ShaderBinding& m) { return m.name == b.name; });
      if (same == bindings_.end()) {
        bindings_.push_back(b);
        firstReader.push_back(shader);
        continue;
      }
      const std::string& other = firstReader[size_t(same - bindings_.begin())];
      if (same->type != b.type || same->count != b.count)
        throw std::logic_error("shaders " + other + " and " + shader + " declare binding " + b.name + " as " +
                               typeName(same->type) + (same->count == 1 ? "" : " array") + " and as " +
                               typeName(b.type) + (b.count == 1 ? "" : " array"));
      same->stages |= b.stages;
    }
  }
  // A runtime-sized array last: only the last binding of a set may have a variable count.
  std::stable_partition(bindings_.begin(), bindings_.end(), [](const ShaderBinding& b) { return b.count != 0; });
  if (std::count_if(bindings_.begin(), bindings_.end(), [](const ShaderBinding& b) { return b.count == 0; }) > 1)
    throw std::logic_error("shaders " + label() + " read more than one runtime-sized array; a set holds one, last");
  for (uint32_t i = 0; i < bindings_.size(); ++i) bindings_[i].binding = i;
  for (size_t s = 0; s < shaders_.size(); ++s)
    for (const Reflected& r : reflected[s]) spirv_[s][r.bindingWord] = find(r.binding.name)->binding;
}

std::string ShaderProgram::label() const {
  std::string s;
  for (const std::string& shader : shaders_) s += (s.empty() ? "" : " + ") + shader;
  return s;
}

const std::vector<uint32_t>& ShaderProgram::spirv(std::string_view shader) const {
  auto it = std::find(shaders_.begin(), shaders_.end(), shader);
  if (it == shaders_.end()) throw std::logic_error("shader " + std::string(shader) + " is not one of " + label());
  return spirv_[size_t(it - shaders_.begin())];
}

const ShaderBinding* ShaderProgram::find(std::string_view name) const {
  for (const ShaderBinding& b : bindings_)
    if (b.name == name) return &b;
  return nullptr;
}

}  // namespace hb
