// hysteresis_blocks: the same edge tracking as hysteresis.comp, in parallel over blocks of 64 rows
// of each 32-pixel strip, each to its own fixed point (hysteresis_sweep.glsl, HYSTERESIS_BLOCKS),
// dispatched before the one workgroup of hysteresis.comp finishes the frame. Only with the Vulkan
// memory model (hysteresis_atomics.glsl); without it hysteresis_rmw.comp does all the work.
#version 450
#extension GL_KHR_memory_scope_semantics : require
#extension GL_GOOGLE_include_directive : require

#define HYSTERESIS_BLOCKS
#include "hysteresis_atomics.glsl"
#include "hysteresis_sweep.glsl"

void SetPassChanged(uint slot) {}  // declared by hysteresis_sweep.glsl; the blocks keep no passes
