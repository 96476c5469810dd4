// Which view of the scene a mesh or background draw belongs to (specialization constant 0 of
// mesh.vert, scene.frag and background.frag; passes::scene::View in Rust).
#ifndef UNDERLIGHT_VIEW_GLSL
#define UNDERLIGHT_VIEW_GLSL
layout(constant_id = 0) const uint VIEW = 0;
// The camera's own view (scene pass).
const uint VIEW_CAMERA = 0;
// The part under the water from the camera, for the surface to refract (refraction pass):
// clipped above the highest crest, radiance leaving each receiver without the water on the
// way to the camera (the surface applies it along the refracted ray).
const uint VIEW_REFRACTION = 1;
// The part above the water mirrored in the mean plane, from the camera (reflection pass):
// clipped below the lowest trough.
const uint VIEW_REFLECTION = 2;
#endif
