// hysteresis: Canny edge tracking to its fixed point in one workgroup, then the edge map keeps the
// sign classes of the edge pixels only (see hysteresis_sweep.glsl), with the edge words shared
// between strips accessed by relaxed atomic loads and stores of the Vulkan memory model.
// Needs the device feature vulkanMemoryModel (mandatory in Vulkan 1.3); runtime/vulkan_context.h.
#version 450
#extension GL_KHR_memory_scope_semantics : require
#extension GL_GOOGLE_include_directive : require

layout(std430, set = 0, binding = 5) buffer Masks { uvec2 masks[]; };

// A neighbour strip's edge word (its owner may be writing it).
uint NeighbourEdges(uint index) {
  return atomicLoad(masks[index].y, gl_ScopeQueueFamily, gl_StorageSemanticsBuffer, gl_SemanticsRelaxed);
}
// This strip's edge word; `word` contains the old one.
void StoreEdges(uint index, uint word) {
  atomicStore(masks[index].y, word, gl_ScopeQueueFamily, gl_StorageSemanticsBuffer, gl_SemanticsRelaxed);
}
// Every invocation of the workgroup waits here; the buffer and shared writes before it are
// visible after it.
void PassBarrier() {
  controlBarrier(gl_ScopeWorkgroup, gl_ScopeWorkgroup, gl_StorageSemanticsBuffer | gl_StorageSemanticsShared,
                 gl_SemanticsAcquireRelease);
}

#include "hysteresis_sweep.glsl"

void SetPassChanged(uint slot) {
  atomicOr(pass_changed[slot], 1u, gl_ScopeWorkgroup, gl_StorageSemanticsShared, gl_SemanticsRelaxed);
}
