#version 450
// Scene meshes from the camera: its own view, the refraction view or the mirrored
// reflection view (view.glsl), the latter two cut at the water by a clip plane.
#include "frame.glsl"
#include "view.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_albedo;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec3 v_albedo;

out gl_PerVertex {
    vec4 gl_Position;
    float gl_ClipDistance[1];
};

void main() {
    v_world = in_position;
    v_normal = in_normal;
    v_albedo = in_albedo;
    float bound = abs(frame.wave_amplitude) + abs(frame.noise_amplitude);
    vec3 p = in_position;
    // The planes sit at the waves' extremes, not the mean level, so no receiver the surface
    // can show is cut away (a sliver of the other side shows instead, at the waves' scale).
    if (VIEW == VIEW_REFRACTION) {
        gl_ClipDistance[0] = frame.water_level + bound - p.y;
    } else if (VIEW == VIEW_REFLECTION) {
        gl_ClipDistance[0] = p.y - (frame.water_level - bound);
        p.y = 2.0 * frame.water_level - p.y;
    } else {
        gl_ClipDistance[0] = 1.0;
    }
    gl_Position = frame.camera_view_proj * vec4(p, 1.0);
}
