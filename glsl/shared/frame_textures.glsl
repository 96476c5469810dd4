// Textures of the frame (set 0). Every pass numbers its bindings alike (frame::bindings);
// each shader declares only the bindings it reads, so a target a scene does not need is
// never bound, never read and never allocated. The BINDING_<NAME> numbers are not written
// here: the shader compiler defines them from frame::bindings, their one definition.
#ifndef UNDERLIGHT_FRAME_TEXTURES_GLSL
#define UNDERLIGHT_FRAME_TEXTURES_GLSL
#endif
