#version 450
// The water surface (scene pass). Each fragment takes the path of
// the side the camera sees it from, so a camera at the waterline sees both in one frame:
// - from below: the sky inside Snell's window with the sun's glint and Fresnel transmittance,
//   total internal reflection of the water's own glow outside it;
// - from above (THROUGH_SURFACE, when the frame has the refraction and reflection passes):
//   Fresnel mix of the reflection (mirrored view, sky where it shows nothing) and the
//   refraction (the underwater view with its caustics and godrays, found along the refracted
//   ray by the thesis's iterative intersection, §7.1, and faded to the water's colour by the
//   distance travelled under water, eq. 4–5), plus the sun's specular highlight, whose glow
//   compose spreads (§9.3).
// Compiled as water.frag (seen from below only) and as water_above*.frag (shaders::VARIANTS),
// which define THROUGH_SURFACE and HAS_CAUSTICS / HAS_GODRAYS, so a scene without an effect
// never binds it.
#include "underwater_shading.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;

// rgb: radiance; a: the specular highlight's radiance, which compose spreads into its glow.
layout(location = 0) out vec4 out_color;
// rgb: 0 (the surface is no caustic receiver); a: the Fresnel reflectance the colour used
// (from above; 0 from below), read back by tests against the formula.
layout(location = 1) out vec4 out_albedo_transmittance;

#ifdef THROUGH_SURFACE
layout(set = 0, binding = BINDING_REFRACTION_COLOR) uniform sampler2D refraction_color;
layout(set = 0, binding = BINDING_REFRACTION_ALBEDO) uniform sampler2D refraction_albedo;
layout(set = 0, binding = BINDING_REFRACTION_DEPTH) uniform sampler2D refraction_depth;
layout(set = 0, binding = BINDING_REFLECTION_COLOR) uniform sampler2D reflection_color;
#ifdef HAS_CAUSTICS
layout(set = 0, binding = BINDING_CAUSTICS) uniform sampler2D caustics;
#endif
#ifdef HAS_GODRAYS
layout(set = 0, binding = BINDING_GODRAYS) uniform sampler2D godrays;
#endif

// Iterations of the refracted ray's intersection with the underwater depth (thesis §7.1).
const int REFRACTION_STEPS = 6;
// How far along the reflected ray the reflection view is read (thesis eq. 6, c = 1 m): the
// thesis's coarse approximation; exact for flat water, where every c gives the same texel.
const float REFLECTION_REACH = 1.0;
// Phong exponent of the specular highlight (thesis §9.3).
const float HIGHLIGHT_EXPONENT = 200.0;

vec2 camera_uv(vec3 p) {
    vec4 c = frame.camera_view_proj * vec4(p, 1.0);
    return c.xy / max(c.w, 1e-6) * 0.5 + 0.5;
}

// The receiver the refraction view shows on the camera ray through p.
vec3 underwater_point_behind(vec3 p) {
    vec3 cam = frame.camera_position;
    vec3 fwd = camera_forward();
    vec2 uv = clamp(camera_uv(p), vec2(0.0), vec2(1.0));
    float z = linear_view_depth(textureLod(refraction_depth, uv, 0.0).r);
    return cam + (p - cam) * (z / max(dot(p - cam, fwd), 1e-4));
}

// Thesis §7.1: where the ray u + t·r (t ≥ 0) meets the underwater scene. Each step reads the
// receiver a_next on the camera ray through the current estimate w; the next estimate is
// where the ray crosses the segment between the last two receivers (eq. 3), or, where it does
// not, w moved along the ray by its gap to a_next (down if w is in front of it, else back up).
// Returns the receiver of the estimate with the smallest gap.
vec3 refracted_hit(vec3 u, vec3 r) {
    vec3 cam = frame.camera_position;
    vec3 fwd = camera_forward();
    vec3 w = u, a = u, best_a = u;
    float best_gap = 1e30;
    for (int i = 0; i < REFRACTION_STEPS; ++i) {
        vec3 a_next = underwater_point_behind(w);
        float gap = distance(a_next, w);
        if (gap < best_gap) { best_gap = gap; best_a = a_next; }
        vec3 q = a_next - a;
        vec3 rq = cross(r, q);
        float den = dot(rq, rq);
        vec3 w_next = w;
        bool between = false;
        if (i > 0 && den > 1e-12) {
            w_next = u + max(dot(cross(a - u, q), rq) / den, 0.0) * r;
            between = distance(w_next, a) + distance(a_next, w_next) <= distance(a_next, a) * (1.0 + 1e-4) + 1e-5;
        }
        if (!between) {
            float toward = dot(w - cam, fwd) > dot(a_next - cam, fwd) ? -1.0 : 1.0;
            w_next = u + max(dot(w - u, r) + toward * gap, 0.0) * r;
        }
        a = a_next;
        w = w_next;
    }
    return best_a;
}

// The refraction view's receiver at uv.
vec3 underwater_point_at(vec2 uv) {
    float depth = textureLod(refraction_depth, uv, 0.0).r;
    vec4 p = frame.camera_inv_view_proj * vec4(uv * 2.0 - 1.0, depth, 1.0);
    return p.xyz / p.w;
}

// Where the refracted lookup reads the refraction view. The view holds only what the camera
// frames, and a refracted ray near the image's border can meet a receiver outside it. Read
// at the border instead (clamping, or shortening the shift to end there), that border's
// texels smear into bars. So where the hit leaves the view, with k the share of the shift
// from the pixel to the hit that stays inside, the read moves only k² of the shift: the
// border shows the receivers straight behind it, blending continuously into the refracted
// image further in (k = 1). A screen-space compromise: the view has nothing better there.
vec2 refraction_lookup_uv(vec3 u, vec3 hit) {
    vec2 from = clamp(camera_uv(u), vec2(0.0), vec2(1.0));
    vec2 shift = camera_uv(hit) - from;
    float k = 1.0;
    for (int axis = 0; axis < 2; ++axis) {
        if (shift[axis] > 1e-6) k = min(k, (1.0 - from[axis]) / shift[axis]);
        if (shift[axis] < -1e-6) k = min(k, -from[axis] / shift[axis]);
    }
    k = clamp(k, 0.0, 1.0);
    return from + k * k * shift;
}

// Radiance arriving at the surface point u along the refracted ray r, from below.
vec3 refracted_radiance(vec3 u, vec3 r) {
    vec2 uv = refraction_lookup_uv(u, refracted_hit(u, r));
    vec3 a = underwater_point_at(uv);
    vec3 C = textureLod(refraction_color, uv, 0.0).rgb;
#ifdef HAS_CAUSTICS
    C += textureLod(refraction_albedo, uv, 0.0).rgb * textureLod(caustics, uv, 0.0).rgb * frame.surface_irradiance;
#endif
    vec3 L = through_water_length(C, distance(a, u));
#ifdef HAS_GODRAYS
    // The godray buffer holds what the medium scatters along the camera ray to that receiver.
    L += textureLod(godrays, uv, 0.0).rgb * frame.surface_irradiance;
#endif
    return L;
}

// Radiance arriving at u along the reflected ray r (pointing up): the reflection view's
// mirrored scene, the sky where it shows nothing.
vec3 reflected_radiance(vec3 u, vec3 r) {
    vec3 p = u + REFLECTION_REACH * r;
    p.y = 2.0 * frame.water_level - p.y;
    vec4 m = textureLod(reflection_color, camera_uv(p), 0.0);
    return mix(sky_radiance(r), m.rgb, m.a);
}

// The sun's (or point light's) highlight: a normalised Phong lobe, so it carries the light's
// reflected irradiance E·F spread over the lobe rather than a 0.5° disc a pixel can miss.
vec3 specular_highlight(vec3 u, vec3 r, float fresnel) {
    vec3 to_light = frame.light_is_point == 0.0 ? -frame.light_axis : normalize(frame.light_position - u);
    float dist2 = frame.light_is_point == 0.0 ? 1.0 : max(dot(frame.light_position - u, frame.light_position - u), 1e-4);
    if (frame.light_is_point != 0.0 && frame.light_position.y < u.y) return vec3(0.0);
    float lobe = (HIGHLIGHT_EXPONENT + 2.0) / (2.0 * PI) * pow(max(dot(r, to_light), 0.0), HIGHLIGHT_EXPONENT);
    return vec3(fresnel * frame.light_strength / dist2 * lobe);
}

void shade_from_above(vec3 u, vec3 n, vec3 v) {
    float ior = frame.ior;
    float cos_v = max(dot(-v, n), 0.0);
    float fresnel = 1.0 - fresnel_transmittance(cos_v, ior);
    vec3 r = reflect(v, n);
    r.y = max(r.y, 1e-3); // a wave's far side can send the ray down: keep it at the horizon
    r = normalize(r);
    vec3 t = refract(v, n, 1.0 / ior);
    vec3 spec = specular_highlight(u, r, fresnel);
    vec3 L = fresnel * reflected_radiance(u, r) + (1.0 - fresnel) * refracted_radiance(u, t) + spec;
    out_color = vec4(L, spec.g);
    out_albedo_transmittance = vec4(0.0, 0.0, 0.0, fresnel);
}
#endif

void shade_from_below(vec3 u, vec3 n, vec3 v) {
    float ior = frame.ior;
    // Looking up from inside the water: refract into air (index ior → 1).
    vec3 t = refract(v, -n, ior);
    vec3 L;
    if (dot(t, t) == 0.0) {
        L = water_fog_radiance(); // total internal reflection: the water's own glow
    } else {
        float tr = fresnel_transmittance(max(dot(t, n), 0.0), ior); // symmetric in direction
        vec3 sky = sky_radiance(normalize(t)) + sun_disc_radiance(normalize(t));
        L = tr * sky + (1.0 - tr) * water_fog_radiance();
    }
    out_color = vec4(through_water_length(L, distance(frame.camera_position, u)), 0.0);
    out_albedo_transmittance = vec4(0.0);
}

void main() {
    vec3 n = normalize(v_normal);
    vec3 u = v_world;
    vec3 v = normalize(u - frame.camera_position);
    // The side is the rasterised facet's (its normal oriented up), so it matches the geometry
    // the depth test saw, whatever the triangle's winding on screen.
    vec3 facet = cross(dFdx(v_world), dFdy(v_world));
    if (facet.y < 0.0) facet = -facet;
    bool from_above = dot(frame.camera_position - u, facet) > 0.0;
#ifdef THROUGH_SURFACE
    // Only in frames that rendered the views it reads (frame_surface_views_ready): a camera
    // under the troughs can still be on the upper side of a steep facet's plane far away.
    if (from_above && frame_surface_views_ready()) {
        shade_from_above(u, n, v);
        return;
    }
#endif
    shade_from_below(u, n, v);
}
