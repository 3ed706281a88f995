// hysteresis_atomics: binding 5 (the hysteresis bit masks) and the accessors hysteresis_sweep.glsl
// needs, as relaxed atomic loads and stores of the Vulkan memory model (plain loads and stores on
// most hardware) and a workgroup barrier with acquire-release semantics. Included by
// hysteresis.comp and hysteresis_blocks.comp, which need the device feature vulkanMemoryModel
// (mandatory in Vulkan 1.3; runtime/vulkan_context.h). hysteresis_rmw.comp has its own, without it.

layout(std430, set = 0, binding = 5) buffer Masks { uvec2 masks[]; };

// An edge word another invocation may be writing.
uint NeighbourEdges(uint index) {
  return atomicLoad(masks[index].y, gl_ScopeQueueFamily, gl_StorageSemanticsBuffer, gl_SemanticsRelaxed);
}
// This invocation's edge word; `word` contains the old one.
void StoreEdges(uint index, uint word) {
  atomicStore(masks[index].y, word, gl_ScopeQueueFamily, gl_StorageSemanticsBuffer, gl_SemanticsRelaxed);
}
// Every invocation of the workgroup waits here; the buffer and shared writes before it are
// visible after it.
void PassBarrier() {
  controlBarrier(gl_ScopeWorkgroup, gl_ScopeWorkgroup, gl_StorageSemanticsBuffer | gl_StorageSemanticsShared,
                 gl_SemanticsAcquireRelease);
}
