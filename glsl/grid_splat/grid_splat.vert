#version 450
// One invocation per coarse grid cell; no vertex buffer: the cell comes from gl_VertexIndex.
#include "grid_splat_params.glsl"

layout(location = 0) flat out uvec2 v_cell;

void main() {
    uint i = uint(gl_VertexIndex);
    v_cell = uvec2(i % pc.grid.x, i / pc.grid.x);
    gl_Position = vec4(0.0);
}
