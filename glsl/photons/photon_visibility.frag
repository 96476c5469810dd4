#version 450
// The visibility test of the rasterised photon splats (behind_scene, photon_visibility.glsl)
// made by the rasteriser's depth test. Drawn first in the caustic points' and the godray
// beams' passes, over the whole target, this writes at each pixel the depth of the farthest
// point that still counts as in front of the scene there; the splats then test against it
// (less or equal) without writing it. The fixed-function test runs before their fragment
// shader, so a fragment behind the scene costs no shading and no read of the scene's depth
// (docs/performance.md, "The photons' visibility as a depth test"). The compute path, which
// has no depth test, calls behind_scene itself; the caustic triangles test both sides
// (off_scene), which one depth test cannot.
#include "photon_visibility.glsl"

// The target this depth is for, which sets the tolerance
// (passes::photon_visibility::VisibilityTarget).
layout(constant_id = 0) const uint VISIBILITY_TARGET = 0;
const uint VISIBILITY_CAUSTICS = 0;
const uint VISIBILITY_GODRAYS = 1;

layout(location = 0) in vec2 v_uv; // the pixel's centre, 0..1 over the target

void main() {
    float tolerance = VISIBILITY_TARGET == VISIBILITY_GODRAYS ? GODRAY_DEPTH_TOLERANCE : CAUSTIC_DEPTH_TOLERANCE;
    float scene_z = scene_view_depth(v_uv);
    gl_FragDepth = depth_of_view_depth(farthest_visible(scene_z, tolerance));
}
