// Caustics (method step 5): each coarse cell becomes SUBDIVISION² photons; each photon that
// reaches a receiver is emitted as a point at the hit, sized by distance to the viewer, and
// carrying the irradiance estimate its splat contributes (see docs/units.md).
// Included by caustics.geom and by caustics_debug.geom, which defines PHOTON_DEBUG to record
// every photon's cast in a storage buffer for comparison with the CPU twin.
#include "photon.glsl"

#ifdef PHOTON_DEBUG
// Per photon, two records: (hit, 1 if it landed else 0), (surface point, flux).
layout(set = 0, binding = BINDING_PHOTON_DEBUG, std430) writeonly buffer PhotonDebug {
    vec4 records[];
} photon_debug;
#endif

layout(points) in;
layout(points, max_vertices = 64) out; // MAX_SUBDIVISION²
layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

layout(set = 0, binding = BINDING_LIGHT_NORMAL) uniform sampler2D light_normal;

layout(location = 0) flat in uvec2 v_cell[];
layout(location = 0) flat out vec4 g_irradiance; // rgb: irradiance / E_surface per covered pixel; a = 1 per photon
layout(location = 1) flat out float g_view_depth;

void main() {
    float photons_per_axis = float(pc.grid * SUBDIVISION);
    float target_h = frame.effect2.w;
    vec3 cam = frame.camera_pos.xyz;
    for (uint j = 0; j < SUBDIVISION; ++j) {
        for (uint i = 0; i < SUBDIVISION; ++i) {
            vec2 uv = photon_grid_uv(v_cell[0], uvec2(i, j), SUBDIVISION, uvec2(pc.grid));
            Photon ph;
            bool landed = cast_photon(uv, photons_per_axis, ph);
#ifdef PHOTON_DEBUG
            uint index = ((v_cell[0].y * pc.grid + v_cell[0].x) * SUBDIVISION + j) * SUBDIVISION + i;
            photon_debug.records[2 * index] = vec4(ph.hit, landed ? 1.0 : 0.0);
            photon_debug.records[2 * index + 1] = vec4(ph.surface, ph.flux);
#endif
            if (!landed) continue;
            vec4 clip = frame.camera_view_proj * vec4(ph.hit, 1.0);
            if (clip.w <= frame.camera_params.x) continue; // behind or at the camera
            vec3 to_hit = ph.hit - cam;
            float d_view = length(to_hit);
            float size = regulated_point_size(d_view, frame.camera_params.x, frame.camera_params.y,
                                              frame.effect0.x, frame.effect0.y);
            // Whole pixels: a square point of integer size covers exactly size² pixel centres
            // wherever it lands, so each photon deposits exactly its flux (a fractional size
            // covers floor² or ceil² pixels depending on its sub-pixel position).
            size = clamp(round(size), 1.0, floor(frame.effect2.x));
            // Cull splats that cannot touch the target: the view volume widened by the point's
            // radius. (Clipping a point outside the viewport is not enough: some rasterisers
            // clamp far-off points to the border instead of discarding them.)
            vec2 reach = clip.w * (1.0 + size / frame.effect2.zw);
            if (any(greaterThan(abs(clip.xy), reach)) || clip.z < 0.0 || clip.z > clip.w) continue;
            ivec2 texel;
            vec3 n = vec3(0.0, 1.0, 0.0);
            if (light_texel(ph.hit, texel)) n = normalize(texelFetch(light_normal, texel, 0).xyz + 1e-6);
            float cos_view = abs(dot(n, to_hit / d_view));
            float cos_axis = clip.w / d_view;
            // The splat spreads the photon's flux over size² pixels, each covering
            // pixel_world_area of the receiver: the density estimate of irradiance.
            float area = size * size * pixel_world_area(d_view, cos_view, cos_axis, target_h);
            vec3 flux = ph.flux * exp(-frame.gamma.rgb * ph.travelled);
            gl_Position = clip;
            gl_PointSize = size;
            // Stored relative to the surface irradiance so half floats keep their precision
            // whatever the light's strength (compose multiplies it back).
            g_irradiance = vec4(flux / (area * frame.light_flux.x), 1.0);
            g_view_depth = clip.w;
            EmitVertex();
        }
    }
}
