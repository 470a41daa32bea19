#version 460
// The roofline's vote math with the device's own division and square root (Vulkan allows them 2.5 ULP and an
// inversesqrt's error: not the CPU's bits), to weigh what the exact ones cost (vote_math.glsl). Benchmark only.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require
#define SVA_ROOFLINE_DIVISION 1
float sva_div(float a, float b) { return a / b; }
float sva_sqrt(float x) { return sqrt(x); }
#include "vote_math.glsl"
