// Shared shader math. Its Rust twin is src/shader_math.rs: change both together (the tests
// compare GPU output with the twin).
#ifndef UNDERLIGHT_SHADER_MATH_GLSL
#define UNDERLIGHT_SHADER_MATH_GLSL

const float PI = 3.14159265358979;

// MAX_SUBDIVISION, TRIANGLE_MAX_SUBDIVISION, FOOTPRINT_MAX_SUBDIVISION, GODRAY_MAX_SUBDIVISION
// and GODRAY_FOOTPRINT_MAX_SUBDIVISION, the largest per-axis photon subdivision a geometry-shader
// invocation emits, are macros from shader_abi::limits
// (their one definition). max_vertices must be a compile-time literal, so each shader is
// compiled for its bound and the actual factor is a specialization constant the driver
// unrolls at pipeline creation.

// Position in [0,1]^2 (light clip space mapped to texture space) of photon `sub` of coarse
// cell `cell` in a `grid` photon grid subdivided `subdiv`×`subdiv`: the centres of the
// sub-cells, so the photons of all cells tile the grid evenly.
vec2 photon_grid_uv(uvec2 cell, uvec2 sub, uint subdiv, uvec2 grid) {
    return (vec2(cell) + (vec2(sub) + 0.5) / float(subdiv)) / vec2(grid);
}

// The same position for photon number `index` when photons are numbered in the geometry
// shader's emission order (cell by cell in rows, within a cell row by row): the paths without
// an amplification stage (one vertex or one invocation per photon) use it, so they visit
// the photons, and blend their splats, in the same order.
vec2 photon_index_uv(uint index, uint subdiv, uint grid) {
    uint per_cell = subdiv * subdiv;
    uint cell = index / per_cell;
    uint k = index % per_cell;
    return photon_grid_uv(uvec2(cell % grid, cell / grid), uvec2(k % subdiv, k / subdiv), subdiv, uvec2(grid));
}

// Gradient of a small sum of travelling sine waves over [0,1]^2. The foundation's demo
// displaces photons by it, which focuses them into caustic-like lines.
vec2 demo_wave_gradient(vec2 uv, float t) {
    vec2 k1 = vec2(7.0, 3.0) * 2.0 * PI;
    vec2 k2 = vec2(-4.0, 9.0) * 2.0 * PI;
    return k1 * cos(dot(k1, uv) + 1.3 * t) / dot(k1, k1)
         + k2 * cos(dot(k2, uv) + 0.9 * t) / dot(k2, k2);
}


// ---------------------------------------------------------------------------------------
// Water surface. y is up; the mean plane is y = level. Rust twin: shader_math::water_*.

const int WATER_CIRCULAR_COSINE = 0;   // circular cosine + small noise
const int WATER_AXIS_COSINE_NOISE = 1; // cosine along x + strong noise

struct WaterParams {
    int model;
    float level;
    float amplitude;
    float wavelength;
    float speed;
    float noise_amplitude;
    float noise_scale; // metres per noise tile
    float ior;
    vec2 center;
    vec2 extent_min;
    vec2 extent_max;
};

// The noise texture holds (value, d/du, d/dv) of tileable gradient noise; it is sampled
// with explicit bilinear weights from texelFetch so the CPU twin reproduces it bit for bit
// up to float rounding (hardware filtering uses few fractional bits on many GPUs).
vec3 sample_noise(sampler2D tex, vec2 uv) {
    ivec2 size = textureSize(tex, 0);
    // Wrap first: GLSL's % is undefined for negative operands, and a texelFetch outside
    // the texture is undefined behaviour (lavapipe crashes on it).
    vec2 p = fract(uv) * vec2(size) - 0.5;
    vec2 f = p - floor(p);
    ivec2 a = ivec2(floor(p));                     // in [-1, size - 1]
    ivec2 b = a + 1;                               // in [0, size]
    a = ivec2(mix(a, a + size, lessThan(a, ivec2(0))));
    b = ivec2(mix(b, b - size, greaterThanEqual(b, size)));
    a = clamp(a, ivec2(0), size - 1);              // NaN input: stay inside
    b = clamp(b, ivec2(0), size - 1);
    vec3 t00 = texelFetch(tex, ivec2(a.x, a.y), 0).xyz;
    vec3 t10 = texelFetch(tex, ivec2(b.x, a.y), 0).xyz;
    vec3 t01 = texelFetch(tex, ivec2(a.x, b.y), 0).xyz;
    vec3 t11 = texelFetch(tex, ivec2(b.x, b.y), 0).xyz;
    return mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
}

// The water's animation at one time, `phase`: x, the waves' phase k·speed·t reduced modulo
// 2π; yz, the noise's drift (0.6, 0.8)·speed·t / noise_scale in tiles, reduced modulo 1.
// Both are reduced on the CPU in double precision (shader_math::water_phase), so the surface
// keeps its shape at late times: in single precision, the drift of the noise alone would
// quantise positions to millimetres after a day.

// Where the noise is read for world point xz: it drifts with the wave speed.
vec2 water_noise_uv(WaterParams w, vec2 xz, vec2 drift) {
    return xz / w.noise_scale + drift;
}

// Height above the mean plane (x) and its gradient d/dx, d/dz (yz) at xz.
vec3 water_height_grad(WaterParams w, sampler2D noise, vec2 xz, vec3 phase) {
    float k = 2.0 * PI / w.wavelength;
    float phase_t = phase.x;
    vec3 hg = vec3(0.0);
    if (w.model == WATER_CIRCULAR_COSINE) {
        vec2 d = xz - w.center;
        float r = length(d);
        float ph = k * r - phase_t;
        hg.x = w.amplitude * cos(ph);
        vec2 dir = r > 1e-6 ? d / r : vec2(0.0);
        hg.yz = -w.amplitude * k * sin(ph) * dir;
    } else {
        float ph = k * xz.x - phase_t;
        hg.x = w.amplitude * cos(ph);
        hg.yz = vec2(-w.amplitude * k * sin(ph), 0.0);
    }
    vec3 n = sample_noise(noise, water_noise_uv(w, xz, phase.yz));
    hg.x += w.noise_amplitude * n.x;
    hg.yz += (w.noise_amplitude / w.noise_scale) * n.yz;
    return hg;
}

vec3 water_normal_from_grad(vec2 grad) {
    return normalize(vec3(-grad.x, 1.0, -grad.y));
}

bool water_covers(WaterParams w, vec2 xz) {
    return all(greaterThanEqual(xz, w.extent_min)) && all(lessThanEqual(xz, w.extent_max));
}

// Intersects a downward ray with the surface. The surface lies in the slab level ± (amplitude
// + noise amplitude) (the noise's values stay within ±1). The ray is marched through that
// slab to the first step that ends below the surface. Steps are a quarter of the shortest
// wave feature along the ray's horizontal travel, so a step passes at most one crest (8 at
// least, WATER_MAX_MARCH_STEPS at most). The crossing is refined inside that step by
// regula falsi (Illinois). A bracketed search converges however grazing the ray. Fixed-point
// iteration on the mean plane, by contrast, diverges once the slope along the ray exceeds the
// ray's steepness: at 10° sun elevation, already for waves of slope 0.2. A result not within
// 1 % of the waves' height of the surface (steps too coarse for absurdly steep waves) counts
// as a miss. Returns t (< 0: no hit: the ray does not go down, starts below the slab, or the
// search did not converge).
const int WATER_MAX_MARCH_STEPS = 64;
const int WATER_REFINE_STEPS = 8;
// The refinement stops once a point lies this share of the waves' height from the surface
// (5 µm on the tank's 5 cm): the remaining steps could move the hit by no more than that.
const float WATER_REFINE_RESIDUAL = 1e-4;
// Shortest noise feature, in noise tiles: the octaves have 8, 16 and 32 cells per tile and
// most of their height is in the first two.
const float WATER_NOISE_FEATURE = 1.0 / 16.0;

// The steepest slope of the noise texture's surface per unit of noise amplitude, in tiles
// (Rust twin: shader_math::WATER_NOISE_SLOPE, whose test measures it on the texture: 28.04
// for the stored derivatives, 27.65 between neighbouring texels' values).
const float WATER_NOISE_SLOPE = 28.1;

// The surface's steepest slope: the waves' amplitude × wavenumber, plus the noise's.
float water_slope_bound(WaterParams w) {
    return abs(w.amplitude) * 2.0 * PI / w.wavelength + abs(w.noise_amplitude) / w.noise_scale * WATER_NOISE_SLOPE;
}

// The most the waves turn a ray falling along unit direction d away from its refraction in
// flat water, rad (Rust twin: shader_math::water_deviation_bound): the surface's normal tilts
// by up to atan(water_slope_bound), and of the normals tilted that far the ray turns most under
// those tilted towards its own horizontal direction, away from it or across it (the twin's
// test samples every azimuth). About (1 − 1/ior) of the tilt under a high sun, up to three
// times that under a low one; a right angle where the waves are steep enough to meet the ray
// edge-on (then a ray may enter along the surface).
float water_deviation_bound(WaterParams w, vec3 d) {
    float tilt = atan(water_slope_bound(w));
    if (tilt >= atan(-d.y, length(d.xz))) return 0.5 * PI;
    float eta = 1.0 / w.ior;
    vec3 up = vec3(0.0, 1.0, 0.0);
    vec3 flat_refracted = refract(d, up, eta);
    vec2 h = dot(d.xz, d.xz) > 1e-12 ? normalize(d.xz) : vec2(1.0, 0.0);
    vec3 towards = vec3(h.x, 0.0, h.y), across = vec3(-h.y, 0.0, h.x);
    vec3 tilted[4] = vec3[4](towards, -towards, across, -across);
    float most = 0.0;
    for (int k = 0; k < 4; ++k) {
        vec3 r = normalize(refract(d, cos(tilt) * up + sin(tilt) * tilted[k], eta));
        most = max(most, acos(clamp(dot(r, flat_refracted), -1.0, 1.0)));
    }
    return most;
}

// The search's stages, in the order a ray takes them: the slab's top, its floor, the march's
// steps, the refinement's steps; or, for a ray that falls steeply enough, Newton's steps.
const int WATER_AT_TOP = 0;
const int WATER_AT_FLOOR = 1;
const int WATER_MARCHING = 2;
const int WATER_REFINING = 3;
const int WATER_NEWTON = 4;

// Where the ray falls more than twice as steeply as the surface can rise along it
// (water_slope_bound), its height above the surface falls through the slab by at least half
// the ray's fall per unit of t: there is one crossing, and Newton's method on that height
// finds it from the mean plane's crossing in two or three evaluations, where the march and
// its refinement take about ten. Each Newton step stays inside the bracket the evaluations
// so far leave, and bisects it where it would leave it. Every other ray is marched.
//
// The two searches share one loop and one evaluation of the surface, each lane taking its
// own stage's step: llvmpipe runs both sides of a branch for every lane, so a branch to a
// Newton search beside the march cost as much as the march (docs/performance.md, "One copy
// of the search"), while a loop stops once no lane needs another pass. The Rust twin,
// shader_math::water_intersect, makes the same evaluations as two separate searches.
// `height_grad`: the surface's height and gradient at the crossing, for its normal.
//
// `newton_only`: every ray the caller casts falls steeply enough for Newton's method (a
// directional light's photons, shader_math::newton_finds_every_crossing), so only Newton's
// search is compiled where the caller passes it as a specialization constant: the shared
// loop's other stages, run masked, cost llvmpipe 6-9 ms of paper-800's caustic pass
// (docs/performance.md, "Newton's search alone where every photon takes it"). A ray that
// starts inside the waves' slab but above the surface meets it once all the same; one that
// starts under it, which the light's frame never casts, is a miss there.

// One Newton step on the ray's height f above the surface at t (hg: the surface's height
// and gradient there): the bracket [ta, tb] narrowed by f's sign, and t moved to Newton's
// estimate, or to the bracket's middle where that would leave it.
void water_newton_step(float f, vec3 hg, vec3 d, inout float ta, inout float tb, inout float t) {
    if (f > 0.0) ta = t; else tb = t;
    float next = t - f / (d.y - dot(hg.yz, d.xz));
    t = next > ta && next < tb ? next : 0.5 * (ta + tb);
}

// The search's answer: its evaluated point nearest the surface, a miss where that is not
// within 1 % of the waves' height of it.
float water_crossing_found(float best_t, float best_f, vec3 best_hg, float bound, out vec3 height_grad) {
    height_grad = vec3(0.0);
    if (!(best_f <= 0.01 * bound + 1e-4)) return -1.0;
    height_grad = best_hg;
    return best_t;
}

// Newton's search alone, from the mean plane's crossing, inside the slab [t_top, t_bottom].
float water_newton_crossing(WaterParams w, sampler2D noise, vec3 o, vec3 d, vec3 phase, float t_top, float t_bottom,
                            float bound, out vec3 height_grad) {
    float ta = t_top, tb = t_bottom, best_t = -1.0, best_f = 1e30;
    vec3 best_hg = vec3(0.0);
    float t = clamp((w.level - o.y) / d.y, t_top, t_bottom);
    for (int refinement = 0; refinement <= WATER_REFINE_STEPS; ++refinement) {
        vec3 p = o + t * d;
        vec3 hg = water_height_grad(w, noise, p.xz, phase);
        float f = p.y - w.level - hg.x;
        if (abs(f) < best_f) { best_t = t; best_f = abs(f); best_hg = hg; }
        if (best_f <= WATER_REFINE_RESIDUAL * bound || refinement == WATER_REFINE_STEPS) break;
        water_newton_step(f, hg, d, ta, tb, t);
    }
    return water_crossing_found(best_t, best_f, best_hg, bound, height_grad);
}

float water_intersect(WaterParams w, sampler2D noise, vec3 o, vec3 d, vec3 phase, bool newton_only,
                      out vec3 height_grad) {
    height_grad = vec3(0.0);
    if (d.y >= -1e-6) return -1.0;
    float bound = abs(w.amplitude) + abs(w.noise_amplitude);
    float t_top = max((w.level + bound - o.y) / d.y, 0.0);
    float t_bottom = (w.level - bound - o.y) / d.y;
    if (t_bottom < t_top) return -1.0;
    if (bound == 0.0) return t_bottom; // flat: the mean plane
    if (newton_only) return water_newton_crossing(w, noise, o, d, phase, t_top, t_bottom, bound, height_grad);
    float feature = min(w.amplitude > 0.0 ? w.wavelength : 1e30,
                        w.noise_amplitude > 0.0 ? w.noise_scale * WATER_NOISE_FEATURE : 1e30);
    float horizontal = (t_bottom - t_top) * length(d.xz);
    int steps = int(clamp(ceil(4.0 * horizontal / feature), 8.0, float(WATER_MAX_MARCH_STEPS)));
    float dt = (t_bottom - t_top) / float(steps);
    float ta = t_top, fa = 0.0, tb = t_bottom, fb = 0.0, best_t = -1.0, best_f = 1e30;
    vec3 hg_b = vec3(0.0), best_hg = vec3(0.0);
    bool monotone = o.y > w.level + bound && water_slope_bound(w) * length(d.xz) <= -0.5 * d.y;
    int stage = monotone ? WATER_NEWTON : WATER_AT_TOP, march_step = 1, refinement = 0, kept = 0;
    float t = monotone ? clamp((w.level - o.y) / d.y, t_top, t_bottom) : t_top;
    for (int evaluation = 0; evaluation < WATER_MAX_MARCH_STEPS + WATER_REFINE_STEPS + 2; ++evaluation) {
        vec3 p = o + t * d;
        vec3 hg = water_height_grad(w, noise, p.xz, phase);
        float f = p.y - w.level - hg.x;
        if (stage == WATER_NEWTON) {
            if (abs(f) < best_f) { best_t = t; best_f = abs(f); best_hg = hg; }
            if (best_f <= WATER_REFINE_RESIDUAL * bound || refinement == WATER_REFINE_STEPS) break;
            water_newton_step(f, hg, d, ta, tb, t);
            ++refinement;
            continue;
        }
        if (stage == WATER_AT_TOP) {
            if (f <= 0.0) { height_grad = hg; return t; } // starts at or below the surface
            fa = f;
            stage = WATER_AT_FLOOR;
            t = t_bottom;
            continue;
        }
        if (stage == WATER_AT_FLOOR) {
            fb = f; hg_b = hg;
            stage = WATER_MARCHING;
        } else if (stage == WATER_MARCHING) {
            if (f <= 0.0) { tb = t; fb = f; hg_b = hg; march_step = steps; }
            else { ta = t; fa = f; ++march_step; }
        } else {
            // Illinois: halve the value kept at an end that survives twice, so both ends move.
            // The answer is the evaluated point nearest the surface, not the last estimate:
            // where the surface runs almost along the ray (a grazing sun over noise), Illinois
            // can stall beside a near-tangent point it already passed.
            if (abs(f) < best_f) { best_t = t; best_f = abs(f); best_hg = hg; }
            if (best_f <= WATER_REFINE_RESIDUAL * bound || refinement == WATER_REFINE_STEPS) break;
            if (f > 0.0) { ta = t; fa = f; if (kept == -1) fb *= 0.5; kept = -1; }
            else { tb = t; fb = f; if (kept == 1) fa *= 0.5; kept = 1; }
            ++refinement;
        }
        if (stage == WATER_MARCHING) {
            if (march_step < steps) { t = t_top + float(march_step) * dt; continue; }
            // The slab's floor lies at or below the surface, so a value above zero there is
            // rounding: a ray kilometres long against a slab micrometres thin (a grazing ray
            // over nearly flat water) cannot resolve it. The floor is then the hit, held to
            // the tolerance below.
            if (fb > 0.0) {
                if (!(fb <= 0.01 * bound + 1e-4)) return -1.0;
                height_grad = hg_b;
                return tb;
            }
            stage = WATER_REFINING;
            best_t = tb; best_f = abs(fb); best_hg = hg_b;
        }
        t = ta + (tb - ta) * fa / (fa - fb);
    }
    return water_crossing_found(best_t, best_f, best_hg, bound, height_grad);
}

// Fresnel transmittance for unpolarised light from a medium of index 1 into index n,
// at incidence cosine cos_i (the full equations, not Schlick).
float fresnel_transmittance(float cos_i, float n) {
    cos_i = clamp(cos_i, 0.0, 1.0);
    float sin_t2 = (1.0 - cos_i * cos_i) / (n * n);
    if (sin_t2 >= 1.0) return 0.0;
    float cos_t = sqrt(1.0 - sin_t2);
    float rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    float rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    return 1.0 - 0.5 * (rs * rs + rp * rp);
}

// Henyey–Greenstein phase function, 1/sr; cos_theta between propagation and the direction
// (the angle between the light's travel direction and the direction of the scattered ray).
float henyey_greenstein(float cos_theta, float g) {
    float denom = 1.0 + g * g - 2.0 * g * cos_theta;
    return (1.0 - g * g) / (4.0 * PI * denom * sqrt(denom));
}

// The paper's distance-regulated point size: s_max at z_near, s_min at z_far, s = a + b/d.
// The distance is clamped to [z_near, z_far]: beyond z_far the formula would fall below
// s_min (and below zero).
float regulated_point_size(float d_view, float z_near, float z_far, float s_min, float s_max) {
    float a = s_max - z_far * (s_max - s_min) / (z_far - z_near);
    float b = z_near * z_far * (s_max - s_min) / (z_far - z_near);
    return a + b / clamp(d_view, z_near, z_far);
}

// Caustic slivers (caustics_triangles.geom): how a mesh triangle much smaller than a pixel
// is deposited. Its footprint is taken as a square of side s = √(its pixel area), centred on its centroid c
// (target pixels). Each pixel takes the fraction of that square it overlaps, per axis the
// overlap of [c − s/2, c + s/2] with the pixel's span over s: the pixel average that the
// reference computes, for a footprint of that size. The fractions sum to 1 wherever c lies,
// so the sliver deposits exactly its flux; s → 0 is "the pixel under the centroid", s = 1 a
// bilinear tent. With s < 1 the footprint touches at most two pixels per axis, so a
// 2-pixel square centred on c covers every one of them.
// The geometry shader passes c and s to the fragment shader inside the irradiance's fourth
// component, the same at the square's four corners (interpolating a constant returns it to
// within rounding: the code is an integer below 2^20, so the rounding is under 0.5): per
// axis c's offset from the nearest pixel edge, in 1/128 pixel, and that edge's parity,
// which tells a fragment whether its pixel lies below or above the edge; and s in 1/16
// pixel.
const float FOOTPRINT_OFFSET_STEPS = 128.0;
const float FOOTPRINT_AXIS_CODES = 2.0 * FOOTPRINT_OFFSET_STEPS; // parity × offset
const float FOOTPRINT_SIDE_STEPS = 16.0;

// Code of a footprint centred on c with side `side` pixels (> 0; 0 means "not a sliver").
float sliver_footprint_code(vec2 c, float side) {
    vec2 edge = floor(c + 0.5); // the pixel edge nearest c (edges sit at integers)
    vec2 offset = clamp(round((c - edge) * FOOTPRINT_OFFSET_STEPS), -FOOTPRINT_OFFSET_STEPS / 2.0, FOOTPRINT_OFFSET_STEPS / 2.0 - 1.0);
    vec2 axis = mod(edge, 2.0) * FOOTPRINT_OFFSET_STEPS + (offset + FOOTPRINT_OFFSET_STEPS / 2.0);
    float s = clamp(round(side * FOOTPRINT_SIDE_STEPS), 1.0, FOOTPRINT_SIDE_STEPS);
    return 1.0 + axis.x + axis.y * FOOTPRINT_AXIS_CODES + (s - 1.0) * FOOTPRINT_AXIS_CODES * FOOTPRINT_AXIS_CODES;
}

// Weight of the fragment at pixel centre `pixel` (gl_FragCoord.xy) for the footprint `code`.
float sliver_footprint_weight(vec2 pixel, float code) {
    float k = round(code) - 1.0;
    float per_side = FOOTPRINT_AXIS_CODES * FOOTPRINT_AXIS_CODES;
    float s = (floor(k / per_side) + 1.0) / FOOTPRINT_SIDE_STEPS;
    k = mod(k, per_side);
    vec2 axis = vec2(mod(k, FOOTPRINT_AXIS_CODES), floor(k / FOOTPRINT_AXIS_CODES));
    vec2 parity = floor(axis / FOOTPRINT_OFFSET_STEPS);
    vec2 offset = (axis - parity * FOOTPRINT_OFFSET_STEPS - FOOTPRINT_OFFSET_STEPS / 2.0) / FOOTPRINT_OFFSET_STEPS;
    // The pixel's span relative to the edge: [0, 1] above it, [−1, 0] below it. Pixels
    // farther away lie outside the 2-pixel square.
    vec2 above = vec2(equal(mod(floor(pixel), 2.0), parity));
    vec2 lo = above - 1.0, hi = above;
    vec2 overlap = max(min(hi, offset + 0.5 * s) - max(lo, offset - 0.5 * s), 0.0) / s;
    return overlap.x * overlap.y;
}

// A long, thin sliver (a fold's edge) is laid along its length as a strip (emit_thin_sliver).
// Drawn one pixel wide with every covered pixel taking the same value, it covered one or two
// pixel centres per row at random, and a grazed wall's thousands of parallel slivers read as a
// dotted hatching where the reference has a smooth wash. So it is drawn two pixels wide, and
// each pixel takes the tent 1 − |d| of its centre's distance d (pixels) from the strip's middle
// line: a box one pixel wide filtered by the pixel's own box, across the strip. Along any row
// or column the tent's samples at unit spacing sum to 1 whatever the offset, so the strip
// deposits its flux smoothly, not only in expectation. The geometry shader passes d in the
// irradiance's fourth component, interpolated across the strip, as a code between the
// triangles' 0 and the footprints' codes above 0.5 (STRIP_CODE_MIDDLE ± STRIP_CODE_SCALE).
const float STRIP_CODE_MIDDLE = 0.25;
const float STRIP_CODE_SCALE = 0.125; // per pixel of d, so d ∈ [−1, 1] codes into [0.125, 0.375]

float strip_across_code(float d) {
    return STRIP_CODE_MIDDLE + STRIP_CODE_SCALE * d;
}

// d ∈ [−1, 1] with half that span again of margin on either side: clear of 0 and 0.5.
bool is_strip_code(float code) {
    return abs(code - STRIP_CODE_MIDDLE) < 1.5 * STRIP_CODE_SCALE;
}

// d, from the code.
float strip_across(float code) {
    return (code - STRIP_CODE_MIDDLE) / STRIP_CODE_SCALE;
}

float strip_weight(float code) {
    return max(1.0 - abs(strip_across(code)), 0.0);
}

// ---------------------------------------------------------------------------------------
// Footprint hats (the footprint-sized points: caustics.geom and caustics.frag with
// FOOTPRINT_POINTS; docs/accuracy.md, "Footprint-sized points"). A photon spreads its light
// over the target by a hat on its cell of the photon lattice: T(s) · T(t), T the unit tent
// max(1 − |x|, 0) and (s, t) a point's coordinates in the basis of the spans to the photon's
// grid neighbours on the target. However the lattice is rotated or sheared, its hats sum to 1
// everywhere, so light the photons spread evenly lands evenly. (Tents along the pixel axes,
// a rectangle's, sum to a ripple on a lattice oblique to them, which the pixel grid turned
// into moiré on the floors the camera sees at a slant.) The hat is sampled at
// FOOTPRINT_HAT_SAMPLES² points spread evenly over each pixel, so a pixel takes about the
// hat's mean over its area. A basis whose singular values are below the samples' spacing is
// widened to it: tents as wide as the samples' spacing sum to 1 over the samples whatever
// their offset, so a photon much smaller than a pixel still deposits its light (exactly,
// for a hat along the pixel axes), where a narrower one could fall between samples.
// Rust twin: shader_math::footprint_hat_*. Compiled only into the shaders that define
// FOOTPRINT_POINTS, so the others' SPIR-V does not carry them.
#ifdef FOOTPRINT_POINTS // only their shaders compile it
const float FOOTPRINT_HAT_SAMPLES = 4.0;

// The hat's basis for the spans `spans` (columns: the photon's cell edges along the grid's
// two axes, target pixels): the spans themselves, with each singular value below 1 /
// FOOTPRINT_HAT_SAMPLES raised to it along its own direction.
mat2 footprint_hat_basis(mat2 spans) {
    float least = 1.0 / FOOTPRINT_HAT_SAMPLES;
    // Most photons' spans need nothing: the smaller singular value is |det| over the larger,
    // which the spans' Frobenius norm bounds from above.
    float frobenius = sqrt(dot(spans[0], spans[0]) + dot(spans[1], spans[1]));
    if (abs(determinant(spans)) >= least * frobenius) return spans;
    // The singular vectors: spansᵀ · spans's eigenvectors, from either row of (gram − λ1 I),
    // the longer (the other vanishes when the spans are already orthogonal).
    mat2 gram = transpose(spans) * spans;
    float half_trace = 0.5 * (gram[0][0] + gram[1][1]);
    float spread = sqrt(max(half_trace * half_trace - (gram[0][0] * gram[1][1] - gram[0][1] * gram[0][1]), 0.0));
    vec2 sigma = sqrt(vec2(half_trace + spread, max(half_trace - spread, 0.0)));
    vec2 a = vec2(half_trace + spread - gram[1][1], gram[0][1]);
    vec2 b = vec2(gram[0][1], half_trace + spread - gram[0][0]);
    vec2 longer = dot(a, a) >= dot(b, b) ? a : b;
    vec2 v1 = dot(longer, longer) > 0.0 ? normalize(longer) : vec2(1.0, 0.0);
    vec2 v2 = vec2(-v1.y, v1.x);
    vec2 u1 = sigma.x > 0.0 ? spans * v1 / sigma.x : vec2(1.0, 0.0);
    // The second's own image where it has one: its sign fixes the hat's orientation.
    vec2 u2 = sigma.y > 1e-6 * sigma.x ? spans * v2 / sigma.y : vec2(-u1.y, u1.x);
    vec2 raise = max(sigma, vec2(least)) - sigma;
    return spans + raise.x * outerProduct(u1, v1) + raise.y * outerProduct(u2, v2);
}

// The share of a hat with `to_lattice` the inverse of its basis that the pixel whose centre
// lies at `lattice` on the hat's (s, t) takes: the hat's mean over the pixel's samples. Over
// every pixel the shares sum to about the hat's area, |det basis| pixels. (For the pixel
// centred on p and the hat centred on c, `lattice` is to_lattice · (p − c); caustics.frag
// interpolates it across the hat's quad and reads `to_lattice` as its screen derivatives.)
float footprint_hat_share(vec2 lattice, mat2 to_lattice) {
    vec2 step_x = to_lattice[0] / FOOTPRINT_HAT_SAMPLES, step_y = to_lattice[1] / FOOTPRINT_HAT_SAMPLES;
    vec2 first = lattice - 0.5 * (FOOTPRINT_HAT_SAMPLES - 1.0) * (step_x + step_y);
    float sum = 0.0;
    for (int j = 0; j < int(FOOTPRINT_HAT_SAMPLES); ++j) {
        for (int i = 0; i < int(FOOTPRINT_HAT_SAMPLES); ++i) {
            vec2 tent = max(1.0 - abs(first + float(i) * step_x + float(j) * step_y), 0.0);
            sum += tent.x * tent.y;
        }
    }
    return sum / (FOOTPRINT_HAT_SAMPLES * FOOTPRINT_HAT_SAMPLES);
}

// How far from its pixel's centre a footprint hat's farthest sample lies along each pixel
// axis, (S − 1) / 2S pixels.
float footprint_hat_samples_reach() {
    return 0.5 - 0.5 / FOOTPRINT_HAT_SAMPLES;
}

// How far along s and t the quad a footprint point's hat is drawn as reaches: its corners are
// the lattice points (±s, ±t), the hat's centre plus its basis times each. The hat's cell,
// |s|, |t| ≤ 1 on the lattice of inverse basis `to_lattice`, widened along s and t by
// `pixel_reach` (how far a pixel's samples lie from its centre along each pixel axis, pixels)
// times the pixel's extent in lattice units: a sample q within that reach of a pixel's centre
// p has s(p) = s(q) + ∂s·(p − q), so every pixel one of whose samples lies on the hat has its
// centre inside the quad.
vec2 footprint_hat_quad_reach(mat2 to_lattice, float pixel_reach) {
    vec2 pixel_extent = vec2(abs(to_lattice[0].x) + abs(to_lattice[1].x), abs(to_lattice[0].y) + abs(to_lattice[1].y));
    return 1.0 + pixel_reach * pixel_extent;
}

// Whether the pixel centred on `pixel` shows the receiver of the footprint point whose hat is
// centred on `centre` (target pixels, `target_size` of them; the camera's vertical half-angle
// tangent `tan_half_fov_y`, square pixels): the surface it shows (its reciprocal view depth
// `w_scene`) lies off the receiver's plane by at most FOOTPRINT_RECEIVER_SLOPE of its distance
// from the photon, on_one_receiver's test for the photons' neighbours (caustic_splat.glsl),
// with a floor of FOOTPRINT_RECEIVER_DEPTH_SLACK of its depth for the depth buffer's steps.
// A hat spans its cell on its receiver's plane, and where that plane runs past the receiver
// (a rock's facet past its crease, a floor past a post's foot) the depth test passes
// whatever lies behind: the hat's light went onto the floor beside a rock's silhouette, or
// onto the neighbouring facet the light does not reach (docs/accuracy.md, "Hats on their own
// receiver"). The plane is its reciprocal view depth, which is affine over the target's
// pixels: `w_centre` at the hat's centre and `w_gradient` per pixel (footprint_receiver_plane).
// Under the perspective, 1/z = A·x + B·y + C over NDC (x, y) is the plane n·P = c with
// (A / tan_x, B / tan_y, C) = n / c, so the pixel's point P = r / w_scene (r = (x·tan_x,
// y·tan_y, 1)) lies n·P − c = (w_plane / w_scene − 1) · c off it.
// Compiled only into the variants that define FOOTPRINT_RECEIVER_TEST.
#ifdef FOOTPRINT_RECEIVER_TEST
const float FOOTPRINT_RECEIVER_SLOPE = 0.25;
const float FOOTPRINT_RECEIVER_DEPTH_SLACK = 2e-3;
bool footprint_pixel_on_receiver(vec2 pixel, vec2 centre, float w_centre, vec2 w_gradient, float w_scene,
                                 vec2 target_size, float tan_half_fov_y) {
    float w_plane = w_centre + dot(w_gradient, pixel - centre);
    if (!(w_plane > 0.0) || !(w_scene > 0.0)) return false;
    vec2 tan_half = vec2(tan_half_fov_y * target_size.x / target_size.y, tan_half_fov_y);
    vec2 ndc_slope = w_gradient * 0.5 * target_size; // dw per NDC unit
    float w_at_axis = w_centre + dot(w_gradient, 0.5 * target_size - centre);
    float plane_distance = 1.0 / max(length(vec3(ndc_slope / tan_half, w_at_axis)), 1e-30); // c
    vec3 ray = vec3((pixel / target_size * 2.0 - 1.0) * tan_half, 1.0);
    vec3 photon_ray = vec3((centre / target_size * 2.0 - 1.0) * tan_half, 1.0);
    float off_plane = abs(w_plane / w_scene - 1.0) * plane_distance;
    float from_photon = length(ray / w_scene - photon_ray / w_centre);
    return off_plane <= FOOTPRINT_RECEIVER_SLOPE * from_photon + FOOTPRINT_RECEIVER_DEPTH_SLACK / w_scene;
}

// The receiver plane's reciprocal view depth per target pixel, over its value at the photon
// (footprint_pixel_on_receiver's `w_gradient` / `w_centre`), from two of the plane's
// directions: their spans on the target `s1`, `s2` (pixels) and the changes `dw1`, `dw2` of
// the reciprocal view depth along them. False where the plane is seen edge on.
bool footprint_receiver_plane(vec2 s1, vec2 s2, float dw1, float dw2, float w_centre, out vec2 w_gradient) {
    float det = s1.x * s2.y - s1.y * s2.x;
    w_gradient = vec2(0.0);
    if (!(abs(det) > 1e-6 * (dot(s1, s1) + dot(s2, s2)))) return false;
    w_gradient = vec2(dw1 * s2.y - dw2 * s1.y, dw2 * s1.x - dw1 * s2.x) / (det * w_centre);
    return true;
}
#endif // FOOTPRINT_RECEIVER_TEST
#endif // FOOTPRINT_POINTS

#endif
