#version 460
// The vote kernel for devices without subgroup arithmetic: one atomic per vote;
// see match_votes.glsl.
#extension GL_GOOGLE_include_directive : require
#include "match_votes.glsl"
