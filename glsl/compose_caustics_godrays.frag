#version 450
// Compose variant; see compose.glsl.
#define HAS_CAUSTICS
#define HAS_GODRAYS
#include "compose.glsl"
