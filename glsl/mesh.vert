#version 450
// Scene meshes from the camera (scene pass).
#include "frame.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_albedo;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec3 v_albedo;

void main() {
    v_world = in_position;
    v_normal = in_normal;
    v_albedo = in_albedo;
    gl_Position = frame.camera_view_proj * vec4(in_position, 1.0);
}
