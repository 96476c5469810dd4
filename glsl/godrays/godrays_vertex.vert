#version 450
// The vertex-only godray path: two vertices per photon drawn as a line list, no
// amplification stage. Both ends cast the same photon (the price of having no stage that
// sees a whole primitive) and draw the geometry shader's line.
#define PHOTON_BEAMS
#include "../photons/photon_cast.glsl"

layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

layout(location = 0) out vec4 g_world_travelled;
layout(location = 1) flat out vec4 g_beam;

void main() {
    uint photon = uint(gl_VertexIndex) / 2u;
    bool at_hit = (gl_VertexIndex & 1) == 1;
    vec2 uv = photon_index_uv(photon, SUBDIVISION, pc.grid);
    Photon ph;
    bool landed = cast_photon(uv, float(pc.grid * SUBDIVISION), ph);
    vec4 a = frame.camera_view_proj * vec4(ph.surface, 1.0);
    vec4 b = frame.camera_view_proj * vec4(ph.hit, 1.0);
    if (!landed || (a.w <= frame.z_near && b.w <= frame.z_near)) {
        // Dropped: both ends outside the depth range, so the clipper removes the line.
        gl_Position = vec4(0.0, 0.0, -1.0, 1.0);
        g_world_travelled = vec4(0.0);
        g_beam = vec4(0.0);
        return;
    }
    gl_Position = at_hit ? b : a;
    g_world_travelled = at_hit ? vec4(ph.hit, ph.travelled) : vec4(ph.surface, 0.0);
    g_beam = vec4(ph.direction, ph.flux);
}
