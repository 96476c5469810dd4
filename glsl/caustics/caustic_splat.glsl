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

// Whether a photon that landed at `p` with unit receiver normal `n` lies on the receiver of
// one that landed at `at` with unit normal `n_at`: normals within 45°, and off that one's
// tangent plane by under a quarter of its distance from it. (Within 25°, the facets of the
// tank's rocks, 20–40° apart, refused their triangles, and their photons drew squares; a wall
// and the floor, 90°, stay two receivers.) The triangles' mesh cells and the footprint
// points' neighbours both ask it.
bool on_one_receiver(vec3 at, vec3 n_at, vec3 p, vec3 n) {
    if (dot(n_at, n) < 0.7) return false;
    vec3 d = p - at;
    return abs(dot(d, n_at)) <= 0.25 * length(d);
}

// Where a grid neighbour's light ray (unit direction d) that enters the water at `entry`,
// refracted there by the unit water normal `water_normal`, meets the plane of unit normal n
// through `hit` (a landed photon's receiver): the cell edges' tail (light_step_edge,
// neighbour_edge_on_plane). False where the ray meets the back of a wave, is totally
// reflected, runs along the plane or meets it behind the water.
bool refracted_ray_meets_plane(vec3 entry, vec3 d, vec3 water_normal, vec3 hit, vec3 n, out vec3 at) {
    at = vec3(0.0);
    vec3 refracted = refract(d, water_normal, 1.0 / frame.ior);
    if (dot(-d, water_normal) <= 0.0 || dot(refracted, refracted) == 0.0) return false;
    refracted = normalize(refracted);
    float along = dot(refracted, n);
    if (abs(along) <= 1e-3) return false;
    float to_plane = dot(hit - entry, n) / along;
    if (!(to_plane > 0.0)) return false;
    at = entry + to_plane * refracted;
    return true;
}

// The edge of a landed photon's cell along grid axis `axis` (0: u, 1: v) from its own
// refracted ray (entering the water at `surface` along `direction`, its hit on the plane of
// unit normal n, cast at `window_uv` of a grid of `photons_per_axis` whose warp scales its
// cell by `cell_scale`): the neighbour's ray cast from the light one grid step away (the step
// isotropic under the view's warp: its area is the warped cell's), entering the water's
// plane at the photon's entry and refracted by its water normal, where it meets its
// receiver's plane. A directional light's neighbour ray is the photon's own taken parallel,
// so its edge needs no refraction; a point light's rays spread, and its neighbour is
// refracted by the normal that refracted the photon's (the slit of
// tests/method.rs::point_light_through_a_slit…, whose strip read 1.57 of the exact law in
// squares without it). False where it never refracted, or a ray runs along the plane. The
// triangles' cut cells (caustics_triangles.geom) and the footprint points (caustics.geom)
// both take it where no neighbour's ray gives the edge.
bool light_step_edge(vec3 hit, vec3 n, vec3 surface, vec3 direction, vec2 window_uv, float cell_scale, int axis,
                     vec2 photons_per_axis, out vec3 edge) {
    edge = vec3(0.0);
    if (!(dot(direction, direction) > 0.5)) return false;
    if (frame.light_is_point == 0.0) {
        // The light's window is orthographic: an NDC step of 2 spans it.
        vec4 across = axis == 0 ? vec4(2.0, 0.0, 0.0, 0.0) : vec4(0.0, 2.0, 0.0, 0.0);
        vec3 step = (frame.light_inv_view_proj * across).xyz * frame.photon_window_size[axis]
                  / photons_per_axis[axis] * sqrt(cell_scale);
        // Along the light to the water's level, then along the refracted ray to the plane.
        vec3 at_water = step - frame.light_axis * (step.y / min(frame.light_axis.y, -1e-3));
        float denom = dot(direction, n);
        if (abs(denom) <= 1e-3) return false;
        edge = at_water - direction * (dot(at_water, n) / denom);
        return true;
    }
    vec2 ndc = photon_window_ndc(window_uv);
    ndc[axis] += 2.0 * frame.photon_window_size[axis] / photons_per_axis[axis] * sqrt(cell_scale);
    vec3 o, d;
    light_ray_at(ndc, o, d);
    if (!(d.y < -1e-3)) return false;
    // Snell's law in vectors: incident − ior · refracted lies along the water's normal.
    vec3 incident = normalize(surface - frame.light_position);
    vec3 water_normal = normalize(incident - frame.ior * direction);
    vec3 entry = o + d * ((surface.y - o.y) / d.y);
    vec3 at;
    if (!refracted_ray_meets_plane(entry, d, water_normal, hit, n, at)) return false;
    edge = at - hit;
    return true;
}

// The edge of a landed photon's cell on its own receiver towards a grid neighbour that is not
// there: another invocation's photon (across the footprint points' coarse cell's border), or
// one that landed on another receiver, was blocked or missed. It takes no search of the
// light's maps: the neighbour's ray from the light enters the light's window at
// `window_uv`, crosses the water at the height where the photon's ray entered it (`surface`),
// is refracted by the water's own normal there, and meets the photon's receiver plane (unit
// normal n through `hit`). `side` is −1 for the neighbour before the photon along the axis,
// +1 for the one after; the edge points along the axis as footprint_edges' spans do.
// Unlike light_step_edge it refracts the neighbour by its own normal, so the edge follows
// the waves' focusing, the spans that make a caustic. The points took the mirror of the span
// on the other side before, the cell's edge only where the waves do not focus: at 3 × 3, 8
// of every 9 photons lie on a border, and their hats, too short on one side and too long on
// the other, drew the coarse grid into the caustic (docs/accuracy.md, "Neighbours across the
// coarse cell's border"); inside the cell, their hats left streaks of nothing beside shadows
// ("Every missing neighbour on the photon's plane"). The height of the photon's entry rather
// than the neighbour's own (one Newton step more) moved no figure in the third decimal. False
// where the ray misses the water, meets the back of a wave or is totally reflected, or runs
// along the plane.
bool neighbour_edge_on_plane(vec3 hit, vec3 n, vec3 surface, vec2 window_uv, float side, out vec3 edge) {
    edge = vec3(0.0);
    vec3 o, d;
    light_ray_at(photon_window_ndc(window_uv), o, d);
    if (!(d.y < -1e-3)) return false;
    WaterParams w = frame_water();
    vec3 phase = frame_water_phase();
    vec3 entry = o + d * ((surface.y - o.y) / d.y);
    vec3 hg = water_height_grad(w, noise_tex, entry.xz, phase);
    vec3 at;
    if (!refracted_ray_meets_plane(entry, d, water_normal_from_grad(hg.yz), hit, n, at)) return false;
    edge = side * (at - hit);
    return true;
}

// A landed photon's receiver normal as a unit vector (Photon::receiver_normal: the one the
// cast read at the texel whose plane placed the hit).
vec3 unit_receiver_normal(Photon ph) {
    return normalize(ph.receiver_normal + 1e-6);
}

// The receiver area one pixel of the caustic target covers at `hit` (normal n, zero where
// unknown: a floor's is taken), whose camera clip w is `clip_w`.
float receiver_pixel_area(vec3 hit, vec3 n, float clip_w) {
    vec3 to_hit = hit - frame.camera_position;
    float d_view = length(to_hit);
    if (n == vec3(0.0)) n = vec3(0.0, 1.0, 0.0); // outside the map: a floor's
    float cos_view = abs(dot(n, to_hit / d_view));
    float cos_axis = clip_w / d_view;
    return pixel_world_area(d_view, cos_view, cos_axis, frame.caustic_target_size.y);
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
    // The splat spreads the photon's flux over size² pixels, each covering pixel_world_area
    // of the receiver: the density estimate of irradiance.
    float area = size * size * receiver_pixel_area(hit, n, s.clip.w);
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
