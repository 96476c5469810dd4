#version 450
// The animated water surface as a grid over the water's extent, displaced by the same
// height function the photons refract at. No vertex buffer: the grid comes from the index.
#include "frame.glsl"
#include "frame_textures.glsl"

layout(constant_id = 0) const uint CELLS = 128;
#include "noise_texture.glsl"

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;

void main() {
    const ivec2 corner[6] = ivec2[6](ivec2(0, 0), ivec2(1, 0), ivec2(0, 1), ivec2(1, 0), ivec2(1, 1), ivec2(0, 1));
    uint quad = uint(gl_VertexIndex) / 6u;
    ivec2 c = ivec2(quad % CELLS, quad / CELLS) + corner[gl_VertexIndex % 6];
    WaterParams w = frame_water();
    vec2 xz = mix(w.extent_min, w.extent_max, vec2(c) / float(CELLS));
    vec3 hg = water_height_grad(w, noise_tex, xz, frame_water_phase());
    v_world = vec3(xz.x, w.level + hg.x, xz.y);
    v_normal = water_normal_from_grad(hg.yz);
    gl_Position = frame.camera_view_proj * vec4(v_world, 1.0);
}
