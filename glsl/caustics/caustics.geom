#version 450
// Caustics (method step 5): each coarse cell becomes SUBDIVISION² photons; each photon that
// reaches a receiver is emitted as a point at the hit, carrying the irradiance estimate its
// splat contributes (see docs/units.md). The paper's points are sized by the distance to the
// viewer. Compiled five times (shaders::VARIANTS): as caustics.geom; as caustics_debug.geom
// with PHOTON_DEBUG, which records every photon's cast in a storage buffer for comparison
// with the CPU twin; and both again with FOOTPRINT_POINTS (caustics_footprint.geom,
// caustics_footprint_debug.geom), the footprint-sized points below; and with FOOTPRINT_POINTS
// and FOOTPRINT_RECEIVER_TEST as caustics_footprint_receiver.geom, which hands each point its
// receiver's plane for the fragments' test (effects.caustic_receiver_test).
#include "caustic_splat.glsl"

#ifdef PHOTON_DEBUG
// Per photon, two records: (hit, 1 if it landed, else −PHOTON_<reason> of photon_cast.glsl), and
// (surface point, flux: transmitted if it landed, else what it carried towards the water); both
// zero for an invocation with no cell. The flux budget records the triangle estimator's photons
// through this variant too, so it numbers its photons over their grid, N/k × N·k coarse cells
// (caustic_grid_cell; k is 1 for the paper's points), each photon at its index in that grid as
// caustics_triangles.geom places it. A footprint point clamped to the device's largest point
// records PHOTON_RECORD_FOOTPRINT_CLAMPED instead of 1 (photon_cast.glsl).
layout(set = 0, binding = BINDING_PHOTON_DEBUG, std430) writeonly buffer PhotonDebug {
    vec4 records[];
} photon_debug;
#endif

layout(points) in;
#ifdef FOOTPRINT_POINTS
// Each footprint point's hat is drawn as a quad (below): 4 vertices × FOOTPRINT_MAX_SUBDIVISION².
layout(triangle_strip, max_vertices = 64) out;
#else
layout(points, max_vertices = 64) out; // MAX_SUBDIVISION²
#endif
layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

layout(location = 0) flat in uvec2 v_cell[];
#ifdef FOOTPRINT_POINTS
// Only the built-in block's member the quads write: the full block adds point size and clip
// and cull distances to every vertex's component count (11 with the receiver's plane, 64
// vertices within the 1024 every geometry-shader device offers: shader_abi::limits).
out gl_PerVertex { vec4 gl_Position; };
#endif
layout(location = 0) flat out vec3 g_irradiance; // irradiance / E_surface per covered pixel
#ifdef FOOTPRINT_POINTS
layout(location = 1) noperspective out vec2 g_lattice; // the hat's (s, t) at the vertex (caustics.frag)
#endif
#ifdef FOOTPRINT_RECEIVER_TEST
layout(location = 2) flat out vec2 g_receiver_plane; // its receiver's plane: 1 / view depth at the photon (< 0: no test), its gradient as two halves
#endif

#ifdef FOOTPRINT_POINTS
// Footprint-sized points (effects.caustic_estimator = "footprint"; issue 16's photon
// differentials; docs/accuracy.md, "Footprint-sized points"). The invocation casts its cell's
// photons together, so each knows where its grid neighbours landed. Its footprint is its cell
// of the photon window refracted onto its receiver: the mean of the four quarters of the mesh
// cells around it, from the spans to its neighbours on its receiver (footprint_edges). The
// photon's irradiance is its flux over the footprint, so sparse photons cover the floor
// between them and dense ones stay under a pixel where the waves focus them. It spreads that
// light over the target by a hat on its cell of the lattice the photons form there, the spans
// to its neighbours projected (footprint_hat_basis and footprint_hat_share, shader_math.glsl):
// neighbouring hats sum to 1 however the lattice is turned, so the footprints tile without
// seams, overlaps or moiré, and the caustic between photons is their irradiance interpolated.
// The hat is drawn as a quad, the parallelogram its tent spans (out to its neighbours'
// centres, |s|, |t| ≤ 1) widened by the reach of a pixel's samples: a point sprite would be
// a square around the hat, and the hats are mostly long and oblique (slivers where the waves
// fold the light, cells stretched along receivers seen at a slant), so at the scenes' own
// sizes five in six of a sprite's fragments lay outside the hat and shaded nothing
// (docs/performance.md, "Footprint hats drawn as quads"). Its size keeps the bound the
// sprites had, the device's largest point; the flux budget (`render --flux-budget`) counts
// the photons that bound clamped. A photon whose ray runs along its receiver takes the
// paper's size, which is bounded, as a square hat.
const int MAX_PHOTONS = FOOTPRINT_MAX_SUBDIVISION * FOOTPRINT_MAX_SUBDIVISION;
vec3 hit[MAX_PHOTONS];
vec3 normal[MAX_PHOTONS]; // unit; zero where the light's normal map holds none
vec3 flux[MAX_PHOTONS];   // transmitted and attenuated to the hit, W per channel
bool seen[MAX_PHOTONS];   // landed on the side of its receiver the camera sees
vec3 surface[MAX_PHOTONS];   // where its ray entered the water, and its refracted direction
vec3 direction[MAX_PHOTONS]; // (light_step_edge)
vec2 window_uv[MAX_PHOTONS];
float cell_scale[MAX_PHOTONS];
#ifdef PHOTON_DEBUG
uint record[MAX_PHOTONS]; // its records' index
#endif

// Photon k's cell edges on its receiver along grid axis `axis` (0: u, 1: v), towards its
// neighbours before and after it: the span to each neighbour in the invocation (`side` a
// row) that landed on its receiver; for a neighbour that did not (another invocation's
// photon at the coarse cell's border, or one in the invocation that landed on another
// receiver, was blocked or missed), the span to that neighbour's ray met with the photon's
// receiver plane (neighbour_edge_on_plane); the other's where only one of these is found; and
// where neither is (both neighbours' rays miss the water or run along the plane) its own ray
// a grid step over (light_step_edge). False with none. `both_on_receiver`: both neighbours
// in the invocation landed on the photon's receiver. Its grid has at least two photons per
// cell a side (CausticEstimator::min_subdivision), so a photon lies on one border of its
// cell along an axis at most, and its neighbour on the other side is in the invocation: the
// missing one's place in the light's window is the photon's mirrored from it (the view's
// warp is smooth over two photons). A neighbour in the invocation gives its own place.
bool footprint_edges(int k, int axis, int side, vec2 photons_per_axis, out vec3 before, out vec3 after,
                     out bool both_on_receiver) {
    int along = axis == 0 ? k % side : k / side, step = axis == 0 ? 1 : side;
    bool a = along > 0 && seen[k - step] && on_one_receiver(hit[k], normal[k], hit[k - step], normal[k - step]);
    bool b = along + 1 < side && seen[k + step] && on_one_receiver(hit[k], normal[k], hit[k + step], normal[k + step]);
    before = a ? hit[k] - hit[k - step] : vec3(0.0);
    after = b ? hit[k + step] - hit[k] : vec3(0.0);
    both_on_receiver = a && b;
    // The missing neighbours, before (-1) and after (+1), in one loop: each inlined copy of
    // neighbour_edge_on_plane carries a refraction and a surface evaluation.
    for (int dir = -1; dir <= 1; dir += 2) {
        if (dir < 0 ? a : b) continue;
        bool in_invocation = dir < 0 ? along > 0 : along + 1 < side;
        vec2 neighbour_uv = in_invocation ? window_uv[k + dir * step] : 2.0 * window_uv[k] - window_uv[k - dir * step];
        vec3 edge;
        if (!neighbour_edge_on_plane(hit[k], normal[k], surface[k], neighbour_uv, float(dir), edge)) continue;
        if (dir < 0) { before = edge; a = true; }
        else { after = edge; b = true; }
    }
    if (!a) before = after;
    if (!b) after = before;
    if (a || b) return true;
    bool own = light_step_edge(hit[k], normal[k], surface[k], direction[k], window_uv[k], cell_scale[k], axis,
                               photons_per_axis, after);
    before = after;
    return own;
}

// A cell edge's span on the target, pixels: the camera's projection linearised at the photon
// (clip position `clip`, in front of the camera). Projecting the edge's far end instead made
// the span, and the light the photon deposits (its irradiance times its pixels), grow
// without bound where that end nears the camera's plane: on the tank at 96×60 with 24² × 3²
// photons, a few photons on the tall pillar drew streaks across the frame and +21 % of the
// caustic flux. Linearised, its pixels over its footprint are the projection's own ratio at
// the hit, and a small cell's span is the same to first order.
vec2 target_span(vec4 clip, vec3 edge) {
    vec4 along = frame.camera_view_proj * vec4(edge, 0.0);
    return (along.xy * clip.w - clip.xy * along.w) / (clip.w * clip.w) * 0.5 * frame.caustic_target_size;
}

void main() {
    int side = int(SUBDIVISION);
#ifdef PHOTON_DEBUG
    uvec2 cell, cells;
    bool has_cell = caustic_grid_cell(v_cell[0], pc.grid, cell, cells);
    vec2 photons_per_axis = vec2(cells * SUBDIVISION);
#else
    float photons_per_axis = float(pc.grid * SUBDIVISION);
#endif
    for (int j = 0; j < side; ++j) {
        for (int i = 0; i < side; ++i) {
            int k = j * side + i;
            Photon ph;
            seen[k] = false;
#ifdef PHOTON_DEBUG
            uint index = ((v_cell[0].y * pc.grid + v_cell[0].x) * SUBDIVISION + uint(j)) * SUBDIVISION + uint(i);
            record[k] = index;
            if (!has_cell) {
                photon_debug.records[2 * index] = vec4(0.0);
                photon_debug.records[2 * index + 1] = vec4(0.0);
                continue;
            }
            vec2 uv = caustic_grid_photon_uv(cell, uvec2(i, j), SUBDIVISION, photons_per_axis);
            bool landed = cast_photon(uv, photons_per_axis, ph);
            photon_debug.records[2 * index] = vec4(ph.hit, landed ? 1.0 : -float(photon_fate));
            photon_debug.records[2 * index + 1] = vec4(ph.surface, ph.flux);
#else
            vec2 uv = photon_grid_uv(v_cell[0], uvec2(i, j), SUBDIVISION, uvec2(pc.grid));
            bool landed = cast_photon(uv, photons_per_axis, ph);
#endif
            hit[k] = ph.hit;
            flux[k] = ph.flux * water_transmittance(ph.travelled);
            surface[k] = ph.surface;
            direction[k] = ph.direction;
            window_uv[k] = ph.window_uv;
            cell_scale[k] = ph.cell_scale;
            // The side test and the footprint's plane: the receiver's normal where the cast
            // placed the hit (caustic_splat).
            vec3 stored = ph.receiver_normal;
            bool has_normal = dot(stored, stored) > 0.25;
            normal[k] = has_normal ? unit_receiver_normal(ph) : vec3(0.0);
            seen[k] = landed && (!has_normal || lit_side_faces_camera(ph.hit, stored, ph.direction));
        }
    }
    float largest = floor(frame.device_max_point_size);
    for (int k = 0; k < side * side; ++k) {
        if (!seen[k]) continue;
        vec4 clip = frame.camera_view_proj * vec4(hit[k], 1.0);
        if (clip.w <= frame.z_near) continue; // behind the camera: caustic_square_on drops it
        vec3 u[2], v[2]; // the cell's edges before and after the photon along each axis
        // The paper's size where the photon has no footprint; its irradiance then comes from
        // the receiver area the square's pixels cover (caustic_square_on).
        float size = regulated_point_size(length(hit[k] - frame.camera_position), frame.z_near, frame.z_far,
                                          frame.point_size_min, frame.point_size_max);
        float footprint = 0.0;
        float pixels = size * size; // the footprint's area on the target
        mat2 spans = mat2(size, 0.0, 0.0, size); // its cell's edges there, as columns
        vec3 hat_u = vec3(0.0), hat_v = vec3(0.0); // and on its receiver (none for the paper's size)
        vec2 du[2], dv[2];
        // One call in a loop over the axes rather than one per axis: each inlined copy of
        // footprint_edges carries a neighbour's refraction (neighbour_edge_on_plane).
        vec3 edges[4]; // before and after along u, then along v
        bool has_footprint = normal[k] != vec3(0.0);
        bool interior = has_footprint; // all four neighbours on the photon's receiver
        for (int axis = 0; axis < 2 && has_footprint; ++axis) {
            bool both;
            has_footprint = footprint_edges(k, axis, side, vec2(photons_per_axis), edges[2 * axis], edges[2 * axis + 1],
                                            both);
            interior = interior && both;
        }
        u = vec3[2](edges[0], edges[1]);
        v = vec3[2](edges[2], edges[3]);
        if (has_footprint) {
            for (int a = 0; a < 2; ++a) {
                du[a] = target_span(clip, u[a]);
                dv[a] = target_span(clip, v[a]);
            }
            // The footprint: the mean of the four quarters of the mesh cells around the
            // photon, each |area| (a folded cell keeps its area, as a folded triangle does).
            // One parallelogram of the edges' means cancelled where the waves fold the light
            // between a photon's neighbours: a footprint of nothing put the photon's light on
            // one pixel, 44× the reference's there (the tank at 320×200 with 130² × 3²).
            // Its pixels: the same quarters projected onto the target, not its area over the
            // area a pixel covers at the hit (pixel_world_area), which is clamped at grazing
            // views, where the points read up to 20 % too bright.
            pixels = 0.0;
            for (int a = 0; a < 2; ++a) {
                for (int b = 0; b < 2; ++b) {
                    footprint += 0.25 * length(cross(u[a], v[b]));
                    pixels += 0.25 * abs(du[a].x * dv[b].y - du[a].y * dv[b].x);
                }
            }
            // The hat's cell: the mean spans to the neighbours either side along each axis.
            spans = mat2(0.5 * (du[0] + du[1]), 0.5 * (dv[0] + dv[1]));
            hat_u = 0.5 * (u[0] + u[1]);
            hat_v = 0.5 * (v[0] + v[1]);
        }
        // The hat's extent on the target (its basis's reach along each pixel axis either side,
        // and the samples' own reach from their pixel's centre, (S − 1) / 2S) stays within the
        // device's largest point, the sprites' bound: a larger hat shrinks, brighter, keeping
        // the photon's light.
        mat2 basis = footprint_hat_basis(spans);
        vec2 reach = abs(basis[0]) + abs(basis[1]);
        float across = max(reach.x, reach.y);
        float samples_reach = footprint_hat_samples_reach();
        float shrink = across + samples_reach > 0.5 * largest ? (0.5 * largest - samples_reach) / across : 1.0;
        basis *= shrink;
        bool clamped = footprint > 0.0 && shrink < 1.0;
#ifdef PHOTON_DEBUG
        if (clamped) photon_debug.records[2 * record[k]].w = PHOTON_RECORD_FOOTPRINT_CLAMPED;
#endif
        CausticSplat splat;
        if (!caustic_square_on(hit[k], normal[k], flux[k], across * shrink, splat)) continue;
        // The photon's light in pixels × irradiance: its flux over its footprint's area, over
        // that area's pixels (or the paper's square's irradiance over its pixels), which its
        // hat's shares deposit, each carrying light over the hat's area.
        vec3 light = footprint > 0.0 ? flux[k] / (footprint * frame.surface_irradiance) * pixels
                                     : splat.irradiance.rgb * pixels;
        // The point's one depth is the test the visibility draw set up (the farthest depth a
        // splat may have at each pixel), and the hat's pixels show its receiver's plane, which
        // comes nearer the camera than the photon on one side: on a floor seen at a grazing
        // angle, by more than the test's 2 % within a few pixels. At the photon's depth that
        // side failed the test and its light was lost (the port's seabed towards the horizon:
        // 320×200 flux −0.67 %, with the hat's nearest corner −0.31 %). So the point takes the
        // depth of its hat's nearest corner on that plane.
        float nearest = splat.clip.z / splat.clip.w;
        for (int c = 0; c < 4; ++c) {
            vec3 corner = hit[k] + shrink * ((c & 1) == 0 ? hat_u : -hat_u) + shrink * ((c & 2) == 0 ? hat_v : -hat_v);
            vec4 at = frame.camera_view_proj * vec4(corner, 1.0);
            if (at.w > frame.z_near) nearest = min(nearest, at.z / at.w);
        }
        vec3 irradiance = light / abs(determinant(basis));
        vec2 centre = (splat.clip.xy / splat.clip.w * 0.5 + 0.5) * frame.caustic_target_size;
#ifdef FOOTPRINT_RECEIVER_TEST
        // The receiver's plane for the fragments' test that their pixel shows it
        // (footprint_pixel_on_receiver): its reciprocal view depth at the photon and, packed as
        // two halves, that depth's gradient over the target's pixels over its value there, from
        // two directions on the plane; a negative depth where the fragments take no test. A hat
        // whose four neighbours all landed on its receiver spans that receiver and takes none
        // (the same figures as testing every hat: docs/accuracy.md, "Hats on their own receiver").
        // Only neighbours inside the invocation say so (those across the coarse cell's border
        // are cast onto the photon's own plane), so at 3 × 3 only the middle photon's hat can
        // skip the test (docs/performance.md, "Where the footprint points' pass goes").
        float w_centre = 1.0 / clip.w;
        vec2 w_gradient = vec2(0.0);
        bool tested = normal[k] != vec3(0.0) && !interior;
        if (tested) {
            vec3 n = normal[k];
            vec3 t1 = normalize(cross(n, abs(n.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
            vec3 t2 = cross(n, t1);
            float dw1 = -(frame.camera_view_proj * vec4(t1, 0.0)).w * w_centre * w_centre;
            float dw2 = -(frame.camera_view_proj * vec4(t2, 0.0)).w * w_centre * w_centre;
            tested = footprint_receiver_plane(target_span(clip, t1), target_span(clip, t2), dw1, dw2, w_centre,
                                              w_gradient);
        }
        vec2 receiver_plane = vec2(tested ? w_centre : -1.0, uintBitsToFloat(packHalf2x16(w_gradient)));
#endif
        mat2 to_lattice = inverse(basis);
        // The quad: every pixel one of whose samples lies on the hat (|s|, |t| < 1) has its
        // centre within the samples' reach of it, at most that reach times the pixel's extent
        // along s and t further out in lattice units (footprint_hat_quad_reach). In NDC at
        // w = 1, the sprite's one depth at every corner. Each corner carries its (s, t), which
        // the rasteriser interpolates to every pixel's centre: the fragments read the hat's
        // inverse basis as that coordinate's screen derivatives, so a vertex carries 9
        // components (11 with the receiver's plane) where the hat's centre and inverse basis
        // made 13 (15): the geometry stage's output, which a GPU holds on chip, a third
        // smaller for the same buffers (docs/performance.md, "The hats' lattice coordinates
        // interpolated").
        vec2 reach_st = footprint_hat_quad_reach(to_lattice, samples_reach);
        float depth = max(nearest, 0.0);
        for (int c = 0; c < 4; ++c) {
            vec2 st = vec2((c & 1) == 0 ? -reach_st.x : reach_st.x, (c & 2) == 0 ? -reach_st.y : reach_st.y);
            vec2 corner = centre + basis * st;
            gl_Position = vec4(corner / frame.caustic_target_size * 2.0 - 1.0, depth, 1.0);
            g_irradiance = irradiance;
            g_lattice = st;
#ifdef FOOTPRINT_RECEIVER_TEST
            g_receiver_plane = receiver_plane;
#endif
            EmitVertex();
        }
        EndPrimitive();
    }
}
#else
void main() {
#ifdef PHOTON_DEBUG
    uvec2 cell, cells;
    bool has_cell = caustic_grid_cell(v_cell[0], pc.grid, cell, cells);
    vec2 photons_per_axis = vec2(cells * SUBDIVISION);
#else
    float photons_per_axis = float(pc.grid * SUBDIVISION);
#endif
    for (uint j = 0; j < SUBDIVISION; ++j) {
        for (uint i = 0; i < SUBDIVISION; ++i) {
            Photon ph;
#ifdef PHOTON_DEBUG
            uint index = ((v_cell[0].y * pc.grid + v_cell[0].x) * SUBDIVISION + j) * SUBDIVISION + i;
            if (!has_cell) {
                photon_debug.records[2 * index] = vec4(0.0);
                photon_debug.records[2 * index + 1] = vec4(0.0);
                continue;
            }
            vec2 uv = caustic_grid_photon_uv(cell, uvec2(i, j), SUBDIVISION, photons_per_axis);
            bool landed = cast_photon(uv, photons_per_axis, ph);
            photon_debug.records[2 * index] = vec4(ph.hit, landed ? 1.0 : -float(photon_fate));
            photon_debug.records[2 * index + 1] = vec4(ph.surface, ph.flux);
#else
            vec2 uv = photon_grid_uv(v_cell[0], uvec2(i, j), SUBDIVISION, uvec2(pc.grid));
            bool landed = cast_photon(uv, photons_per_axis, ph);
#endif
            CausticSplat splat;
            if (!landed || !caustic_splat(ph, splat)) continue;
            gl_Position = splat.clip;
            gl_PointSize = splat.size;
            g_irradiance = splat.irradiance.rgb;
            EmitVertex();
        }
    }
}
#endif
