#version 450
// Filter (method step 7): a low-pass over a sparse photon buffer with a kernel of TAPS taps
// on a disc, rotated per pixel so the residual pattern becomes fine noise instead of a
// regular grid. Weights are equal, so the filter keeps the buffer's mean (its energy). Taps
// that land on another surface than the centre's (depth_aware.glsl) are left out, so the
// kernel does not carry light across a silhouette.
#include "shader_math.glsl"
#include "depth_aware.glsl"
#include "pixel_noise.glsl"

layout(constant_id = 0) const int TAPS = 8;
layout(push_constant) uniform FilterPush {
    float radius_px;
    float same_surface; // frame::CAUSTIC_SAME_SURFACE, GODRAY_SAME_SURFACE
} pc;
layout(set = 0, binding = BINDING_FILTER_INPUT) uniform sampler2D input_buffer;

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_color;

void main() {
    vec2 size = vec2(textureSize(input_buffer, 0));
    vec2 texel = 1.0 / size;
    float angle = 2.0 * PI * pixel_noise(gl_FragCoord.xy);
    SurfacePlane plane = surface_plane(v_uv, size);
    vec4 sum = texelFetch(input_buffer, ivec2(gl_FragCoord.xy), 0);
    float taken = 1.0;
    for (int i = 0; i < TAPS; ++i) {
        // Taps on a golden-angle spiral fill the disc evenly.
        float a = angle + float(i) * 2.39996323;
        float r = pc.radius_px * sqrt((float(i) + 0.5) / float(TAPS));
        vec2 offset_px = r * vec2(cos(a), sin(a));
        vec2 uv = v_uv + offset_px * texel;
        if (off_surface(plane, offset_px, inverse_view_depth(uv)) <= pc.same_surface) {
            sum += texture(input_buffer, uv);
            taken += 1.0;
        }
    }
    out_color = sum / taken;
}
