#version 450
// Compose variant; see compose.glsl.
#define HAS_GODRAYS
#include "compose.glsl"
