#version 450
// The caustics geometry shader recording every photon (tests and debugging); see caustics.glsl.
#define PHOTON_DEBUG
#include "caustics.glsl"
