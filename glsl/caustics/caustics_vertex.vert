#version 450
// The vertex-only caustic photon path: one vertex per photon (grid × subdivision, squared),
// no amplification stage; each vertex finds its photon from gl_VertexIndex and draws the
// same splat as the geometry-shader path. Measured against it by `underlight bench`.
#include "caustic_splat.glsl"

layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

layout(location = 0) flat out vec3 g_irradiance;

void main() {
    vec2 uv = photon_index_uv(uint(gl_VertexIndex), SUBDIVISION, pc.grid);
    Photon ph;
    CausticSplat splat;
    if (cast_photon(uv, float(pc.grid * SUBDIVISION), ph) && caustic_splat(ph, splat)) {
        gl_Position = splat.clip;
        gl_PointSize = splat.size;
        g_irradiance = splat.irradiance.rgb;
    } else {
        // Dropped: outside the clip volume's depth range, which clips a point exactly.
        gl_Position = vec4(0.0, 0.0, -1.0, 1.0);
        gl_PointSize = 1.0;
        g_irradiance = vec3(0.0);
    }
}
