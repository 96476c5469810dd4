#version 450
// Light-space receiver maps for the image-space intersection: the world position of the
// nearest receiver per texel (w = 1 where there is one) and its triangle's unit normal
// (shadow.geom).
layout(location = 0) in vec3 g_world;
layout(location = 1) flat in vec3 g_normal;

layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;

void main() {
    out_position = vec4(g_world, 1.0);
    out_normal = vec4(g_normal, 0.0);
}
