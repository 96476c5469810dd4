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

// Gradient of a small sum of travelling sine waves over [0,1]^2. The foundation's demo
// displaces photons by it, which focuses them into caustic-like lines.
vec2 demo_wave_gradient(vec2 uv, float t) {
    vec2 k1 = vec2(7.0, 3.0) * 2.0 * PI;
    vec2 k2 = vec2(-4.0, 9.0) * 2.0 * PI;
    return k1 * cos(dot(k1, uv) + 1.3 * t) / dot(k1, k1)
         + k2 * cos(dot(k2, uv) + 0.9 * t) / dot(k2, k2);
}

#endif
