// Textures of the frame (set 0). Every pass uses the same set layout (frame::FrameBindings);
// each shader declares only the bindings it reads, so a target a scene does not need is
// never bound, never read and never allocated.
#ifndef UNDERLIGHT_FRAME_TEXTURES_GLSL
#define UNDERLIGHT_FRAME_TEXTURES_GLSL
#define BINDING_NOISE 1
#define BINDING_LIGHT_POSITION 2
#define BINDING_LIGHT_NORMAL 3
#define BINDING_SCENE_DEPTH 4
#define BINDING_SCENE_COLOR 5
#define BINDING_ALBEDO_TRANSMITTANCE 6
#define BINDING_CAUSTICS 7
#define BINDING_GODRAYS 8
#define BINDING_FILTER_INPUT 9
#define BINDING_PHOTON_DEBUG 10
#define BINDING_PHOTON_ACCUMULATION 11
#define BINDING_SPLAT_RECORDS 12
// What the camera sees through the water surface from above (refraction and reflection passes).
#define BINDING_REFRACTION_COLOR 13
#define BINDING_REFRACTION_ALBEDO 14
#define BINDING_REFRACTION_DEPTH 15
#define BINDING_REFLECTION_COLOR 16
#endif
