// hysteresis: Canny edge tracking on bit masks (see hysteresis_sweep.glsl), with the edge words
// shared between strips accessed by relaxed atomic loads and stores of the Vulkan memory model.
// Needs the device feature vulkanMemoryModel (mandatory in Vulkan 1.3); runtime/vulkan_context.h.
#version 450
#extension GL_KHR_memory_scope_semantics : require
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8) in;

layout(std430, set = 0, binding = 6) buffer Masks { uvec2 masks[]; };

// A neighbour strip's edge word (its owner may be writing it).
uint NeighbourEdges(uint index) {
  return atomicLoad(masks[index].y, gl_ScopeQueueFamily, gl_StorageSemanticsBuffer, gl_SemanticsRelaxed);
}
// This strip's edge word; `word` contains the old one.
void StoreEdges(uint index, uint word) {
  atomicStore(masks[index].y, word, gl_ScopeQueueFamily, gl_StorageSemanticsBuffer, gl_SemanticsRelaxed);
}

#include "hysteresis_sweep.glsl"

void SetFlag(uint index) {
  atomicOr(flags[index], 1u, gl_ScopeQueueFamily, gl_StorageSemanticsBuffer, gl_SemanticsRelaxed);
}
