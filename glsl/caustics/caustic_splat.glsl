// A caustic photon's splat (method step 5), shared by the geometry-shader photon path
// (caustics.geom) and the vertex-only one (caustics_vertex.vert), so both draw the same points.
#ifndef UNDERLIGHT_CAUSTIC_SPLAT_GLSL
#define UNDERLIGHT_CAUSTIC_SPLAT_GLSL
#include "../photons/photon_cast.glsl"

struct CausticSplat {
    vec4 clip;        // camera clip position of the hit
    float size;       // point size, whole pixels
    vec4 irradiance;  // rgb: irradiance / E_surface per covered pixel; a = 1 per photon
};

// The caustic photon grid's coarse cells for this frame: N/k columns, and as many rows of them
// as N² cells fill (frame.caustic_grid_aspect = k, 1 but for the triangle estimator's grid,
// which the survey shapes so that its mesh cells are square on screen: frame::photon_density).
// The draw still issues N² invocations, numbered row by row over N columns; `invocation`'s
// number over the new columns gives its `cell` of `cells`. False for the last row's leftover
// invocations, which have no cell.
bool caustic_grid_cell(uvec2 invocation, uint grid, out uvec2 cell, out uvec2 cells) {
    uint columns = clamp(uint(round(float(grid) / frame.caustic_grid_aspect)), 1u, grid * grid);
    cells = uvec2(columns, (grid * grid) / columns);
    uint number = invocation.y * grid + invocation.x;
    cell = uvec2(number % columns, number / columns);
    return cell.y < cells.y;
}

// Where photon `sub` of coarse `cell` lies on that grid (`photons_per_axis`: cells ×
// SUBDIVISION), from its global index, so that every invocation that casts a photon computes
// the same bits for it (photon_grid_uv's cell + sub / SUBDIVISION rounds differently on the
// two sides of a cell's border, and the triangles' meshes would crack there).
vec2 caustic_grid_photon_uv(uvec2 cell, uvec2 sub, uint subdivision, vec2 photons_per_axis) {
    return (vec2(cell * subdivision + sub) + 0.5) / photons_per_axis;
}

// Whether the camera sees the side of the receiver (normal n, either orientation) that light
// travelling along `light_dir` falls on. A photon on the top of a rail seen from below, or on
// the far face of a thin panel, lights nothing the camera sees; the depth test cannot tell
// at a silhouette, where that face lies within its tolerance of the face the pixel shows
// (the storage's rails drew lines of light 4× too bright, where the reference has none).
bool lit_side_faces_camera(vec3 hit, vec3 n, vec3 light_dir) {
    return dot(n, -light_dir) * dot(n, frame.camera_position - hit) > 0.0;
}

// A landed photon's receiver normal as a unit vector (Photon::receiver_normal: the one the
// cast read at the texel whose plane placed the hit).
vec3 unit_receiver_normal(Photon ph) {
    return normalize(ph.receiver_normal + 1e-6);
}

// A square splat of `size` whole pixels centred on receiver point `hit`, spreading the
// transmitted flux `flux` (W per channel, attenuation applied) over the receiver area its
// pixels cover; false when it cannot touch the target. Shared by the paper's points and by
// the triangle estimator's fallbacks (caustics_triangles.geom). `n`: the receiver's unit
// normal, as the cast found it (Photon::receiver_normal); zero when unknown (a floor's is
// taken).
bool caustic_square_on(vec3 hit, vec3 n, vec3 flux, float size, out CausticSplat s) {
    s.clip = frame.camera_view_proj * vec4(hit, 1.0);
    s.size = size;
    s.irradiance = vec4(0.0);
    if (s.clip.w <= frame.z_near) return false; // behind or at the camera
    // Cull splats that cannot touch the target: the view volume widened by the point's
    // radius. (Clipping a point outside the viewport is not enough: some rasterisers clamp
    // far-off points to the border instead of discarding them.)
    vec2 reach = s.clip.w * (1.0 + size / frame.caustic_target_size);
    if (any(greaterThan(abs(s.clip.xy), reach)) || s.clip.z < 0.0 || s.clip.z > s.clip.w) return false;
    vec3 to_hit = hit - frame.camera_position;
    float d_view = length(to_hit);
    if (n == vec3(0.0)) n = vec3(0.0, 1.0, 0.0); // outside the map: a floor's
    float cos_view = abs(dot(n, to_hit / d_view));
    float cos_axis = s.clip.w / d_view;
    // The splat spreads the photon's flux over size² pixels, each covering pixel_world_area
    // of the receiver: the density estimate of irradiance.
    float area = size * size * pixel_world_area(d_view, cos_view, cos_axis, frame.caustic_target_size.y);
    // Stored relative to the surface irradiance, so the buffer's values sit near 1 whatever
    // the light's strength (compose multiplies it back).
    s.irradiance = vec4(flux / (area * frame.surface_irradiance), 1.0);
    return true;
}

// The point a landed photon draws (the paper's estimator); false when it cannot touch the
// target.
bool caustic_splat(Photon ph, out CausticSplat s) {
    vec3 to_hit = ph.hit - frame.camera_position;
    float size = regulated_point_size(length(to_hit), frame.z_near, frame.z_far,
                                      frame.point_size_min, frame.point_size_max);
    // Whole pixels: a square point of integer size covers exactly size² pixel centres
    // wherever it lands, so each photon deposits exactly its flux (a fractional size covers
    // floor² or ceil² pixels depending on its sub-pixel position).
    size = clamp(round(size), 1.0, floor(frame.device_max_point_size));
    // The receiver's normal for the side test and the splat's area: the one the cast read at
    // the texel whose plane placed the hit, not read again at the hit's own texel (a second
    // fetch per photon, and on a receiver's edge another receiver's normal).
    vec3 stored = ph.receiver_normal;
    vec3 n = vec3(0.0);
    if (dot(stored, stored) > 0.25) {
        if (!lit_side_faces_camera(ph.hit, stored, ph.direction)) { s.irradiance = vec4(0.0); return false; }
        n = unit_receiver_normal(ph);
    }
    return caustic_square_on(ph.hit, n, ph.flux * water_transmittance(ph.travelled), size, s);
}
#endif
