#version 450
// Compose variant; see compose.glsl.
#define HAS_CAUSTICS
#include "compose.glsl"
