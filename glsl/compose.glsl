// Compose (method step 8): scene colour + caustic irradiance × albedo/π × transmittance to
// the camera + godray radiance, then tonemapped. Included by compose*.frag, which define
// HAS_CAUSTICS / HAS_GODRAYS so a scene without an effect never binds its target.
#include "frame.glsl"
#include "frame_textures.glsl"

layout(set = 0, binding = BINDING_SCENE_COLOR) uniform sampler2D scene_color;
#ifdef HAS_CAUSTICS
layout(set = 0, binding = BINDING_ALBEDO_TRANSMITTANCE) uniform sampler2D albedo_transmittance;
layout(set = 0, binding = BINDING_CAUSTICS) uniform sampler2D caustics;
#endif
#ifdef HAS_GODRAYS
layout(set = 0, binding = BINDING_GODRAYS) uniform sampler2D godrays;
#endif

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 L = texture(scene_color, v_uv).rgb;
#ifdef HAS_CAUSTICS
    L += texture(albedo_transmittance, v_uv).rgb * texture(caustics, v_uv).rgb * frame.light_flux.x;
#endif
#ifdef HAS_GODRAYS
    L += texture(godrays, v_uv).rgb * frame.light_flux.x; // stored relative to E_surface too
#endif
    // 1 − e^(−exposure·L): linear in the shadows, rolls highlights off. The target is sRGB,
    // so the hardware encodes.
    out_color = vec4(1.0 - exp(-frame.water3.w * max(L, vec3(0.0))), 1.0);
}
