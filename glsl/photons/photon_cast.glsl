// Photon casting shared by the caustics and godrays geometry shaders (method steps 5–6):
// a photon of the light-space grid is unprojected to a world ray, intersected with the
// water surface, refracted, and intersected with the scene by Shah's image-space iteration
// against the light's receiver-position map.
#ifndef UNDERLIGHT_PHOTON_CAST_GLSL
#define UNDERLIGHT_PHOTON_CAST_GLSL
#include "frame.glsl"
#include "frame_textures.glsl"

#include "noise_texture.glsl"
// The light's receiver maps, a layer per pair (passes::shadow): layer 0 bent along flat
// water's refracted light, layer 1 (where the maps bend) more steeply
// (frame::uniforms::steep_light_axis), searched by the photons whose iteration does not
// converge in the first. One array, so that a search reads either pair in one fetch.
layout(set = 0, binding = BINDING_LIGHT_POSITION) uniform sampler2DArray light_positions;
layout(set = 0, binding = BINDING_LIGHT_NORMAL) uniform sampler2DArray light_normals;

struct Photon {
    vec3 surface;     // p_s: where it enters the water
    vec3 direction;   // r_t: refracted direction (unit)
    vec3 hit;         // p_i: where it meets the scene
    float flux;       // W carried after the surface (Fresnel transmittance applied); dropped: before it
    float travelled;  // |p_i − p_s|, m
    float cell_scale; // its grid cell's area over the even grid's (photon_density_warp; 1 unwarped)
    bool steep_map;   // its hit was found in the second, steeper maps (its receiver's normal is there)
    // Its receiver's normal as the light's map stores it at the texel whose plane placed the
    // hit (intersect_receivers), unnormalised; zero where the search found no receiver.
    vec3 receiver_normal;
    vec2 window_uv;   // where in the photon window it was cast, after the warp ([0, 1]² inside)
    // W per unit of the window's uv area that it carries (after the surface, like flux):
    // its flux over its warped cell's area, kept apart because a cell wholly outside the window
    // has none (the caustic triangles' ring, caustics_triangles.geom).
    float flux_density;
};

// Whether the pass's pipeline may warp its grid at all: false where the scene spreads this
// grid evenly (passes/caustics.rs and godrays.rs specialize it), so the warp is compiled out
// there. A branch on the frame's value alone does not skip the warp's work on llvmpipe, whose
// shaders run both sides of a branch masked (docs/performance.md, "The view's warp compiled
// out where a scene spreads its photons evenly").
layout(constant_id = 1) const bool PHOTON_WARP = true;

// Whether every photon ray falls steeply enough through the waves for Newton's search of the
// water crossing alone (water_intersect's newton_only; passes/caustics.rs and godrays.rs
// specialize it from shader_math::newton_finds_every_crossing): a directional light's rays
// all share its direction, so the scene decides it once.
layout(constant_id = 2) const bool WATER_NEWTON_ONLY = false;

// The photon grid's warp (frame::photon_density; Rust twin shader_math::photon_density_warp):
// grid position g ∈ [0, 1]² to the photon window's uv, through the inverse cumulative
// densities in the frame's uniforms: the window's v from the rows' knots, the window's u from
// the knots of the two bands of v around it, interpolated so that neighbouring photons stay
// neighbours. In mode 2 (DENSITY_WARP) the window's u and v exchange those roles, and so do
// the grid's: the survey picks the order whose mesh cells are squarer on screen. The
// caustics' warp follows the pixels that see where photons land, the godray beams' the view
// rays' length through the water above where they enter (effects.caustic_photon_density,
// godray_photon_density). The knots are read from the frame's buffer itself, not from its
// copy in `frame` (frame.glsl says why).
#ifdef PHOTON_BEAMS
#define DENSITY_WARP frame.godray_density_warp
#define DENSITY_ROWS frame_buffer.godray_density_rows
#define DENSITY_COLUMNS frame_buffer.godray_density_columns
#else
#define DENSITY_WARP frame.photon_density_warp
#define DENSITY_ROWS frame_buffer.photon_density_rows
#define DENSITY_COLUMNS frame_buffer.photon_density_columns
#endif
float density_knot_lerp_v(float g) {
    const int segments = PHOTON_DENSITY_KNOTS - 1;
    float t = clamp(g, 0.0, 1.0) * float(segments);
    int k = min(int(t), segments - 1);
    return mix(DENSITY_ROWS[k], DENSITY_ROWS[k + 1], t - float(k));
}

float density_knot_lerp_u(float g, float v) {
    const int segments = PHOTON_DENSITY_KNOTS - 1;
    float band = clamp(v * float(segments) - 0.5, 0.0, float(segments - 1));
    int j = min(int(band), segments - 2);
    float t = clamp(g, 0.0, 1.0) * float(segments);
    int k = min(int(t), segments - 1);
    int a = j * PHOTON_DENSITY_KNOTS + k, b = a + PHOTON_DENSITY_KNOTS;
    float ua = mix(DENSITY_COLUMNS[a], DENSITY_COLUMNS[a + 1], t - float(k));
    float ub = mix(DENSITY_COLUMNS[b], DENSITY_COLUMNS[b + 1], t - float(k));
    return mix(ua, ub, band - float(j));
}

// `half_cell`: half the grid's spacing along u and along v. `cell_scale`: the area of the
// photon's warped cell (its grid cell's corners through the warp, the v of its centre for the
// u) over the even grid's: the flux it carries scales with it. Measured over the cell rather
// than as the warp's derivative at its centre, so that a cell across a knot, where the slope
// changes, carries the light the mesh's triangles there cover.
vec2 photon_density_warp(vec2 g, vec2 half_cell, out float cell_scale) {
    bool exchanged = DENSITY_WARP > 1.5;
    if (exchanged) {
        g = g.yx;
        half_cell = half_cell.yx;
    }
    float v = density_knot_lerp_v(g.y);
    float v_span = density_knot_lerp_v(g.y + half_cell.y) - density_knot_lerp_v(g.y - half_cell.y);
    float u_span = density_knot_lerp_u(g.x + half_cell.x, v) - density_knot_lerp_u(g.x - half_cell.x, v);
    cell_scale = u_span * v_span / (4.0 * half_cell.x * half_cell.y);
    vec2 uv = vec2(density_knot_lerp_u(g.x, v), v);
    return exchanged ? uv.yx : uv;
}

// Texel of the first light maps (`steep`: the second) under world point p; false when p
// projects outside the map or behind the light.
bool light_texel(vec3 p, bool steep, out ivec2 texel) {
    vec4 c = frame.light_view_proj * vec4(light_map_point(p, steep), 1.0);
    if (c.w <= 0.0) return false;
    vec2 uv = c.xy / c.w * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return false;
    texel = ivec2(uv * frame.light_map_size);
    return true;
}

// The receiver (xyz, w > 0 where one) and its normal at a texel of either pair of maps.
vec4 map_receiver(ivec2 texel, bool steep) {
    return texelFetch(light_positions, ivec3(texel, steep ? 1 : 0), 0);
}

vec3 map_normal(ivec2 texel, bool steep) {
    return texelFetch(light_normals, ivec3(texel, steep ? 1 : 0), 0).xyz;
}

// The width of a map texel's beam at world point p (`steep`: the second maps'): it grows with
// distance from a point light, and under the water it is the refracted beam's.
float map_texel_size(vec3 p, bool steep) {
    float stretch = steep ? frame.steep_texel_stretch : frame.refracted_texel_stretch;
    return 2.0 * max(frame.light_half_extent.x, frame.light_half_extent.y) / frame.light_map_size
         * (frame.light_is_point > 0.0 ? length(p - frame.light_position) : 1.0)
         * (frame.light_is_point == 0.0 && p.y < frame.water_level ? stretch : 1.0);
}

// How far a photon's hit may lie off its receiver's plane: a few map texels (`texel_size`,
// map_texel_size) or 5 % of the distance `dist` it travelled, whichever is more.
float across_allowance(float texel_size, float dist) {
    return max(3.0 * texel_size, 0.05 * dist);
}

// How far point p lies off the plane of the receiver the maps store at point `receiver` with
// normal `receiver_normal` (as stored, not unit); where they store no normal, the plain
// distance to the point.
float off_receiver(vec3 p, vec3 receiver, vec3 receiver_normal) {
    vec3 off = p - receiver;
    float len_n = length(receiver_normal);
    return len_n > 0.5 ? abs(dot(off, receiver_normal / len_n)) : length(off);
}

// Converged when the estimate lies on the receiver the map stores at its texel: within a
// few map texels of that receiver's plane (a texel's world size grows with distance for a
// point light), or 5 % of the distance travelled. Within the plane the allowance is
// stretched by 1/cos of the light's incidence on the receiver, because that is how long a
// texel's footprint is there: at a 10° sun a floor texel is 5.8 texels long, and the
// iteration can only place the hit somewhere inside it. (Measuring the plain distance to
// the stored point rejected most correct hits below a 15° sun.)
bool converged(vec3 hit, vec3 receiver, vec3 receiver_normal, vec3 light_to_hit, float dist, bool steep) {
    float texel_size = map_texel_size(hit, steep);
    float across_allowed = across_allowance(texel_size, dist);
    float across = off_receiver(hit, receiver, receiver_normal);
    float len_n = length(receiver_normal);
    if (!(len_n > 0.5)) return across <= across_allowed; // no normal stored: plain distance
    vec3 n = receiver_normal / len_n;
    vec3 off = hit - receiver;
    float along = length(off - dot(off, n) * n);
    // 0.01 bounds the stretch at 100 (a receiver lit within 0.6° of edge-on).
    float facing = max(abs(dot(n, light_to_hit)), 0.01);
    return across <= across_allowed && along <= max(3.0 * texel_size / facing, 0.05 * dist);
}

// Whether a photon could land at world point p: p lies on the plane of a receiver that the
// first light maps store near p's texel. No photon's light belongs where this fails: in the
// shadow of a receiver nearer the light (a shelf over a wall, a pillar beside the floor), or
// on a face the maps never see. The footprint points' hats, which reach a whole span past
// their photon, are held to it (photon_visibility.frag), so that a hat beside a shadow's edge
// stops near it.
//
// The maps hold what flat water's refracted light meets; the waves turn each ray by up to
// water_deviation_bound, so a shadow's edge wanders by that angle times the way from the edge's
// caster to p (under the water, at most the way from the surface). So besides p's own texel
// the test reads the four that far from it along the map's axes (at least the next ones, for
// the texels' own steps), and p lies on a receiver's plane within the allowance a photon's
// hit has across its receiver (across_allowance). The second, steeper maps are not read: the light
// they place lies within that reach of the first maps' (they bend by about the waves' tilt),
// and each texel read costs: the test cost 25 ms of the tank's caustic pass at 800×800 on
// lavapipe, of which the four reads around p were half, when every pixel read them
// (docs/accuracy.md, "Hats held out of the shadows"); since, only a pixel its own texel does
// not place pays for them and for the waves' reach.
bool light_could_land(vec3 p) {
    ivec2 texel;
    if (!light_texel(p, false, texel)) return false;
    vec3 direction = light_map_direction(p, false);
    float below = max(frame.water_level - p.y, 0.0) / max(-direction.y, 1e-3);
    float texel_size = map_texel_size(p, false);
    float across_allowed = across_allowance(texel_size, below);
    vec4 caster = map_receiver(texel, false);
    // Most of what the light reaches lies on the receiver its own texel stores: tested first,
    // so that only the rest pays for the waves' reach (water_deviation_bound: five
    // refractions) and the four texels that far away.
    if (caster.w > 0.0 && off_receiver(p, caster.xyz, map_normal(texel, false)) <= across_allowed) return true;
    float way = caster.w > 0.0 ? min(below, length(p - caster.xyz)) : below;
    // The light's direction before the water: a point light's towards p, which it only nears.
    vec3 falling = frame.light_is_point > 0.0 ? normalize(p - frame.light_position) : frame.light_axis;
    float deviation = water_deviation_bound(frame_water(), falling);
    int reach = int(clamp(round(deviation * way / texel_size), 1.0, frame.light_map_size));
    ivec2 last = ivec2(frame.light_map_size) - 1;
    const ivec2 around[4] = ivec2[4](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
    for (int k = 0; k < 4; ++k) {
        ivec2 t = clamp(texel + reach * around[k], ivec2(0), last);
        vec4 receiver = map_receiver(t, false);
        if (receiver.w > 0.0 && off_receiver(p, receiver.xyz, map_normal(t, false)) <= across_allowed) return true;
    }
    return false;
}

// Moves the iteration's estimate `hit` (`dist` along the refracted ray from `ps`) onto the
// plane of the receiver stored at its texel (point `receiver`, normal `receiver_normal`)
// where that point still lies on the same receiver; leaves it where the plane is missing or
// the ray runs along it.
void onto_receiver_plane(vec3 ps, vec3 rt, vec3 receiver, vec3 receiver_normal, vec3 light_to_hit, bool steep,
                         inout vec3 hit, inout float dist) {
    float len_n = length(receiver_normal);
    if (!(len_n > 0.5)) return;
    vec3 n = receiver_normal / len_n;
    float denom = dot(rt, n);
    if (abs(denom) <= 1e-3) return;
    float t = dot(receiver - ps, n) / denom;
    vec3 on_plane = ps + t * rt;
    if (t > 0.0 && converged(on_plane, receiver, receiver_normal, light_to_hit, t, steep)) {
        hit = on_plane;
        dist = t;
    }
}

// The image-space iteration stops once its residual is this small a share of the distance
// (Rust twin: shader_math::ITERATION_RESIDUAL).
const float ITERATION_RESIDUAL = 1e-5;

// Why cast_photon dropped its photon (PHOTON_LANDED when it did not), for the flux budget
// (`render --flux-budget`, src/flux_budget.rs, whose `DropReason` lists the same codes).
const int PHOTON_LANDED = 0;
const int PHOTON_MISSES_WATER = 1;
const int PHOTON_OUTSIDE_WATER = 2;
const int PHOTON_BLOCKED_ABOVE = 3;
const int PHOTON_BACK_OF_WAVE = 4;
const int PHOTON_TOTAL_REFLECTION = 5;
const int PHOTON_LEAVES_MAP = 6;
const int PHOTON_NOT_CONVERGED = 7;
const int PHOTON_ABOVE_WATER = 8;
const int PHOTON_NOT_FINITE = 9;
// A landed footprint point's record code where the device's largest point clamped its
// footprint (caustics.geom, FOOTPRINT_POINTS with PHOTON_DEBUG; flux_budget::FOOTPRINT_CLAMPED);
// a landed photon's is otherwise 1.
const float PHOTON_RECORD_FOOTPRINT_CLAMPED = 3.0;
int photon_fate = PHOTON_LANDED; // set by every cast_photon

// The light's ray to a photon's surface point: from `origin` along `direction`, meeting the
// water `distance` from its origin (cast_photon).
struct LightRay {
    vec3 origin;
    vec3 direction;
    float distance;
};

// Where the refracted ray from ps along rt meets the receivers the first light maps hold
// (`steep`: the second maps): PHOTON_LANDED with the hit and its distance, PHOTON_LEAVES_MAP,
// or PHOTON_NOT_CONVERGED with the last estimate; PHOTON_BLOCKED_ABOVE, or `surface_fate`
// where that is not PHOTON_LANDED, before any search (below).
//
// In the first maps the receiver stored under ps, which the first guess reads, is also the
// light's first receiver along its ray to the water: nearer the light than the water, it
// blocks the photon before the water (a deck, a wall above it: the water mask, derived), and
// the search returns PHOTON_BLOCKED_ABOVE. Tested here rather than before the refraction, so
// that the map is read once for both: a read of its own cost about 1.5 ms of paper-800's
// caustic pass on lavapipe (docs/performance.md, "The light map read once where the cast read
// it twice").
// `surface_fate`: where the photon was lost at the surface (PHOTON_BACK_OF_WAVE,
// PHOTON_TOTAL_REFLECTION; else PHOTON_LANDED), returned after the blocked test, which it
// yields to: a photon the deck shades never meets the wave.
//
// Shah's iteration: guess d, project p_s + d·r_t into the light's map, and take the stored
// receiver's distance F(d) from p_s as the next guess. The first guess assumes the
// receiver lies as deep below p_s as the one straight along the unrefracted ray (Shah
// takes that one's distance, which at a low sun is several times too far, and its
// map position may hold nothing). Shah's update d ← F(d) is a fixed-point iteration;
// it diverges where |F'| > 1, which for a horizontal receiver happens once the sun is
// below about 18° (F' = 1 − cos θt·cos(θi − θt)/sin e). From the second step on, the
// update is therefore a secant step on the same residual g(d) = F(d) − d, which uses the
// same one map fetch per step and converges there too. Where g is constant across a map
// texel the secant step equals Shah's.
// Where the map holds nothing straight along the light ray (at a low sun that ray leaves
// the receivers long before the refracted one would), the guess is the scene's lowest
// point: exact for a flat floor, and the secant steps correct it for anything above.
int intersect_receivers(vec3 ps, vec3 rt, bool steep, LightRay light, int surface_fate, out vec3 hit,
                        out float dist, out vec3 normal) {
    normal = vec3(0.0);
    float bottom = ps.y - frame.scene_lowest_y;
    dist = bottom > 1e-3 ? bottom / max(-rt.y, 1e-3) : 1.0;
    hit = ps;
    ivec2 texel;
    if (light_texel(ps, steep, texel)) {
        vec4 below = map_receiver(texel, steep);
        if (!steep && below.w > 0.0 && dot(below.xyz - light.origin, light.direction) < light.distance - 1e-3)
            return PHOTON_BLOCKED_ABOVE;
        float depth = ps.y - below.y;
        if (below.w > 0.0) dist = depth > 1e-3 ? depth / max(-rt.y, 1e-3) : max(length(below.xyz - ps), 1e-3);
    }
    if (surface_fate != PHOTON_LANDED) return surface_fate;
    float prev_dist = 0.0, prev_g = 0.0;
    bool have_prev = false;
    ivec2 prev_texel = ivec2(0);
    vec4 r = vec4(0.0), prev_r = vec4(0.0);
    int iterations = int(frame.iterations);
    // Each pass reads the map at the estimate; the last (i == iterations) only reads, so that
    // the receiver under the final estimate is always one the loop has read: a photon that
    // converges keeps its last read instead of projecting and reading its texel again.
    for (int i = 0; i <= iterations; ++i) {
        // A step that leaves the map or its receivers ends the iteration at the last estimate
        // that had one (the convergence test below judges it): at a grazing sun a texel
        // stretches over a third of a metre of floor, and a step from an exact first guess
        // towards the texel's centre can leave the receivers. With no estimate yet, or off
        // the map on the final, read-only pass, the photon hits nothing the map knows of and
        // is dropped.
        bool inside = light_texel(ps + dist * rt, steep, texel);
        r = inside ? map_receiver(texel, steep) : vec4(0.0);
        if (r.w <= 0.0) {
            if (!have_prev || i == iterations) return PHOTON_LEAVES_MAP;
            dist = prev_dist;
            texel = prev_texel;
            r = prev_r;
            break;
        }
        if (i == iterations) break;
        float g = length(r.xyz - ps) - dist;
        // At the fixed point already (within 10 µm per metre): a further step would move the
        // estimate by g and fetch the same texel again. Stopping saves the remaining fetches
        // wherever the whole SIMD group has converged.
        if (abs(g) <= ITERATION_RESIDUAL * max(dist, 1.0)) break;
        float next = dist + g;
        if (have_prev && abs(g - prev_g) > 1e-6 * max(dist, 1.0)) {
            next = dist - g * (dist - prev_dist) / (g - prev_g);
        }
        prev_dist = dist; prev_g = g; prev_texel = texel; prev_r = r; have_prev = true;
        dist = max(next, 1e-3);
    }
    hit = ps + dist * rt;
    vec3 rn = map_normal(texel, steep);
    normal = rn;
    vec3 to_hit = light_map_direction(hit, steep);
    // The iteration ends on the right texel but anywhere inside it: the stored receiver is the
    // one at the texel's centre, and the estimate's error is up to a texel, several mm on the
    // built-in scenes' floors against 13 mm between photons. The caustic estimators measure
    // areas between neighbouring hits, so that error was noise in the irradiance (tank
    // triangles: relative RMSE 0.66 from the texel, 0.61 on the plane). The receiver's plane at the texel
    // (its stored point and normal) gives the exact hit on planar receivers.
    onto_receiver_plane(ps, rt, r.xyz, rn, to_hit, steep, hit, dist);
    return converged(hit, r.xyz, rn, to_hit, dist, steep) ? PHOTON_LANDED : PHOTON_NOT_CONVERGED;
}

// The light's NDC at a point of the photon window (`window_uv`, after the warp: [0, 1]²
// inside; Photon::window_uv).
vec2 photon_window_ndc(vec2 window_uv) {
    return (frame.photon_window_min + window_uv * frame.photon_window_size) * 2.0 - 1.0;
}

// The light's ray through its NDC `ndc`: from the light's near plane, along a unit direction.
// cast_photon casts a photon along it; the caustic estimators' cell edges
// (caustic_splat.glsl) cast a grid neighbour's without the neighbour's search.
void light_ray_at(vec2 ndc, out vec3 origin, out vec3 direction) {
    vec4 near_point = frame.light_inv_view_proj * vec4(ndc, 0.0, 1.0);
    vec4 far_point = frame.light_inv_view_proj * vec4(ndc, 1.0, 1.0);
    origin = near_point.xyz / near_point.w;
    direction = normalize(far_point.xyz / far_point.w - origin);
}

// Casts the photon at light-space position uv ∈ [0,1]² of a grid with photons_per_axis.x ×
// photons_per_axis.y photons (square but for the caustic triangles' grid, whose aspect
// follows the view: caustics_triangles.geom). Returns false for photons that never enter the
// water, are blocked before it, meet the back of a wave or are totally reflected, leave the
// light's map, hit nothing, land above the water, are not finite, or whose iteration does not
// converge (but for the godray beams, PHOTON_BEAMS, which are drawn to their last estimate):
// those are dropped, never splatted. `photon_fate` says which.
bool cast_photon(vec2 uv, vec2 photons_per_axis, out Photon ph) {
    ph.surface = vec3(0.0); ph.direction = vec3(0.0); ph.hit = vec3(0.0); ph.flux = 0.0; ph.travelled = 0.0;
    ph.cell_scale = 1.0;
    ph.steep_map = false;
    ph.receiver_normal = vec3(0.0);
    ph.window_uv = vec2(0.0);
    ph.flux_density = 0.0;
    photon_fate = PHOTON_LANDED;
    // The grid covers the water's footprint in the light's window, not the whole window.
    // Shifted by this frame's sub-cell offset (effects.photon_jitter; zero without it), and
    // warped to where the view needs photons (effects.caustic_photon_density and
    // godray_photon_density; the identity without).
    uv += frame.photon_jitter / photons_per_axis;
    if (PHOTON_WARP && DENSITY_WARP > 0.0) uv = photon_density_warp(uv, 0.5 / photons_per_axis, ph.cell_scale);
    ph.window_uv = uv;
    vec3 o, d;
    light_ray_at(photon_window_ndc(uv), o, d);
    // Flux of this photon before the surface (what a dropped photon's record carries): the
    // light's power through its share of the photon window. Directional: E⊥ × window area
    // / N². Point: I × the photon's solid angle (tangent-plane cell area × cos³ of its angle
    // to the light's axis). The window is photon_window_size of the map's, so N² photons
    // share that fraction of it.
    float n2 = photons_per_axis.x * photons_per_axis.y / (frame.photon_window_size.x * frame.photon_window_size.y);
    float flux;
    if (frame.light_is_point == 0.0) {
        flux = frame.light_strength * 4.0 * frame.light_half_extent.x * frame.light_half_extent.y / n2;
    } else {
        float c = max(dot(d, frame.light_axis), 0.0);
        flux = frame.light_strength * 4.0 * frame.light_half_extent.x * frame.light_half_extent.y / n2 * c * c * c;
    }
    // An even cell is 1 / (photons_per_axis.x · photons_per_axis.y) of the window's uv area.
    ph.flux_density = flux * photons_per_axis.x * photons_per_axis.y;
    flux *= ph.cell_scale;
    ph.flux = flux;

    WaterParams w = frame_water();
    vec3 hg; // the surface's height and gradient where the ray crosses it (its normal below)
    float t = water_intersect(w, noise_tex, o, d, frame_water_phase(), WATER_NEWTON_ONLY, hg);
    if (!(t > 0.0)) { photon_fate = PHOTON_MISSES_WATER; return false; }
    vec3 ps = o + t * d;
    if (!water_covers(w, ps.xz)) { photon_fate = PHOTON_OUTSIDE_WATER; return false; }
    vec3 n = water_normal_from_grad(hg.yz);
    float cos_i = dot(-d, n);
    vec3 rt = refract(d, n, 1.0 / w.ior);
    // Lost at the surface: the back of a steep wave, or totally reflected. Reported by the
    // first maps' search once it has read whether the photon is blocked before the water
    // (intersect_receivers). Such a photon has no refracted ray: the search gets the light's
    // direction instead, which only its first guess uses.
    int surface_fate = cos_i <= 0.0 ? PHOTON_BACK_OF_WAVE : dot(rt, rt) == 0.0 ? PHOTON_TOTAL_REFLECTION : PHOTON_LANDED;
    rt = surface_fate == PHOTON_LANDED ? normalize(rt) : d;
    LightRay light = LightRay(o, d, t);

    // The first maps, then, for a photon they cannot place, the second (steeper) ones. A
    // loop over the two pairs rather than two calls, so that the search is compiled once: on
    // lavapipe the second inlined copy, though few photons run it, cost 10-15 % of the
    // paper-800 caustic pass (docs/performance.md, "One copy of the search"). Where the
    // second maps place nothing either, the first maps' outcome stands.
    vec3 hit = ps;
    float dist = 0.0;
    int fate = PHOTON_LEAVES_MAP;
    int map_pairs = frame.steep_light_axis.y < -1e-3 ? 2 : 1;
    for (int pair = 0; pair < map_pairs; ++pair) {
        bool steep = pair == 1;
        vec3 pair_hit, pair_normal;
        float pair_dist;
        int pair_fate = intersect_receivers(ps, rt, steep, light, surface_fate, pair_hit, pair_dist, pair_normal);
        if (!steep || pair_fate == PHOTON_LANDED) {
            fate = pair_fate;
            hit = pair_hit;
            ph.receiver_normal = pair_normal;
            dist = pair_dist;
            ph.steep_map = steep;
        }
        // Placed, or lost before the search (blocked, or at the surface): no second pair.
        if (fate != PHOTON_LEAVES_MAP && fate != PHOTON_NOT_CONVERGED) break;
    }
    // The outcome, without a return per case: on lavapipe each early return masks the rest of
    // the shader lane by lane. A photon lost before the search (blocked, or at the surface)
    // keeps no surface point; the others keep it and their refracted direction, also where
    // dropped below: the footprint beams measure their cross-sections from their
    // neighbours' refracted rays (godrays_footprint.geom). A dropped photon keeps the flux it
    // carried towards the water (the flux budget's records).
    bool lost_before_search = fate == PHOTON_BLOCKED_ABOVE || fate == PHOTON_BACK_OF_WAVE || fate == PHOTON_TOTAL_REFLECTION;
    ph.surface = lost_before_search ? vec3(0.0) : ps;
    ph.direction = lost_before_search ? vec3(0.0) : rt;
#ifdef PHOTON_BEAMS
    bool placed = fate == PHOTON_LANDED || fate == PHOTON_NOT_CONVERGED; // a beam is drawn to its last estimate
#else
    bool placed = fate == PHOTON_LANDED;
#endif
    bool above_water = hit.y > w.level + abs(w.amplitude) + abs(w.noise_amplitude);
    bool drawn = placed && !above_water;
    float transmitted = fresnel_transmittance(cos_i, w.ior);
    ph.hit = drawn ? hit : vec3(0.0);
    ph.flux = drawn ? flux * transmitted : flux;
    ph.flux_density *= drawn ? transmitted : 1.0;
    ph.travelled = drawn ? dist : 0.0;
    bool finite = !(any(isnan(hit)) || any(isinf(hit)) || isnan(ph.flux) || isinf(ph.flux));
    photon_fate = !placed ? fate
                : above_water ? PHOTON_ABOVE_WATER
                : fate == PHOTON_LANDED && !finite ? PHOTON_NOT_FINITE
                : fate;
    return drawn && finite;
}

// The photon of a square grid of `photons_per_axis`² photons.
bool cast_photon(vec2 uv, float photons_per_axis, out Photon ph) {
    return cast_photon(uv, vec2(photons_per_axis), ph);
}
#endif
