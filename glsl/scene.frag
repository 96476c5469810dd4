#version 450
// Scene meshes into colour and albedo×transmittance; see scene_shading.glsl.
#include "scene_shading.glsl"
