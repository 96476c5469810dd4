// The water's gradient-noise texture (set 0), declared once for every shader that includes
// the water's height function through more than one path.
#ifndef UNDERLIGHT_NOISE_TEXTURE_GLSL
#define UNDERLIGHT_NOISE_TEXTURE_GLSL
#include "frame_textures.glsl"
layout(set = 0, binding = BINDING_NOISE) uniform sampler2D noise_tex;
#endif
