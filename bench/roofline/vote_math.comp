#version 460
// The roofline's vote math with the engine's exact division and square root; see vote_math.glsl.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#include "vote_math.glsl"
