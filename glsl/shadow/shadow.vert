#version 450
// Scene meshes from the light: world position for the receiver maps, and the vertex normal,
// which orients each triangle's plane. The geometry shader (shadow.geom) projects them.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;

void main() {
    v_world = in_position;
    v_normal = in_normal;
}
