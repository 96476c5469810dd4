// Shared shader math. Its Rust twin is src/shader_math.rs: change both together (the tests
// compare GPU output with the twin).
#ifndef UNDERLIGHT_COMMON_GLSL
#define UNDERLIGHT_COMMON_GLSL

const float PI = 3.14159265358979;

// Largest per-axis photon subdivision a geometry shader invocation emits. max_vertices must
// be a compile-time literal, so the shader is compiled for this bound and the actual factor is
// a specialization constant the driver unrolls at pipeline creation.
const int MAX_SUBDIVISION = 8;

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

// Where the noise is read for world point xz at time t: it drifts with the wave speed.
vec2 water_noise_uv(WaterParams w, vec2 xz, float t) {
    return xz / w.noise_scale + vec2(0.6, 0.8) * (w.speed * t / w.noise_scale);
}

// Height above the mean plane (x) and its gradient d/dx, d/dz (yz) at xz.
vec3 water_height_grad(WaterParams w, sampler2D noise, vec2 xz, float t) {
    float k = 2.0 * PI / w.wavelength;
    // The phase is reduced modulo 2π before the cosine so long run times keep precision.
    float phase_t = mod(k * w.speed * t, 2.0 * PI);
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
    vec3 n = sample_noise(noise, water_noise_uv(w, xz, t));
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

// Intersects a downward ray with the surface: start on the mean plane, then fixed-point
// iterations t ← (level + h(x(t)) − o.y) / d.y, which converge while the surface slope
// along the ray stays below the ray's steepness. Returns t (< 0: no hit).
float water_intersect(WaterParams w, sampler2D noise, vec3 o, vec3 d, float time) {
    if (d.y >= -1e-6) return -1.0;
    float t = (w.level - o.y) / d.y;
    for (int i = 0; i < 4; ++i) {
        vec3 p = o + t * d;
        float h = water_height_grad(w, noise, p.xz, time).x;
        t = (w.level + h - o.y) / d.y;
    }
    return t;
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
float regulated_point_size(float d_view, float z_near, float z_far, float s_min, float s_max) {
    float a = s_max - z_far * (s_max - s_min) / (z_far - z_near);
    float b = z_near * z_far * (s_max - s_min) / (z_far - z_near);
    return a + b / max(d_view, z_near);
}

#endif
