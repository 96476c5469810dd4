#version 450
// Water surface variant; see water.glsl.
#define THROUGH_SURFACE
#include "water.glsl"
