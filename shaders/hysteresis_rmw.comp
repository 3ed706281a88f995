// hysteresis_rmw: hysteresis.comp for devices without vulkanMemoryModel: the
// edge words shared between strips are accessed by atomic read-modify-writes (atomicOr), which
// every Vulkan device has. Slower on lavapipe (README); the same result.
#version 450
#extension GL_GOOGLE_include_directive : require

layout(std430, set = 0, binding = 5) buffer Masks { uvec2 masks[]; };

uint NeighbourEdges(uint index) { return atomicOr(masks[index].y, 0u); }
void StoreEdges(uint index, uint word) { atomicOr(masks[index].y, word); }
void PassBarrier() {
  memoryBarrierBuffer();
  memoryBarrierShared();
  barrier();
}

#include "hysteresis_sweep.glsl"

void SetPassChanged(uint slot) { atomicOr(pass_changed[slot], 1u); }
