// A per-pixel value in [0, 1) with little low-frequency structure (interleaved gradient noise,
// Jimenez 2014), for the passes that dither a per-pixel choice (the filter's kernel rotation,
// the godray march's first step), so a regular pattern becomes fine noise.
#ifndef UNDERLIGHT_PIXEL_NOISE_GLSL
#define UNDERLIGHT_PIXEL_NOISE_GLSL
float pixel_noise(vec2 pixel) {
    return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}
#endif
