#version 450
// Compose variant; see compose.glsl.
#include "compose.glsl"
