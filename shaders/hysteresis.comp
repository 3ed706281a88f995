// hysteresis: Canny edge tracking to its fixed point in one workgroup, then the edge map keeps the
// sign classes of the edge pixels only (see hysteresis_sweep.glsl), with the edge words shared
// between strips accessed by relaxed atomic loads and stores of the Vulkan memory model
// (hysteresis_atomics.glsl). Runs after hysteresis_blocks.comp.
#version 450
#extension GL_KHR_memory_scope_semantics : require
#extension GL_GOOGLE_include_directive : require

#include "hysteresis_atomics.glsl"
#include "hysteresis_sweep.glsl"

void SetPassChanged(uint slot) {
  atomicOr(pass_changed[slot], 1u, gl_ScopeWorkgroup, gl_StorageSemanticsShared, gl_SemanticsRelaxed);
}
