#version 450
// The receiver maps' projection, bent at the water level for a directional light
// (light_map_point, frame.glsl): above the water along the light, below it along the
// light's refracted direction. The bend is linear on each side of the level but not across
// it, so a triangle that crosses the level is cut there first, into the triangle on one side
// and the quad (two triangles) on the other; each piece then projects exactly. (Drawn
// whole, a wall from the floor to above the water lay up to a few centimetres off in the
// map, and the photons that met it did not converge.) The pass renders two pairs of maps,
// the second bent along a steeper direction (`steep`; frame::uniforms::steep_light_axis).
// The normal map holds each triangle's own plane, not its interpolated vertex normals: the
// photon cast places its hits on the plane of the receiver stored at a texel (its point and
// normal), so a smooth-shaded mesh's normals, which tilt across each facet, put the hits off
// the geometry. On a face the light grazes that moved them centimetres along it: an 8 cm post
// whose OBJ had no normals (the loader averages them over its corners) held 11.7 % less light
// than the reference, in blotches, against 2.4 % with its faces' normals (docs/accuracy.md,
// "Receivers' planes from their geometry").
#include "frame.glsl"

layout(push_constant) uniform ShadowPush { uint steep; } pc;

layout(triangles) in;
// Three triangles at most (the cut-off corner and the quad's two), each its own strip.
layout(triangle_strip, max_vertices = 9) out;

layout(location = 0) in vec3 v_world[];
layout(location = 1) in vec3 v_normal[];
layout(location = 0) out vec3 g_world;
layout(location = 1) flat out vec3 g_normal;

void emit(vec3 world, vec3 normal) {
    g_world = world;
    g_normal = normal;
    gl_Position = frame.light_view_proj * vec4(light_map_point(world, pc.steep != 0u), 1.0);
    EmitVertex();
}

void emit_triangle(vec3 p0, vec3 p1, vec3 p2, vec3 normal) {
    emit(p0, normal);
    emit(p1, normal);
    emit(p2, normal);
    EndPrimitive();
}

// The unit normal of the triangle's plane, on the side its vertex normals face: the photons'
// receiver tests compare neighbouring receivers' normals, so a mesh's facets must agree in
// orientation whatever the winding of each. Its vertex normals' sum where the cross product
// vanishes (the loader drops zero-area triangles; this guards a float underflow), and zero,
// which the cast reads as no plane, where that vanishes too.
vec3 plane_normal() {
    vec3 face = cross(v_world[1] - v_world[0], v_world[2] - v_world[0]);
    vec3 shading = v_normal[0] + v_normal[1] + v_normal[2];
    if (dot(face, shading) < 0.0) face = -face;
    vec3 n = dot(face, face) > 0.0 ? face : shading;
    return dot(n, n) > 0.0 ? normalize(n) : vec3(0.0);
}

void main() {
    vec3 normal = plane_normal();
    float level = frame.water_level;
    float s[3] = float[3](v_world[0].y - level, v_world[1].y - level, v_world[2].y - level);
    bool bends = light_map_bend(pc.steep != 0u).y < -1e-3;
    // The corner alone on its side of the level, if the triangle crosses it.
    int lone = -1;
    for (int i = 0; i < 3; ++i) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        if ((s[i] > 0.0 && s[j] <= 0.0 && s[k] <= 0.0) || (s[i] < 0.0 && s[j] >= 0.0 && s[k] >= 0.0)) lone = i;
    }
    if (!bends || lone < 0) {
        emit_triangle(v_world[0], v_world[1], v_world[2], normal);
        return;
    }
    // Corners in the triangle's own order from the lone one, so the pieces keep its winding.
    int a = lone, b = (lone + 1) % 3, c = (lone + 2) % 3;
    float tb = s[a] / (s[a] - s[b]), tc = s[a] / (s[a] - s[c]);
    vec3 xb = mix(v_world[a], v_world[b], tb), xc = mix(v_world[a], v_world[c], tc);
    xb.y = level; // on the level exactly, so both sides' pieces meet there
    xc.y = level;
    emit_triangle(v_world[a], xb, xc, normal);
    emit_triangle(xb, v_world[b], v_world[c], normal);
    emit_triangle(xb, v_world[c], xc, normal);
}
