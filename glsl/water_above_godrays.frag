#version 450
// Water surface variant; see water.glsl.
#define THROUGH_SURFACE
#define HAS_GODRAYS
#include "water.glsl"
