#version 450
// Caustics with the triangle estimator (the "caustic triangles" of Frühstück & Prast's
// survey, §5.2.2, after Watt's beam tracing). The photons are the vertices of a mesh: each
// coarse cell casts its SUBDIVISION² photons and the next row and column of its neighbours',
// and emits the mesh cells whose lower-left corner is one of its own photons, each as two
// triangles on the receivers. A triangle carries the flux of its light-space area over its
// receiver area, so the target holds the irradiance of the refracted wavefront: no gaps
// where photons spread, no blur where they focus, folds add up.
//   - A triangle carries the light through its own area of the photon window: that area
//     (between the places its corners were cast, after the view's warp) times its corners'
//     mean flux density (Photon::flux_density: the light's, the surface's transmittance,
//     the water's attenuation to each hit). On the even grid that is a sixth of each corner's
//     flux, so the mesh carries the flux the paper's points would. On a grid warped for the
//     view it is also exact where the warp's slope changes, where a sixth of each corner's
//     flux (its cell measured across the change) lit flat water 14 % too dark or too bright
//     along the window's edges (tests/method.rs, the_mesh_reaches_the_water_s_edges).
//   - A folded triangle (flipped by a caustic) keeps |area|.
//   - Irradiance is per vertex, interpolated across the triangle, as the survey advises: a
//     photon's is the flux over the area of the drawn triangles around it (those of this
//     invocation). Flat per-triangle values showed every cell's facet. Each triangle's
//     three vertex values are then scaled together so that their mean is the triangle's own
//     flux over its area: the triangle deposits exactly its flux, and where the values are
//     smooth the scale is 1. (Plain interpolation let a photon beside a fold, whose small
//     triangles give it a high value, spread that value over its larger neighbours: +3 %
//     flux on the tank, +10 % on the port's near seabed.)
//   - Rasterised, the mesh's triangles tile the receivers, so each pixel centre samples the
//     wavefront's irradiance once per sheet. A triangle much smaller than a pixel would be a
//     firefly: of area a px², it covers a centre with probability about a and then deposits
//     1/a times its flux. One under SLIVER_PIXELS (1 px²) is deposited as the pixels' share of its
//     footprint instead (shader_math.glsl): exactly its flux, over the one to four pixels
//     a square of its area centred on its centroid overlaps.
//   - A mesh cell that spans a discontinuity (a corner that did not land, or corners on
//     different receivers: a wall and the floor, a box top and the floor) would smear light
//     over what lies between, so its triangles are not drawn. It is cut instead
//     (emit_cut_cell, marching squares over the receivers): each run of its corners on one
//     receiver draws the polygon of those corners and the places on the cell's edges where
//     that receiver ends, found by bisecting the grid edge (search_borders). A crossing lies
//     on the corner's receiver's plane, along the photon differential (footprint_edge: the
//     span of its grid neighbours' refracted rays on that plane, which needs their rays, not
//     their hits; where no neighbour's ray meets the plane, a deck's or a rail's shadow, a
//     ray cast from the light a grid step over and refracted as the photon's own was,
//     light_step_edge). The polygon carries the light through its own part of the
//     photon window, so a border is drawn as the straight line between its crossings and
//     carries the light up to it.
//     (Before, a refused triangle handed a third of its flux to each landed corner, and each
//     drew it over the bounding box of its cell's quarters, out to the borders: the borders
//     were staircases, and a slit narrower than the photons' spacing read 4/3 of its light at
//     its brightest. Cut, 320×200: tank 0.316 → 0.321, port 0.413, storage 0.370 → 0.361;
//     holes 0.30 / 0.21 / 1.56 % → 0.07 / 0.10 / 0.94 %; at the scenes' own sizes 0.839 /
//     1.316 / 1.227 → 0.833 / 1.312 / 1.206, holes 0.99 / 0.77 / 1.82 % → 0.79 / 0.56 /
//     1.67 %; flux 0.05–0.3 % lower; docs/accuracy.md, "Cells cut at receivers' borders".)
//     A corner whose polygon cannot be had (a photon whose ray runs along its receiver's
//     plane) draws a square the size of its footprint or of the paper's points, whichever
//     is smaller. (Squares everywhere were the tank's most visible flaw: dots of
//     light on its ledge, its cube's face and its rocks, where the light grazes a face and
//     a row or two of photons lands on it.)
// Measured on the tank at 320×200 against the reference (relative RMSE, flux), with flat
// values and slivers as one whole pixel: threshold 0 (all rasterised) 3.44, −6.2 %;
// 0.125 px² 0.86, −3.1 %; 0.5 px² 0.66, −2.4 %; 1 px² 0.68, −2.4 % (above 0.5 px² squares
// left holes on distant floors, where photons are merely dense). Per vertex, with the hits
// on the receivers' planes (photon_cast.glsl): 0.61; with the triangles' own flux 0.55,
// −2.9 %; with the slivers' footprints 0.50, −2.9 %, and a third of the holes.
// With the footprints, the threshold is 1 px² (the largest footprint the code holds: a side
// of one pixel), not 0.5: a triangle of about a pixel covers zero, one or two pixel centres
// and deposits its irradiance at each, where its footprint gives each pixel its share of the
// triangle's area. The shipped settings at 320×200 (caustics at ×1): tank 0.470 → 0.427, port
// 0.573 → 0.516, storage 0.600 → 0.561, flux unchanged; 2 px² (footprints capped at one
// pixel) read 0.421 on the tank. One receiver within 45° (see one_receiver) then reads 0.426 /
// 0.512 / 0.561.
#include "caustic_splat.glsl"

const float SLIVER_PIXELS = 1.0; // px²; see above (a footprint's side is at most a pixel)
const float THIN_TRIANGLE_HEIGHT = 1.0; // px across its longest edge: a triangle under it is drawn as a strip
const float THIN_SLIVER_LENGTH = 1.5; // px: a sliver longer than this is drawn along its length
const float FOOTPRINT_MAX_EDGE = 64.0; // px: the farthest a cut cell's crossing lies from its corner
const int MAX_SIDE = TRIANGLE_MAX_SUBDIVISION + 1;  // photons per axis an invocation casts
const int MAX_PHOTONS = MAX_SIDE * MAX_SIDE;

layout(points) in;
// The output bound. Each of the 3² mesh cells is drawn whole, as two triangles that each draw
// themselves (3 vertices), a strip or a square (4), or cut at a receiver's border, as up to
// 12 vertices (emit_cut_cell): at most 9 · 12 = 108 vertices. Each has 8 components
// (gl_Position alone of gl_PerVertex, and the irradiance's location): 864 of the 1024 every
// geometry-shader device offers.
layout(triangle_strip, max_vertices = 108) out;
out gl_PerVertex { vec4 gl_Position; };
layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

#ifdef CAUSTIC_REFINEMENT
// Refinement at receivers' borders (effects.caustic_refinement; compiled as
// caustics_triangles_refined.geom). A mesh cell whose corners land on two receivers, or of
// which one did not land, is where the mesh cannot follow the light: a post's face a
// centimetre wide in the light's window between photons 4 cm apart, a rock's flank between
// its rim and the floor. The grid's draw hands such cells to a second draw (REFINED_DRAW)
// instead of drawing them, which casts each again as SUBDIVISION × SUBDIVISION mesh cells
// of its own and draws those as the grid's are drawn. The cells handed on are listed in a
// buffer whose head is the second draw's indirect command: the grid's draw counts them
// into its vertex count (passes/caustics.rs resets it to zero each frame).
layout(constant_id = 3) const bool REFINED_DRAW = false;
layout(set = 0, binding = BINDING_REFINED_CELLS, std430) buffer RefinedCells {
    uint vertex_count; // VkDrawIndirectCommand: one invocation per cell handed on
    uint instance_count;
    uint first_vertex;
    uint first_instance;
    ivec2 first_photon[]; // each cell's lower-left photon on the grid (−1 in the ring)
} refined;
#else
const bool REFINED_DRAW = false;
#endif

layout(location = 0) flat in uvec2 v_cell[];
// rgb: irradiance / E_surface, interpolated per vertex; a: 0, a strip's code across it
// (strip_across_code, shader_math.glsl), or a sliver's footprint code, the same at its four
// corners.
layout(location = 0) out vec4 g_irradiance;

// The invocation's photons, row by row, SUBDIVISION + 1 per row.
vec3 hit[MAX_PHOTONS];
// Transmitted and attenuated to the hit, W per channel per unit of the photon window's uv
// area (Photon::flux_density); 0: dropped.
vec3 flux_density[MAX_PHOTONS];
vec2 window_uv[MAX_PHOTONS]; // where in the photon window it was cast (Photon::window_uv)
vec3 normal[MAX_PHOTONS];    // the receiver's, from the light's normal map
vec4 clip[MAX_PHOTONS];
vec3 surface[MAX_PHOTONS];   // where its ray entered the water, and its refracted direction:
vec3 direction[MAX_PHOTONS]; // zero where it never refracted (footprint_edge)
float cell_scale[MAX_PHOTONS]; // its grid cell's area over the even grid's (photon_density_warp)
bool landed[MAX_PHOTONS];
bool steep[MAX_PHOTONS];     // found in the second light maps (Photon::steep_map)
bool seen[MAX_PHOTONS];      // landed on the side of its receiver the camera sees (lit_side_faces_camera)
bool in_cut_cell[MAX_PHOTONS]; // a seen corner of a cut cell (emit_cut_cell)
// Its cell's edges on its receiver's plane along the grid's u and v (footprint_edge), for a
// cut cell's corner (cut_cell_edges); has_edge: whether footprint_edge found one.
vec3 cell_edge_u[MAX_PHOTONS];
vec3 cell_edge_v[MAX_PHOTONS];
bool has_edge_u[MAX_PHOTONS];
bool has_edge_v[MAX_PHOTONS];
vec3 around_flux[MAX_PHOTONS]; // sums over the drawn triangles around each photon
float around_area[MAX_PHOTONS];
float around_pixels[MAX_PHOTONS];     // their pixels and world area, where in front of the
float around_pixel_area[MAX_PHOTONS]; // camera: the receiver area per pixel near the photon
float around_count[MAX_PHOTONS];      // how many such triangles (a photon's cell is two)
vec2 grid_uv[MAX_PHOTONS];   // where on the photon grid it was cast (cast_photon's uv)
// Where the receiver of photon k, or of its neighbour, ends on the grid edge to its +u (k + 1)
// and +v (k + side) neighbour, as a fraction of the edge from k (search_borders); −1 where
// not searched (both ends on one receiver, or neither seen).
float border_u[MAX_PHOTONS];
float border_v[MAX_PHOTONS];

// A square of s.size pixels centred on s.clip, at the photon's one depth; `footprint` is the
// fragment shader's weighting code: a sliver's (a 2-pixel square), or for a lone photon's
// square −s.size (every covered pixel gets the whole irradiance). Non-zero either way, which
// tells the fragment shader that the square's depth is a point's, not its receiver's at each
// pixel, and how far its pixels reach.
void emit_square(CausticSplat s, float footprint) {
    vec2 half_size = s.size / frame.caustic_target_size; // a pixel spans 2 / target size in NDC
    for (int k = 0; k < 4; ++k) {
        vec2 corner = vec2(k & 1, k >> 1) * 2.0 - 1.0;
        gl_Position = s.clip + vec4(corner * half_size * s.clip.w, 0.0, 0.0);
        g_irradiance = vec4(s.irradiance.rgb, footprint);
        EmitVertex();
    }
    EndPrimitive();
}

// Whether a photon that landed at `p` with receiver normal `n` lies on photon k's receiver
// (on_one_receiver, caustic_splat.glsl).
bool on_receiver_of(int k, vec3 p, vec3 n) {
    return on_one_receiver(hit[k], normal[k], p, n);
}

// Whether photons a, b, c landed on one smooth receiver (a's: on_receiver_of), on the side
// the camera sees.
bool one_receiver(int a, int b, int c) {
    if (!(landed[a] && landed[b] && landed[c])) return false;
    if (!(seen[a] && seen[b] && seen[c])) return false;
    return on_receiver_of(a, hit[b], normal[b]) && on_receiver_of(a, hit[c], normal[c]);
}

// Target pixels (the caustic target's) of a clip position in front of the camera.
vec2 target_pixel(vec4 c) {
    return (c.xy / c.w * 0.5 + 0.5) * frame.caustic_target_size;
}

float triangle_area(int a, int b, int c) {
    return 0.5 * length(cross(hit[b] - hit[a], hit[c] - hit[a])); // m², |.| for folds
}

// Area in caustic-target pixels; huge for a triangle through the near plane (the
// rasteriser clips it, and it is not small).
float triangle_pixels(int a, int b, int c) {
    if (min(min(clip[a].w, clip[b].w), clip[c].w) <= frame.z_near) return 1e30;
    vec2 pa = target_pixel(clip[a]), pb = target_pixel(clip[b]), pc = target_pixel(clip[c]);
    vec2 u = pb - pa, v = pc - pa;
    return 0.5 * abs(u.x * v.y - u.y * v.x);
}

// The photon window's uv area between the places where photons a, b, c were cast.
float window_area(int a, int b, int c) {
    vec2 u = window_uv[b] - window_uv[a], v = window_uv[c] - window_uv[a];
    return 0.5 * abs(u.x * v.y - u.y * v.x);
}

// The light through triangle (a, b, c): its window area times its corners' mean flux density.
vec3 triangle_flux(int a, int b, int c) {
    return (flux_density[a] + flux_density[b] + flux_density[c]) * (window_area(a, b, c) / 3.0);
}

// First pass over a triangle of a cell drawn whole: it lends its flux and area to its
// corners' irradiance (photon_irradiance).
void gather_triangle(int a, int b, int c) {
    vec3 share = triangle_flux(a, b, c);
    float area = triangle_area(a, b, c);
    around_flux[a] += share; around_flux[b] += share; around_flux[c] += share;
    around_area[a] += area; around_area[b] += area; around_area[c] += area;
    float pixels = triangle_pixels(a, b, c);
    if (pixels < 1e29) {
        around_pixels[a] += pixels; around_pixels[b] += pixels; around_pixels[c] += pixels;
        around_count[a] += 1.0; around_count[b] += 1.0; around_count[c] += 1.0;
        around_pixel_area[a] += area; around_pixel_area[b] += area; around_pixel_area[c] += area;
    }
}

// A strip two pixels wide between clip positions `from` and `to`, offset `middle` pixels
// along `across` (the unit normal of their line on the target), each of its pixels taking
// `value` weighted by the tent of its distance from the middle line (strip_weight,
// shader_math.glsl).
void emit_strip(vec4 from, vec4 to, vec2 across, float middle, vec3 value) {
    for (int k = 0; k < 4; ++k) {
        vec4 end = (k >> 1) == 0 ? from : to;
        float d = (k & 1) == 0 ? -1.0 : 1.0;
        vec2 offset_px = across * (middle + d);
        gl_Position = end + vec4(offset_px * 2.0 / frame.caustic_target_size * end.w, 0.0, 0.0);
        g_irradiance = vec4(value, strip_across_code(d));
        EmitVertex();
    }
    EndPrimitive();
}

// Emits the sliver (a, b, c) as a strip along its longest edge, through the middle of its
// height, when that edge is longer than THIN_SLIVER_LENGTH pixels; `per_pixel` is its flux
// over the receiver area of one pixel (/E_surface). The strip is two pixels wide, and each
// pixel takes per_pixel over its length, weighted by the tent of its distance from the
// strip's middle (strip_weight, shader_math.glsl): the weights sum to about the strip's
// length, so it deposits its flux.
bool emit_thin_sliver(int a, int b, int c, vec3 per_pixel) {
    int corners[3] = int[3](a, b, c);
    vec2 p[3] = vec2[3](target_pixel(clip[a]), target_pixel(clip[b]), target_pixel(clip[c]));
    int longest = 0;
    float length_px = 0.0;
    for (int i = 0; i < 3; ++i) {
        float l = distance(p[i], p[(i + 1) % 3]);
        if (l > length_px) { length_px = l; longest = i; }
    }
    if (!(length_px > THIN_SLIVER_LENGTH)) return false;
    int i0 = longest, i1 = (longest + 1) % 3, i2 = (longest + 2) % 3;
    vec2 along = (p[i1] - p[i0]) / length_px;
    vec2 across = vec2(-along.y, along.x);
    float middle = 0.5 * dot(p[i2] - p[i0], across); // half the height, towards the third corner
    emit_strip(clip[corners[i0]], clip[corners[i1]], across, middle, per_pixel / length_px);
    return true;
}

// Whether triangle (a, b, c), of `pixels` px², is thinner than THIN_TRIANGLE_HEIGHT pixels
// across its longest edge.
bool thin_triangle(int a, int b, int c, float pixels) {
    vec2 pa = target_pixel(clip[a]), pb = target_pixel(clip[b]), pc = target_pixel(clip[c]);
    float longest = max(max(distance(pa, pb), distance(pb, pc)), distance(pc, pa));
    return 2.0 * pixels < THIN_TRIANGLE_HEIGHT * longest;
}

// A photon's cell on its receiver in target pixels, from the light alone (a directional
// light): its cell of a grid of photons_per_axis.x × .y over the photon window (scaled by the
// grid's warp there, effects.caustic_photon_density), widened under the
// water as the refracted beam is (refracted_texel_stretch) and spread over the receiver as
// the beam meets it, over the receiver area one pixel covers there. For a photon with no
// drawn triangle around it (a post or an edge that only it reached), where the paper's
// distance rule drew a 5-20 px square on a post a few pixels wide.
float cell_pixels(int k, vec2 photons_per_axis) {
    float cell = 4.0 * frame.light_half_extent.x * frame.light_half_extent.y
               * frame.photon_window_size.x * frame.photon_window_size.y
               / (photons_per_axis.x * photons_per_axis.y) * cell_scale[k];
    vec3 beam = light_map_direction(hit[k], steep[k]);
    float stretch = hit[k].y < frame.water_level ? frame.refracted_texel_stretch : 1.0;
    float on_receiver = cell * stretch / max(abs(dot(normal[k], beam)), 0.1);
    vec3 to_hit = hit[k] - frame.camera_position;
    float d_view = length(to_hit);
    float cos_view = abs(dot(normal[k], to_hit / d_view));
    float cos_axis = clip[k].w / d_view;
    return on_receiver / pixel_world_area(d_view, cos_view, cos_axis, frame.caustic_target_size.y);
}

// Where photon m's refracted ray meets the plane of photon k's receiver; false where it never
// refracted, or runs along the plane or away from it.
bool ray_on_receiver_plane(int m, int k, out vec3 q) {
    q = vec3(0.0);
    if (!(dot(direction[m], direction[m]) > 0.5)) return false;
    vec3 n = normal[k];
    float denom = dot(direction[m], n);
    if (abs(denom) <= 1e-3) return false;
    float t = dot(hit[k] - surface[m], n) / denom;
    if (!(t > 0.0)) return false;
    q = surface[m] + t * direction[m];
    return true;
}

// One edge of photon k's cell on its receiver's plane, along grid axis `axis` (0: u, 1: v)
// between its neighbours before and after it on the invocation's grid (of `side` photons a
// row): half the span between their rays on that plane (the photon differential), or the
// span to the one whose ray meets it. Where neither does (both blocked above the water, or
// running along the plane), k's own ray a grid step over (light_step_edge, caustic_splat.glsl).
// False with none of these.
bool footprint_edge(int k, int axis, int side, vec2 photons_per_axis, out vec3 edge) {
    int along = axis == 0 ? k % side : k / side, step = axis == 0 ? 1 : side;
    vec3 qa, qb;
    bool a = along > 0 && ray_on_receiver_plane(k - step, k, qa);
    bool b = along + 1 < side && ray_on_receiver_plane(k + step, k, qb);
    edge = a && b ? 0.5 * (qb - qa) : b ? qb - hit[k] : a ? hit[k] - qa : vec3(0.0);
    return a || b
        || light_step_edge(hit[k], normal[k], surface[k], direction[k], window_uv[k], cell_scale[k], axis,
                           photons_per_axis, edge);
}

vec3 photon_irradiance(int k) {
    return around_flux[k] / (max(around_area[k], 1e-20) * frame.surface_irradiance);
}

// Draws triangle (a, b, c) of a cell drawn whole (its corners on one receiver, one_receiver).
void emit_triangle(int a, int b, int c) {
    float area = triangle_area(a, b, c);
    float pixels = triangle_pixels(a, b, c);
    bool sliver = pixels < SLIVER_PIXELS || !(area > 1e-12);
    // A long, thin triangle, sliver or not, is laid along its length as a strip carrying its
    // flux (emit_thin_sliver), handed its flux over one pixel's receiver area (/E_surface). One
    // call for both: llvmpipe runs every side of a branch, masked, for every triangle
    // (docs/performance.md, "The caustic triangles' masked work").
    bool strip = false;
    vec3 strip_per_pixel = vec3(0.0);
    CausticSplat s;
    vec3 flat_e = vec3(0.0);
    if (sliver) {
        vec3 share = triangle_flux(a, b, c);
        // On its corners' one receiver: a's normal (one_receiver).
        if (!caustic_square_on((hit[a] + hit[b] + hit[c]) / 3.0, normal[a], share, 1.0, s)) return;
        // The receiver area one pixel covers, exactly: the triangle's own world area over its
        // pixels. (caustic_square_on's estimate bounds cos θ_view by 0.2, which overstated the
        // port's distant, grazing seabed: flux +5.6 % against +2.4 %.) A triangle too small
        // for the ratio to be more than rounding keeps the estimate.
        if (area > 1e-12 && pixels > 1e-4) s.irradiance.rgb = share * pixels / (area * frame.surface_irradiance);
        // A long sliver (the strip's own test) is drawn as a strip: drawn at its centroid, a
        // fold through sparse photons was a dotted line (the port's near seabed).
        strip = true;
        strip_per_pixel = s.irradiance.rgb;
    } else {
        flat_e = triangle_flux(a, b, c) / (area * frame.surface_irradiance);
        // Under a pixel across its longest edge, a triangle would cover the pixel centres along
        // it in a broken line (a grazed wall's hatching, docs/accuracy.md "Strips weighed by a
        // tent across").
        strip = thin_triangle(a, b, c, pixels);
        strip_per_pixel = flat_e * pixels;
    }
    if (strip && emit_thin_sliver(a, b, c, strip_per_pixel)) return;
    if (sliver) {
        // A sliver that is not drawn as a strip: to the pixels its footprint overlaps
        // (sliver_footprint_code, shader_math.glsl).
        s.size = 2.0;
        emit_square(s, sliver_footprint_code(target_pixel(s.clip), sqrt(pixels)));
        return;
    }
    vec3 ea = photon_irradiance(a), eb = photon_irradiance(b), ec = photon_irradiance(c);
    vec3 mean_e = (ea + eb + ec) / 3.0;
    vec3 scale = flat_e / max(mean_e, vec3(1e-30));
    ea *= scale; eb *= scale; ec *= scale;
    // Outputs are undefined after each EmitVertex: set them for every vertex.
    gl_Position = clip[a]; g_irradiance = vec4(ea, 0.0); EmitVertex();
    gl_Position = clip[b]; g_irradiance = vec4(eb, 0.0); EmitVertex();
    gl_Position = clip[c]; g_irradiance = vec4(ec, 0.0); EmitVertex();
    EndPrimitive();
}

// Bisections of a grid edge whose ends lie on different receivers, or of which one end did
// not land (a shadow's edge, the water's): each casts a photon at the middle of the interval
// left, and halves it. Without them the light reached half-way to the neighbour whatever
// lay between, and every lit region's border was a staircase of cells (long spikes where
// cells stretch along the view: the tank's shadows at 800×800).
const int BORDER_BISECTIONS = 3;
const int MAX_EDGES = 2 * MAX_SIDE * (MAX_SIDE - 1);

// Whether the light runs on along grid edge k–m on one receiver: both ends seen (landed on
// the side the camera sees), each on the other's receiver.
bool edge_continuous(int k, int m) {
    return seen[k] && seen[m] && on_receiver_of(k, hit[m], normal[m]) && on_receiver_of(m, hit[k], normal[k]);
}

// Whether grid edge k → m crosses a receiver's border that a cut cell's polygon reaches: an
// end is a cut cell's seen corner (the others never read the border: the ring's photons
// past the grid's first, whose mesh cells its own invocations draw), and the light does not
// run on along it.
bool edge_crosses_border(int k, int m) {
    return (in_cut_cell[k] || in_cut_cell[m]) && !edge_continuous(k, m);
}

// Searches every edge of the invocation that crosses a receiver's border (border_u,
// border_v): from the end the camera sees, the fraction of the edge at which its receiver
// ends. The edges are listed first and searched in one loop, around one cast_photon: an
// invocation pays for its own borders, and the shader holds one copy of the photon's cast.
void search_borders(int side, vec2 photons_per_axis) {
    int edges[MAX_EDGES];
    int count = 0;
    for (int k = 0; k < side * side; ++k) {
        int i = k % side, j = k / side;
        if (i + 1 < side && edge_crosses_border(k, k + 1)) edges[count++] = 2 * k;
        if (j + 1 < side && edge_crosses_border(k, k + side)) edges[count++] = 2 * k + 1;
    }
    for (int e = 0; e < count; ++e) {
        int low = edges[e] >> 1;
        bool along_u = (edges[e] & 1) == 0;
        int high = along_u ? low + 1 : low + side;
        // Search from the end the camera sees; the fraction is stored from the low end.
        int from = seen[low] ? low : high, to = from == low ? high : low;
        float inside = 0.0, outside = 1.0;
        for (int b = 0; b < BORDER_BISECTIONS; ++b) {
            float t = 0.5 * (inside + outside);
            Photon ph;
            bool on_it = false;
            if (cast_photon(mix(grid_uv[from], grid_uv[to], t), photons_per_axis, ph)) {
                on_it = on_receiver_of(from, ph.hit, unit_receiver_normal(ph));
                // Where the other end landed too, the sample belongs to whichever end's plane
                // it lies nearer: on_receiver_of alone drifts with the distance from `from`,
                // and put the border between two facets 30° apart past their crease (+5 %
                // light there, tests/method.rs).
                if (on_it && landed[to])
                    on_it = abs(dot(ph.hit - hit[from], normal[from])) <= abs(dot(ph.hit - hit[to], normal[to]));
            }
            if (on_it) inside = t; else outside = t;
        }
        float border = 0.5 * (inside + outside);
        if (from != low) border = 1.0 - border;
        if (along_u) border_u[low] = border; else border_v[low] = border;
    }
}

// The fraction of grid edge k–m from k at which k's receiver ends (search_borders, which
// stores it from the edge's low end); half-way where the edge was not searched.
float border_from(int k, int m) {
    int low = min(k, m);
    float border = abs(k - m) == 1 ? border_u[low] : border_v[low];
    if (border < 0.0) return 0.5;
    return k == low ? border : 1.0 - border;
}

// Each cut cell's corner's cell edges (footprint_edge), once per photon rather than once per
// crossing that reads them, over a list of those photons (llvmpipe's masked loops).
void cut_cell_edges(int side, vec2 photons_per_axis) {
    int corners[MAX_PHOTONS];
    int count = 0;
    for (int k = 0; k < side * side; ++k) {
        has_edge_u[k] = false;
        has_edge_v[k] = false;
        if (in_cut_cell[k]) corners[count++] = k;
    }
    for (int listed = 0; listed < count; ++listed) {
        int k = corners[listed];
        has_edge_u[k] = footprint_edge(k, 0, side, photons_per_axis, cell_edge_u[k]);
        has_edge_v[k] = footprint_edge(k, 1, side, photons_per_axis, cell_edge_v[k]);
    }
}

// Where the light on photon k's receiver ends along its grid edge towards neighbour m, which
// lies `sign` (±1) along grid axis `axis` from it, at fraction f of the edge: on k's
// receiver's plane, f of k's cell's edge there (cut_cell_edges), at most FOOTPRINT_MAX_EDGE
// pixels from k. `window`: the same fraction of the photon window between the places they
// were cast. False where k's cell has no such edge. (The span to m's own ray alone, rather
// than the cell's edge, which averages both neighbours' rays, put bright single pixels on
// the tank's cube and the storage's floor: where m lands on another receiver, its ray can
// meet k's plane anywhere.)
bool border_crossing(int k, int m, int axis, float sign, float f, out vec3 p, out vec2 window) {
    window = mix(window_uv[k], window_uv[m], f);
    p = hit[k];
    if (!(axis == 0 ? has_edge_u[k] : has_edge_v[k])) return false;
    vec3 offset = f * sign * (axis == 0 ? cell_edge_u[k] : cell_edge_v[k]);
    vec4 far_end = frame.camera_view_proj * vec4(hit[k] + offset, 1.0);
    if (clip[k].w > frame.z_near && far_end.w > frame.z_near) {
        float length_px = distance(target_pixel(far_end), target_pixel(clip[k]));
        if (length_px > FOOTPRINT_MAX_EDGE) offset *= FOOTPRINT_MAX_EDGE / length_px;
    }
    p = hit[k] + offset;
    return true;
}

// A square for the light of a cut cell's corner k that has no polygon (a photon whose ray
// runs along its receiver's plane, so that it has no cell edge there, or a polygon without
// area): the photon's own footprint (its cell: two of the triangles around it) where that is
// smaller than the paper's distance rule, whose 5-20 px blurred the edge of every lit region
// by that much. Where the footprint is larger (faces the light grazes, whose cells stretch),
// the rule's size: footprint-sized squares there were grey blocks on the tank's cube, against
// faint streaks in the reference.
void emit_corner_square(int k, vec3 flux, vec2 photons_per_axis) {
    float size = regulated_point_size(length(hit[k] - frame.camera_position), frame.z_near, frame.z_far,
                                      frame.point_size_min, frame.point_size_max);
    if (around_count[k] > 0.0) size = min(size, sqrt(2.0 * around_pixels[k] / around_count[k]));
    else if (frame.light_is_point == 0.0) size = min(size, sqrt(cell_pixels(k, photons_per_axis)));
    size = clamp(round(size), 1.0, floor(frame.device_max_point_size));
    CausticSplat s;
    if (!caustic_square_on(hit[k], normal[k], flux, size, s)) return; // off the target
    // The receiver area per pixel from the drawn triangles around the photon, where it has
    // any (see emit_triangle).
    if (around_pixels[k] > 1e-4 && around_pixel_area[k] > 1e-12)
        s.irradiance.rgb = flux * around_pixels[k] / (size * size * around_pixel_area[k] * frame.surface_irradiance);
    emit_square(s, -size);
}

// With a cell's corners listed around it (p00, p10, p11, p01), its edge e runs from corner e
// to corner e + 1 along grid axis e & 1 (0: u, 1: v): forwards (+1) for e = 0, 1, backwards
// (−1) for e = 2, 3.
float cell_edge_sign(int e) {
    return e < 2 ? 1.0 : -1.0;
}

float cross2(vec2 a, vec2 b) {
    return a.x * b.y - a.y * b.x;
}

// Draws the light of a mesh cell that spans a receiver's border (a corner that did not land,
// that the camera does not see, or that lies on another receiver): each run of its corners
// along which the light runs on (edge_continuous) draws the polygon of those corners and the
// two places on the cell's edges where their receiver ends (border_crossing), at most six
// vertices (a run of the four, broken on one edge). Marching squares over the receivers, with
// the borders bisected: a border through the cell is drawn as the straight line between its
// crossings, where the photons' cells (bounding boxes of the refused triangles' quarters,
// before) drew it as a staircase. Each polygon carries the light through its own part of
// the photon window (the polygon's corners there) at its corners' mean flux density, flat
// over its area on the receiver: exact for the light that the waves do not bend within the
// cell, so a slit narrower than the photons' spacing over flat water reads flat water's
// irradiance (tests/method.rs). A polygon thinner than a pixel is laid as a strip, and one
// under a pixel goes to the pixels its footprint overlaps, as a triangle is. The corners are
// listed around the cell: p00, p10, p11, p01. The output bound: up to four runs, each a
// triangle (3 vertices) or, in a cell of at most three runs, a strip or a square (4): 12
// vertices at most (a run of two and two of one, as squares). A cell of four runs (its four
// corners on four receivers) rasterises its triangles whatever their size.
void emit_cut_cell(int p00, int p10, int p11, int p01, vec2 photons_per_axis) {
    int q[4] = int[4](p00, p10, p11, p01);
    bool continuous[4]; // edge e, corner e to corner e + 1
    for (int e = 0; e < 4; ++e) continuous[e] = edge_continuous(q[e], q[(e + 1) & 3]);
    // A cell all of whose edges carry the light on (its triangles refused across a diagonal)
    // is one run of four, drawn as its quadrilateral.
    bool whole = continuous[0] && continuous[1] && continuous[2] && continuous[3];
    // The runs' first corners (a seen corner whose edge before it is broken), listed
    // first and drawn in one loop over the list, as main lists the cut cells.
    int run_first[4];
    int runs = 0;
    for (int c = 0; c < 4; ++c) {
        if (whole ? c == 0 : seen[q[c]] && !continuous[(c + 3) & 3]) run_first[runs++] = c;
    }
    bool squares = runs < 4;
    for (int run = 0; run < runs; ++run) {
        int first = run_first[run];
        vec3 p[6];
        vec2 window[6];
        vec3 density = vec3(0.0);
        int n = 0, last = first;
        for (int step = 0; step < 4; ++step) {
            last = (first + step) & 3;
            p[n] = hit[q[last]];
            window[n] = window_uv[q[last]];
            density += flux_density[q[last]];
            ++n;
            if (!continuous[last] || step == 3) break;
        }
        density /= float(n);
        bool crossed = true;
        if (!whole) {
            int next = (last + 1) & 3, before = (first + 3) & 3;
            crossed = border_crossing(q[last], q[next], last & 1, cell_edge_sign(last),
                                      border_from(q[last], q[next]), p[n], window[n]);
            ++n;
            bool back = border_crossing(q[first], q[before], before & 1, -cell_edge_sign(before),
                                        border_from(q[first], q[before]), p[n], window[n]);
            crossed = crossed && back;
            ++n;
        }
        // On the receiver, the polygon's triangles from its first corner each keep |area|, as
        // a folded triangle does: a polygon that the waves fold would cancel its own area.
        float window_area = 0.0, area = 0.0;
        for (int v = 0; v < n; ++v) {
            window_area += cross2(window[v], window[(v + 1) % n]);
            if (v >= 1 && v + 1 < n) area += 0.5 * length(cross(p[v] - p[0], p[v + 1] - p[0]));
        }
        vec3 flux = density * (0.5 * abs(window_area));
        if (!crossed || !(area > 1e-12)) {
            if (squares) emit_corner_square(q[first], flux, photons_per_axis);
            continue;
        }
        vec4 corner_clip[6];
        vec2 corner_px[6];
        float pixels = 0.0;
        bool in_front = true;
        for (int v = 0; v < n; ++v) {
            corner_clip[v] = frame.camera_view_proj * vec4(p[v], 1.0);
            corner_px[v] = target_pixel(corner_clip[v]);
            in_front = in_front && corner_clip[v].w > frame.z_near;
        }
        // Its longest chord on the target, for a polygon thinner than a pixel across it.
        float length_px = 0.0;
        int end_0 = 0, end_1 = 1;
        for (int v = 1; v < n; ++v) {
            pixels += v + 1 < n ? 0.5 * abs(cross2(corner_px[v] - corner_px[0], corner_px[v + 1] - corner_px[0])) : 0.0;
            for (int w = 0; w < v; ++w) {
                float d = distance(corner_px[v], corner_px[w]);
                if (d > length_px) { length_px = d; end_0 = w; end_1 = v; }
            }
        }
        vec3 irradiance = flux / (area * frame.surface_irradiance);
        // A polygon under a pixel across its longest chord would cover the pixel centres along
        // it in a broken line, each with all of its irradiance (bright dots along a shadow's
        // border): laid along that chord as a strip carrying its flux, as a thin triangle is.
        if (in_front && squares && length_px > THIN_SLIVER_LENGTH
            && (pixels < SLIVER_PIXELS || 2.0 * pixels < THIN_TRIANGLE_HEIGHT * length_px)) {
            vec2 along = (corner_px[end_1] - corner_px[end_0]) / length_px;
            vec2 across = vec2(-along.y, along.x);
            vec2 centre_px = vec2(0.0);
            for (int v = 0; v < n; ++v) centre_px += corner_px[v];
            float middle = dot(centre_px / float(n) - corner_px[end_0], across);
            emit_strip(corner_clip[end_0], corner_clip[end_1], across, middle, irradiance * pixels / length_px);
            continue;
        }
        if (in_front && pixels < SLIVER_PIXELS && squares) {
            vec3 centre = vec3(0.0);
            for (int v = 0; v < n; ++v) centre += p[v];
            CausticSplat s;
            if (!caustic_square_on(centre / float(n), normal[q[first]], flux, 1.0, s)) continue; // off the target
            s.irradiance.rgb = irradiance * pixels;
            s.size = 2.0;
            emit_square(s, sliver_footprint_code(target_pixel(s.clip), sqrt(pixels)));
            continue;
        }
        // A convex polygon as a strip: 0, 1, n − 1, 2, n − 2, …
        for (int v = 0; v < n; ++v) {
            int corner = (v & 1) == 1 ? (v + 1) >> 1 : (n - (v >> 1)) % n;
            gl_Position = corner_clip[corner];
            g_irradiance = vec4(irradiance, 0.0);
            EmitVertex();
        }
        EndPrimitive();
    }
}

// Whether mesh cell (p00, p10, p01, p11) is split along its p00–p11 diagonal rather than its
// p10–p01 one: the shorter of the two between the photons' hits. That gives the two more
// compact triangles on the receiver (the Delaunay choice for a quadrilateral), so each
// triangle's flux is spread over the ground between photons that landed near each other,
// not along a long thin sliver. Measured against the fixed split, 320×200, t = 1 s: tank
// 0.421 → 0.419, port 0.506 → 0.503, storage 0.543 → 0.537, tank at 800×800 1.192 → 1.177.
// The shorter diagonal in pixels read the same; the longer diagonal 0.483 on the tank, and
// splits that balance or minimise the two triangles' areas 0.467 and 0.437.
bool split_along_p00_p11(int p00, int p10, int p01, int p11) {
    if (!(landed[p00] && landed[p10] && landed[p01] && landed[p11])) return false;
    vec3 d00_11 = hit[p11] - hit[p00], d10_01 = hit[p01] - hit[p10];
    return dot(d00_11, d00_11) < dot(d10_01, d10_01);
}

// The coarse cell whose mesh this invocation draws. The grid's own N/k × N·k cells first
// (caustic_grid_cell: on the storage, whose corridor is narrow across the photon window and
// long along it, a square grid's mesh cells were 2.2× longer one way than the other on
// screen). Then, for the invocations past them, a ring of cells at −1 before the grid's first
// row and column: the mesh cells between the grid's first photons (index 0), which lie half a
// cell inside the photon window, and photons half a cell outside it (index −1). Without them
// the light between the first photons and the window's low edges was drawn by nobody (along
// the storage's far wall, where the water reaches that edge, a band below the water line
// stayed dark; docs/accuracy.md, "The mesh to the photon window's edges"). The pass draws
// enough invocations for the ring (passes/caustics.rs, `mesh_invocations`). False for an
// invocation past both.
bool mesh_cell(uvec2 invocation, uint grid, out ivec2 cell, out uvec2 cells) {
    uvec2 grid_cell;
    if (caustic_grid_cell(invocation, grid, grid_cell, cells)) {
        cell = ivec2(grid_cell);
        return true;
    }
    uint ring = invocation.y * grid + invocation.x - cells.x * cells.y;
    if (ring <= cells.x) cell = ivec2(int(ring) - 1, -1);                        // row −1, columns −1 … N/k − 1
    else cell = ivec2(-1, int(ring - cells.x - 1u));                             // column −1, rows 0 … N·k − 1
    return cell.y < int(cells.y);
}

// Whether this invocation draws mesh cell (i, j) of its photons: all of them in the grid's
// own cells; in the ring's, only those from its photons at −1 (the others are the grid's).
bool mesh_cell_drawn(ivec2 cell, int i, int j) {
    return (cell.x >= 0 || i == 0) && (cell.y >= 0 || j == 0);
}

void main() {
    int side = int(SUBDIVISION) + 1;
    ivec2 cell;
    uvec2 cells;
    ivec2 first;
    vec2 photons_per_axis;
    if (REFINED_DRAW) {
#ifdef CAUSTIC_REFINEMENT
        // A mesh cell of the grid, handed on: its photons are a SUBDIVISION-times finer grid
        // over it, whose corners are the grid's own four photons, at the same bits.
        uint handed_on = v_cell[0].y * pc.grid + v_cell[0].x;
        if (handed_on >= min(refined.vertex_count, uint(refined.first_photon.length()))) return;
        uvec2 grid_cell;
        caustic_grid_cell(uvec2(0u), pc.grid, grid_cell, cells);
        cell = ivec2(0); // every mesh cell of the finer grid is drawn (mesh_cell_drawn)
        first = refined.first_photon[handed_on];
#endif
    } else {
        if (!mesh_cell(v_cell[0], pc.grid, cell, cells)) return;
        // Along an axis where the cell is the ring's, the invocation's photons start at −1, so
        // that the grid's first photon has its neighbours on both sides for its cell's edges
        // (footprint_edge); only the mesh cells from −1 are drawn there (mesh_cell_drawn).
        first = ivec2(cell.x < 0 ? -1 : cell.x * int(SUBDIVISION), cell.y < 0 ? -1 : cell.y * int(SUBDIVISION));
    }
    photons_per_axis = vec2(cells * SUBDIVISION);
    // The photons' own grid, for their cells' size (cell_pixels): the finer one where refined.
    vec2 mesh_photons_per_axis = REFINED_DRAW ? photons_per_axis * float(SUBDIVISION) : photons_per_axis;
    for (int j = 0; j < side; ++j) {
        for (int i = 0; i < side; ++i) {
            int k = j * side + i;
            // Sub-cell SUBDIVISION is the neighbour cell's first photon, at the same bits as
            // the neighbour casts it (caustic_grid_photon_uv, whose float arithmetic this
            // repeats for the ring's photons at −1). Refined, photon (i, j) lies i/SUBDIVISION
            // and j/SUBDIVISION of a grid edge past the cell's first: 0 and 1 at its corners,
            // exactly, so they are the grid's photons to the bit.
            vec2 uv = REFINED_DRAW ? (vec2(first) + 0.5 + vec2(i, j) / float(SUBDIVISION)) / photons_per_axis
                                   : (vec2(first + ivec2(i, j)) + 0.5) / photons_per_axis;
            Photon ph;
            grid_uv[k] = uv;
            border_u[k] = -1.0;
            border_v[k] = -1.0;
            landed[k] = cast_photon(uv, photons_per_axis, ph);
            hit[k] = ph.hit;
            cell_scale[k] = ph.cell_scale;
            surface[k] = ph.surface;
            direction[k] = ph.direction;
            flux_density[k] = landed[k] ? ph.flux_density * water_transmittance(ph.travelled) : vec3(0.0);
            window_uv[k] = ph.window_uv;
            steep[k] = ph.steep_map;
            normal[k] = landed[k] ? unit_receiver_normal(ph) : vec3(0.0);
            clip[k] = frame.camera_view_proj * vec4(ph.hit, 1.0);
            seen[k] = landed[k] && lit_side_faces_camera(ph.hit, normal[k], ph.direction);
            in_cut_cell[k] = false;
            around_flux[k] = vec3(0.0);
            around_area[k] = 0.0;
            around_pixels[k] = 0.0;
            around_pixel_area[k] = 0.0;
            around_count[k] = 0.0;
        }
    }
    // Mesh cell (i, j) spans photons (i, j), (i+1, j), (i, j+1), (i+1, j+1), split along the
    // shorter diagonal (split_along_p00_p11): into (p00, p10, p11) and (p00, p11, p01) along
    // p00-p11, else into (p00, p10, p01) and (p10, p11, p01). The corners are picked before
    // the two calls rather than in an if and an else with two calls each: llvmpipe runs
    // both sides of a branch for every lane, masked, and the triangles are most of the
    // shader's work (docs/performance.md, "One copy of the search").
    // Each mesh cell's split (split_along_p00_p11) and whether it is drawn whole, its two
    // triangles on one receiver, by its lower-left photon.
    bool split_cell[MAX_PHOTONS];
    bool whole_cell[MAX_PHOTONS];
    for (int j = 0; j + 1 < side; ++j) {
        for (int i = 0; i + 1 < side; ++i) {
            int p00 = j * side + i, p10 = p00 + 1, p01 = p00 + side, p11 = p01 + 1;
            split_cell[p00] = split_along_p00_p11(p00, p10, p01, p11);
            bool split = split_cell[p00];
            whole_cell[p00] = mesh_cell_drawn(cell, i, j) && one_receiver(p00, p10, split ? p11 : p01)
                           && one_receiver(split ? p00 : p10, p11, p01);
        }
    }
#ifdef CAUSTIC_REFINEMENT
    // Which mesh cells this invocation hands to the refinement draw (indexed by their
    // lower-left photon): those with a refused triangle and a corner the camera sees.
    bool handed_on[MAX_PHOTONS];
    for (int k = 0; k < MAX_PHOTONS; ++k) handed_on[k] = false;
    if (!REFINED_DRAW) {
        for (int j = 0; j + 1 < side; ++j) {
            for (int i = 0; i + 1 < side; ++i) {
                int p00 = j * side + i, p10 = p00 + 1, p01 = p00 + side, p11 = p01 + 1;
                if (!mesh_cell_drawn(cell, i, j) || whole_cell[p00] || !(seen[p00] || seen[p10] || seen[p01] || seen[p11]))
                    continue;
                uint slot = atomicAdd(refined.vertex_count, 1u);
                // A full list: the cell is drawn here, as without refinement.
                if (slot >= uint(refined.first_photon.length())) continue;
                refined.first_photon[slot] = first + ivec2(i, j);
                handed_on[p00] = true;
            }
        }
    }
#endif
    // The mesh cells cut at a receiver's border (emit_cut_cell), listed by their lower-left
    // photon: drawn in one loop over the list, as search_borders lists its edges. llvmpipe
    // runs a loop's body, masked, until no lane needs another pass, so a loop over every cell
    // that skipped the others ran the cutting once per cell, where most invocations cut none
    // (docs/performance.md, "The caustic triangles' masked work").
    int cut_cells[MAX_PHOTONS];
    int cut_count = 0;
    for (int j = 0; j + 1 < side; ++j) {
        for (int i = 0; i + 1 < side; ++i) {
            int p00 = j * side + i, p10 = p00 + 1, p01 = p00 + side, p11 = p01 + 1;
            if (whole_cell[p00]) {
                bool split = split_cell[p00];
                gather_triangle(p00, p10, split ? p11 : p01);
                gather_triangle(split ? p00 : p10, p11, p01);
                continue;
            }
#ifdef CAUSTIC_REFINEMENT
            if (handed_on[p00]) continue;
#endif
            if (!mesh_cell_drawn(cell, i, j) || !(seen[p00] || seen[p10] || seen[p01] || seen[p11])) continue;
            cut_cells[cut_count++] = p00;
            in_cut_cell[p00] = in_cut_cell[p00] || seen[p00];
            in_cut_cell[p10] = in_cut_cell[p10] || seen[p10];
            in_cut_cell[p01] = in_cut_cell[p01] || seen[p01];
            in_cut_cell[p11] = in_cut_cell[p11] || seen[p11];
        }
    }
    for (int j = 0; j + 1 < side; ++j) {
        for (int i = 0; i + 1 < side; ++i) {
            int p00 = j * side + i, p10 = p00 + 1, p01 = p00 + side, p11 = p01 + 1;
            if (!whole_cell[p00]) continue;
            bool split = split_cell[p00];
            emit_triangle(p00, p10, split ? p11 : p01);
            emit_triangle(split ? p00 : p10, p11, p01);
        }
    }
    search_borders(side, photons_per_axis);
    cut_cell_edges(side, mesh_photons_per_axis);
    for (int listed = 0; listed < cut_count; ++listed) {
        int p00 = cut_cells[listed], p10 = p00 + 1, p01 = p00 + side, p11 = p01 + 1;
        emit_cut_cell(p00, p10, p11, p01, mesh_photons_per_axis);
    }
}
