#version 450
// Godrays with footprint-sized beams (effects.godray_method = "footprint"). The same photon
// casting as godrays.geom, but each beam is drawn as a ribbon facing the camera, as wide as
// the beam's cross-section: the illumination volume of Frühstück & Prast's survey (§8), the
// refracted cell of each photon followed down the water. The ribbon's fragments spread the
// beam's flux evenly across its width (ribbon_radiance, godray_beam.glsl), so where beams
// spread they still cover the view without gaps between lines, and where they focus the
// ribbons narrow and brighten with them.
//   - A photon's cell is spanned by its grid neighbours, one along each axis (within this
//     invocation: the next photon, or the previous one for the last of a row). Each refracted
//     ray is a line p_s + s·r_t, so the cell's cross-section a distance s down the beam is the
//     parallelogram between the three rays at s. It needs the neighbours' rays only, not
//     their hits, so neighbours that land on another receiver or not at all still measure it.
//   - The ribbon's width is that parallelogram's extent across the ribbon (perpendicular to
//     the beam and to the view ray): the width of the beam the camera sees. A beam that
//     focuses to a line keeps the line's length when the line lies across the view.
//   - The width is taken where the beam enters the water and where it lands, and varies
//     linearly between them. A third sample halfway, which narrows the ribbon at a focus on
//     the way, read worse against the reference (godray relative RMSE at a full-resolution
//     godray target, 320×200, tank / port / storage: 0.046 / 0.079 / 0.045 against
//     0.039 / 0.069 / 0.044) for half as many vertices again.
//   - A ribbon narrower than a pixel on screen would miss pixel centres (a dotted beam): it is
//     widened to one pixel, and its radiance is spread over the width drawn, so its light is
//     the same.
//   - A photon with no neighbour in the water on one axis (the water's edge) takes the
//     extent along the other; with none at all it is drawn one pixel wide, as a line.
// Compiled twice (shaders::VARIANTS): as godrays_footprint.geom, and as
// godrays_footprint_debug.geom with PHOTON_DEBUG, which records every beam's cast for the flux
// budget (src/flux_budget.rs) as godrays.geom does.
#define PHOTON_BEAMS
#include "../photons/photon_cast.glsl"
#include "godray_beam.glsl"

#ifdef PHOTON_DEBUG
// Per beam, two records: (hit, its fate: 1 drawn, 2 drawn although the image-space iteration
// did not converge, −PHOTON_<reason> of photon_cast.glsl when dropped), and (surface point,
// flux: transmitted if drawn, else what it carried towards the water).
layout(set = 0, binding = BINDING_PHOTON_DEBUG, std430) writeonly buffer PhotonDebug {
    vec4 records[];
} photon_debug;
#endif

const int RIBBON_SAMPLES = 2;       // widths along each beam: where it enters the water, where it lands
const float RIBBON_MIN_PIXELS = 1.0; // narrowest ribbon drawn, across its length on screen
// Photons per axis an invocation casts: its own, and for a subdivision of 1 the neighbour
// cells' first photons too, so that every photon has a neighbour on each axis.
const int MAX_SIDE = GODRAY_FOOTPRINT_MAX_SUBDIVISION < 2 ? 2 : GODRAY_FOOTPRINT_MAX_SUBDIVISION;

layout(points) in;
// 2·RIBBON_SAMPLES vertices × GODRAY_FOOTPRINT_MAX_SUBDIVISION² beams = 4 × 4² = 64, each of
// 16 components (gl_Position alone of gl_PerVertex and three locations; the budget counts
// whole locations): the 1024 output components every geometry-shader device offers.
layout(triangle_strip, max_vertices = 64) out;
layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

layout(location = 0) flat in uvec2 v_cell[];
out gl_PerVertex { vec4 gl_Position; };
layout(location = 0) out vec4 g_world_travelled;   // world position; w: distance from the surface, m
layout(location = 1) flat out vec4 g_beam;         // xyz: r_t; w: flux, W (after the surface)
layout(location = 2) out float g_width;            // the ribbon's width here, m

vec3 surface_point[MAX_SIDE * MAX_SIDE];
vec3 direction[MAX_SIDE * MAX_SIDE]; // (0, 0, 0): never refracted into the water

// The neighbour of photon (i, j) along one axis (`step` = (1, 0) or (0, 1)) whose ray can
// span its cell: the next photon, else the previous one; −1 when neither entered the water.
int cell_neighbour(int i, int j, ivec2 step, int side) {
    ivec2 next = ivec2(i, j) + step, prev = ivec2(i, j) - step;
    if (all(lessThan(next, ivec2(side)))) {
        int n = next.y * side + next.x;
        if (dot(direction[n], direction[n]) > 0.0) return n;
    }
    if (all(greaterThanEqual(prev, ivec2(0)))) {
        int n = prev.y * side + prev.x;
        if (dot(direction[n], direction[n]) > 0.0) return n;
    }
    return -1;
}

// The beam's width across the ribbon at `s` metres down photon k's ray: the extent along
// `across` of the parallelogram its neighbours' rays span there (0 without neighbours).
float cross_section_width(int k, int nx, int ny, float s, vec3 across) {
    vec3 at = surface_point[k] + s * direction[k];
    float ex = nx >= 0 ? abs(dot(surface_point[nx] + s * direction[nx] - at, across)) : -1.0;
    float ey = ny >= 0 ? abs(dot(surface_point[ny] + s * direction[ny] - at, across)) : -1.0;
    if (ex < 0.0) ex = max(ey, 0.0); // one axis missing: a square cell
    if (ey < 0.0) ey = ex;
    return ex + ey;
}

void main() {
    int side = max(int(SUBDIVISION), 2);
    float photons_per_axis = float(pc.grid * SUBDIVISION);
    Photon own[GODRAY_FOOTPRINT_MAX_SUBDIVISION * GODRAY_FOOTPRINT_MAX_SUBDIVISION];
    bool landed[GODRAY_FOOTPRINT_MAX_SUBDIVISION * GODRAY_FOOTPRINT_MAX_SUBDIVISION];
    for (int j = 0; j < side; ++j) {
        for (int i = 0; i < side; ++i) {
            // From the photon's global index, as the triangle estimator does: the extra
            // photons of a subdivision of 1 are the neighbour cells' own.
            vec2 uv = (vec2(v_cell[0] * SUBDIVISION + uvec2(i, j)) + 0.5) / photons_per_axis;
            Photon ph;
            bool hit = cast_photon(uv, photons_per_axis, ph);
            surface_point[j * side + i] = ph.surface;
            direction[j * side + i] = ph.direction;
            if (i < int(SUBDIVISION) && j < int(SUBDIVISION)) {
                int o = j * int(SUBDIVISION) + i;
                own[o] = ph;
                landed[o] = hit;
#ifdef PHOTON_DEBUG
                uint index = ((v_cell[0].y * pc.grid + v_cell[0].x) * SUBDIVISION + j) * SUBDIVISION + i;
                float fate = hit ? (photon_fate == PHOTON_NOT_CONVERGED ? 2.0 : 1.0) : -float(photon_fate);
                photon_debug.records[2 * index] = vec4(ph.hit, fate);
                photon_debug.records[2 * index + 1] = vec4(ph.surface, ph.flux);
#endif
            }
        }
    }
    for (int j = 0; j < int(SUBDIVISION); ++j) {
        for (int i = 0; i < int(SUBDIVISION); ++i) {
            int o = j * int(SUBDIVISION) + i;
            if (!landed[o]) continue;
            Photon ph = own[o];
            vec4 a = frame.camera_view_proj * vec4(ph.surface, 1.0);
            vec4 b = frame.camera_view_proj * vec4(ph.hit, 1.0);
            if (a.w <= frame.z_near && b.w <= frame.z_near) continue; // wholly behind the camera
            int k = j * side + i;
            int nx = cell_neighbour(i, j, ivec2(1, 0), side), ny = cell_neighbour(i, j, ivec2(0, 1), side);
            for (int m = 0; m < RIBBON_SAMPLES; ++m) {
                float s = ph.travelled * float(m) / float(RIBBON_SAMPLES - 1);
                vec3 at = ph.surface + s * ph.direction;
                vec3 across = ribbon_across(at, ph.direction);
                float width = cross_section_width(k, nx, ny, s, across);
                // At least RIBBON_MIN_PIXELS across on screen: a godray-target pixel on the view
                // axis spans p·z metres at view depth z, and off the axis a pixel subtends less
                // (p·cos α across the radial direction), so p·z covers one everywhere. Behind
                // the camera (z < 0) the rasteriser clips the strip, and its width there only
                // shapes the clipped edge.
                float view_depth = (frame.camera_view_proj * vec4(at, 1.0)).w;
                width = max(width, RIBBON_MIN_PIXELS * godray_pixel_angle() * max(view_depth, 0.0));
                for (int edge = -1; edge <= 1; edge += 2) {
                    vec3 corner = at + (0.5 * float(edge) * width) * across;
                    gl_Position = frame.camera_view_proj * vec4(corner, 1.0);
                    g_world_travelled = vec4(corner, s);
                    g_beam = vec4(ph.direction, ph.flux);
                    g_width = width;
                    EmitVertex();
                }
            }
            EndPrimitive();
        }
    }
}
