#version 450
// The visibility test of the rasterised photon splats (behind_scene, photon_visibility.glsl)
// made by the rasteriser's depth test. Drawn first in the caustic points' and the godray
// beams' passes, over the whole target, this writes at each pixel the depth of the farthest
// point that still counts as in front of the scene there; the splats then test against it
// (less or equal) without writing it. The fixed-function test runs before their fragment
// shader, so a fragment behind the scene costs no shading and no read of the scene's depth
// (docs/performance.md, "The photons' visibility as a depth test"). The compute path, which
// has no depth test, calls behind_scene itself; the caustic triangles test both sides
// (off_scene), which one depth test cannot. For the footprint points it also holds their
// light to where a photon could land (VISIBILITY_CAUSTICS_LIT).
#include "photon_visibility.glsl"
#include "photon_cast.glsl"

// The target this depth is for, which sets the tolerance
// (passes::photon_visibility::VisibilityTarget).
layout(constant_id = 0) const uint VISIBILITY_TARGET = 0;
const uint VISIBILITY_CAUSTICS = 0;
const uint VISIBILITY_GODRAYS = 1;
// The footprint points' target: as the caustics', and where no photon could land (in a
// shadow, light_could_land) nothing counts. A footprint point's hat reaches a whole span past
// its photon, tens of pixels along a wall the light grazes; where its neighbour across a
// shadow's edge was blocked, the hat runs that far into the shadow.
const uint VISIBILITY_CAUSTICS_LIT = 2;

layout(location = 0) in vec2 v_uv; // the pixel's centre, 0..1 over the target

// Whether the pixel at uv lies on a silhouette: reciprocal depth, affine across a plane, bends
// there by more than SILHOUETTE_BEND of itself between the pixel's neighbours, so the pixel
// sees more than one surface. The reference averages a pixel's irradiance over all it sees,
// so the pixel beside a lit floor's far edge holds some of the floor's light even where its
// centre shows the unlit wall behind: such a pixel keeps the plain visibility test.
const float SILHOUETTE_BEND = 0.05;
bool on_silhouette(vec2 uv, float w) {
    vec2 step = 1.0 / frame.caustic_target_size;
    float across = inverse_view_depth(uv - vec2(step.x, 0.0)) + inverse_view_depth(uv + vec2(step.x, 0.0)) - 2.0 * w;
    float down = inverse_view_depth(uv - vec2(0.0, step.y)) + inverse_view_depth(uv + vec2(0.0, step.y)) - 2.0 * w;
    return max(abs(across), abs(down)) > SILHOUETTE_BEND * w;
}

void main() {
    float tolerance = VISIBILITY_TARGET == VISIBILITY_GODRAYS ? GODRAY_DEPTH_TOLERANCE : CAUSTIC_DEPTH_TOLERANCE;
    float scene_z = scene_view_depth(v_uv);
    // The shadow test before the silhouette's four depth reads, which only a pixel in shadow
    // needs: the same answer, the cheaper question first.
    bool lit = VISIBILITY_TARGET != VISIBILITY_CAUSTICS_LIT || light_could_land(scene_world_point(v_uv))
            || on_silhouette(v_uv, 1.0 / scene_z);
    // Depth 0, the near plane, holds every splat off the pixel (one nearer is clipped).
    gl_FragDepth = lit ? depth_of_view_depth(farthest_visible(scene_z, tolerance)) : 0.0;
}
