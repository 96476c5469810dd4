#version 450
// Scene meshes into colour only (reflection pass); see scene_shading.glsl.
#define COLOR_ONLY
#include "scene_shading.glsl"
