// Shading helpers shared by the scene and water-surface shaders.
#ifndef UNDERLIGHT_UNDERWATER_GLSL
#define UNDERLIGHT_UNDERWATER_GLSL
#include "frame.glsl"

// Length of the segment a→b that lies below the water's mean plane.
float underwater_length(vec3 a, vec3 b, float level) {
    float len = length(b - a);
    bool a_in = a.y < level, b_in = b.y < level;
    if (a_in && b_in) return len;
    if (!a_in && !b_in) return 0.0;
    float s = (level - a.y) / (b.y - a.y); // where the segment crosses the plane
    return a_in ? s * len : (1.0 - s) * len;
}

// Diffuse (sky) irradiance at a point, W/m²: the ambient share of the light, attenuated by
// the water above the point; a receiver facing down gets less of it.
vec3 ambient_irradiance(vec3 p, vec3 n) {
    float depth = max(frame.water0.x - p.y, 0.0);
    return frame.water3.z * exp(-frame.gamma.rgb * depth) * (0.6 + 0.4 * n.y);
}

// Radiance the water itself sends towards the viewer from in-scattered ambient light
// (what a long underwater view fades to).
vec3 water_fog_radiance() {
    vec3 g = max(frame.gamma.rgb, vec3(1e-3));
    return frame.water3.z * frame.gamma.w / g / (4.0 * PI);
}

// Applies the water between the camera and p to radiance L leaving p.
vec3 through_water(vec3 L, vec3 p) {
    float d = underwater_length(frame.camera_pos.xyz, p, frame.water0.x);
    vec3 t = exp(-frame.gamma.rgb * d);
    return L * t + water_fog_radiance() * (1.0 - t);
}
#endif
