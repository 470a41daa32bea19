#version 460
// The vote kernel with subgroup pre-aggregation of equal keys (devices with
// basic, ballot and arithmetic subgroup operations); see match_votes.glsl.
#extension GL_GOOGLE_include_directive : require
#define SVA_SUBGROUP_AGGREGATION 1
#include "match_votes.glsl"
