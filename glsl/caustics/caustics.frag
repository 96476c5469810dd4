#version 450
// Adds a photon's irradiance where its receiver is visible. Only fragments in front of the
// scene reach it: the pass's depth test, against the depth that photon_visibility.frag wrote,
// is the visibility test, made before the shader runs.
// Compiled again with FOOTPRINT_POINTS (caustics_footprint.frag) for the footprint-sized
// points (caustics.geom), whose rectangles are any size, not whole pixels. Each point spreads
// its light by a tent per axis whose half-width is the rectangle's side, integrated over
// each pixel: the weights over the pixels sum to the rectangle's area, so the point
// deposits exactly its flux, and on a regular lattice the neighbours' tents sum to a
// constant (linear interpolation). Boxes of the rectangle itself (each pixel taking the
// share of it the rectangle covers) tile only where the footprints are axis-aligned: oblique
// ones overlapped one way and left seams the other, a hatching the reference does not have
// (docs/accuracy.md, "Footprint-sized points").

// The point's vertex carries only what varies per photon (4 components besides its position
// and size): its depth is the point's, and every photon counts 1 in alpha.
layout(location = 0) flat in vec3 g_irradiance;
#ifdef FOOTPRINT_POINTS
// The rectangle on the target: its centre, width and height (pixels, any size); the point
// drawn for it is a pixel wider than twice its larger side, so that it reaches every pixel
// its tents touch.
layout(location = 1) flat in vec4 g_square;

// The share of a unit tent of half-width 1 centred at 0 that lies below t (its cumulative
// distribution), per component.
vec2 tent_below(vec2 t) {
    t = clamp(t, -1.0, 1.0);
    return mix(0.5 * (1.0 + t) * (1.0 + t), 1.0 - 0.5 * (1.0 - t) * (1.0 - t), step(0.0, t));
}
#endif
layout(location = 0) out vec4 out_irradiance;
layout(early_fragment_tests) in;

void main() {
#ifdef FOOTPRINT_POINTS
    // The pixel's share of each axis's tent, times the rectangle's area in pixels: the
    // irradiance is the footprint's, over that many pixels.
    vec2 half_width = max(g_square.zw, vec2(1e-6));
    vec2 share = tent_below((gl_FragCoord.xy + 0.5 - g_square.xy) / half_width)
               - tent_below((gl_FragCoord.xy - 0.5 - g_square.xy) / half_width);
    float covered = share.x * share.y * g_square.z * g_square.w;
    out_irradiance = vec4(g_irradiance * covered, covered);
#else
    out_irradiance = vec4(g_irradiance, 1.0);
#endif
}
