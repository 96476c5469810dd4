#version 450
// The raw splat floor: draws recorded caustic splats (caustics_record.comp) as they are, so
// the caustics pass's cost can be compared with that of its points alone.
layout(location = 0) in vec4 in_clip;
layout(location = 1) in vec4 in_irradiance;
layout(location = 2) in vec4 in_size_depth;

layout(location = 0) flat out vec3 g_irradiance;

void main() {
    gl_Position = in_clip;
    gl_PointSize = in_size_depth.x;
    g_irradiance = in_irradiance.rgb;
}
