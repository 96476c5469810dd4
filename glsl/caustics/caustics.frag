#version 450
// Adds a photon's irradiance where its receiver is visible. Only fragments in front of the
// scene reach it: the pass's depth test, against the depth that photon_visibility.frag wrote,
// is the visibility test, made before the shader runs.
// Compiled again with FOOTPRINT_POINTS (caustics_footprint.frag) for the footprint-sized
// points (caustics.geom), whose hats are any size and shape: each pixel takes its share of the
// photon's hat (footprint_hat_share, shader_math.glsl), and the shares of neighbouring
// photons sum to 1 however their lattice lies on the target. With FOOTPRINT_RECEIVER_TEST too
// (caustics_footprint_receiver.frag, effects.caustic_receiver_test), a hat lights only the
// pixels that show its receiver (footprint_pixel_on_receiver). Its own variant: on llvmpipe a
// fragment shader that reads a texture at all costs more of the pass whether or not its
// fragments take the read, 1.03–1.29× since the hats are quads (1.12–1.49× as sprites;
// docs/performance.md, "Footprint hats drawn as quads").

// The paper's point carries only its irradiance besides its position and size: its depth is
// the point's, and every such photon counts 1 in alpha. A footprint point's alpha is the
// pixel's share of its hat.
layout(location = 0) flat in vec3 g_irradiance;
#ifdef FOOTPRINT_POINTS
#include "../shared/shader_math.glsl"
#ifdef FOOTPRINT_RECEIVER_TEST
#include "../shared/scene_depth.glsl"
#endif
// The hat on the target: the pixel centre's place on the hat's lattice (s, t), interpolated
// across the quad drawn for it (caustics.geom), which is a parallelogram in screen space, so
// (s, t) is affine in the pixel and its screen derivatives are the inverse of the hat's
// basis, whose columns are the hat's edges (footprint_hat_basis).
layout(location = 1) noperspective in vec2 g_lattice;
#ifdef FOOTPRINT_RECEIVER_TEST
layout(location = 2) flat in vec2 g_receiver_plane; // its reciprocal depth and gradient (caustics.geom)
#endif
#endif
layout(location = 0) out vec4 out_irradiance;
layout(early_fragment_tests) in;

void main() {
#ifdef FOOTPRINT_POINTS
    // g_irradiance is the photon's light over its hat's area: the pixel's share of the hat
    // makes its part of the light.
    mat2 to_lattice = mat2(dFdx(g_lattice), dFdy(g_lattice));
    float covered = footprint_hat_share(g_lattice, to_lattice);
#ifdef FOOTPRINT_RECEIVER_TEST
    if (g_receiver_plane.x > 0.0) {
        vec2 centre = gl_FragCoord.xy - inverse(to_lattice) * g_lattice; // the hat's, pixels
        vec2 w_gradient = g_receiver_plane.x * unpackHalf2x16(floatBitsToUint(g_receiver_plane.y));
        float w_scene = 1.0 / scene_view_depth(gl_FragCoord.xy / frame.caustic_target_size);
        if (!footprint_pixel_on_receiver(gl_FragCoord.xy, centre, g_receiver_plane.x, w_gradient, w_scene,
                                         frame.caustic_target_size, frame.tan_half_fov_y))
            covered = 0.0;
    }
#endif
    out_irradiance = vec4(g_irradiance * covered, covered);
#else
    out_irradiance = vec4(g_irradiance, 1.0);
#endif
}
