// How the compute photon shaders number their photons (src/passes/photon_accumulation.rs,
// `dispatch_per_photon`): dispatches wider than the device's group-count limit use a second
// dimension of rows of gl_NumWorkGroups.x groups.
#ifndef UNDERLIGHT_PHOTON_DISPATCH_GLSL
#define UNDERLIGHT_PHOTON_DISPATCH_GLSL
uint photon_invocation_index() {
    return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
}
#endif
