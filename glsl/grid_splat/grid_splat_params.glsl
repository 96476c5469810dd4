// Push constants of the grid-splat pass. Rust side: passes::grid_splat::GridSplatPush.
layout(push_constant) uniform GridSplatPush {
    uvec2 grid;           // coarse cells per axis
    float point_size;     // pixels
    float energy;         // added to RGB by every photon
    float wave_amplitude; // demo displacement, in uv units (0: photons at sub-cell centres)
    float time;           // seconds
} pc;
