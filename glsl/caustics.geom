#version 450
// The caustics geometry shader; see caustics.glsl.
#include "caustics.glsl"
