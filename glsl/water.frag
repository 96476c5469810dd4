#version 450
// Water surface, seen from below only (no refraction or reflection pass); see water.glsl.
#include "water.glsl"
