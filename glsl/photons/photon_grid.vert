#version 450
// One invocation per coarse cell of a photon grid (caustics, godrays); no vertex buffer.
layout(push_constant) uniform GridPush { uint grid; } pc;
layout(location = 0) flat out uvec2 v_cell;

void main() {
    uint i = uint(gl_VertexIndex);
    v_cell = uvec2(i % pc.grid, i / pc.grid);
    gl_Position = vec4(0.0);
}
