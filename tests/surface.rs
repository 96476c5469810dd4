//! The water surface seen from above and across the waterline (issue 8): Fresnel weights
//! against the formula, the caustic-lit floor seen through the surface, and a camera path
//! through the surface.

mod common;

use common::*;
use glam::{Vec2, Vec3, Vec4};
use underlight::frame::uniforms::camera_matrices;
use underlight::frame::FrameOptions;
use underlight::headless::{SceneImages, SceneRenderer};
use underlight::image_io::HdrImage;
use underlight::metrics::sample_bilinear;
use underlight::passes::PassId;
use underlight::scene::Scene;
use underlight::shader_math::{refract, water_height_grad, water_intersect, water_normal_from_grad, NoiseTexture};
use underlight::vk::vk;

fn tank() -> Scene {
    underlight::scene::load("tank").expect("built-in tank")
}

fn flat(mut scene: Scene) -> Scene {
    scene.water.amplitude = 0.0;
    scene.water.noise_amplitude = 0.0;
    scene
}

/// Animation time of the single frame each view renders.
const RENDER_TIME: f32 = 1.0;

fn render(ctx: &underlight::vk::Context, scene: &Scene, size: [u32; 2]) -> (SceneImages, Vec<PassId>) {
    let extent = vk::Extent2D { width: size[0], height: size[1] };
    let mut r = SceneRenderer::new(&ctx.device, scene, extent).expect("renderer");
    let (timings, images) = r.render(1, RENDER_TIME, 0.0, true).expect("render");
    let passes = timings.last().expect("a frame").passes.iter().map(|p| p.0).collect();
    (images.expect("read back"), passes)
}

/// The camera ray through the centre of pixel (x, y) (the shaders' mapping: uv·2 − 1 in
/// Vulkan's clip space, y down).
fn pixel_ray(scene: &Scene, size: [u32; 2], x: u32, y: u32) -> Vec3 {
    let (view, proj) = camera_matrices(scene, size[0] as f32 / size[1] as f32);
    let inv = (proj * view).inverse();
    let uv = Vec2::new((x as f32 + 0.5) / size[0] as f32, (y as f32 + 0.5) / size[1] as f32);
    let p = inv * Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0);
    (p.truncate() / p.w - scene.camera.position).normalize()
}

/// Where the ray from the camera meets the flat water inside its extent, if it does.
fn flat_water_hit(scene: &Scene, dir: Vec3) -> Option<Vec3> {
    let c = scene.camera.position;
    let t = (scene.water.level - c.y) / dir.y;
    let p = c + t * dir;
    let inside = p.x > scene.water.extent_min.x
        && p.x < scene.water.extent_max.x
        && p.z > scene.water.extent_min.y
        && p.z < scene.water.extent_max.y;
    (t > 0.0 && inside).then_some(p)
}

/// Compares the Fresnel reflectance the surface shader mixed with (read back from the
/// albedo×transmittance target's alpha) with the full unpolarised Fresnel equations for each
/// pixel's ray, on flat water. Returns the mean reflectance over the water pixels.
fn check_fresnel(ctx: &underlight::vk::Context, scene: &Scene, size: [u32; 2]) -> f64 {
    let (images, passes) = render(ctx, scene, size);
    assert!(passes.contains(&PassId::Refraction) && passes.contains(&PassId::Reflection), "passes: {passes:?}");
    let ior = scene.water.ior;
    let (mut n, mut sum, mut worst, mut expected_water) = (0usize, 0f64, 0f32, 0usize);
    for y in 0..size[1] {
        for x in 0..size[0] {
            let dir = pixel_ray(scene, size, x, y);
            let measured = images.albedo_transmittance.at(x, y)[3];
            if flat_water_hit(scene, dir).is_some() {
                expected_water += 1;
            }
            if measured <= 0.0 {
                continue; // not the surface (or the surface behind a mesh above the water)
            }
            assert!(
                flat_water_hit(scene, dir).is_some(),
                "pixel ({x}, {y}) has a Fresnel weight but its ray misses the water"
            );
            let formula = 1.0 - underlight::shader_math::fresnel_transmittance(-dir.y, ior);
            // The target is half float: 11 bits of mantissa, 5e-4 relative.
            let err = (measured - formula).abs();
            assert!(err <= 1e-3 * formula + 2e-4, "pixel ({x}, {y}): Fresnel weight {measured}, formula {formula}");
            worst = worst.max(err);
            n += 1;
            sum += measured as f64;
        }
    }
    // Most of the water the camera frames must be shaded from above (the rest: behind the
    // tank's rocks and pillars where they rise out of the water).
    assert!(n * 10 >= expected_water * 8, "only {n} of {expected_water} water pixels shaded from above");
    println!("{n} water pixels, worst Fresnel error {worst:.2e}, mean reflectance {:.3}", sum / n as f64);
    sum / n as f64
}

#[test]
fn fresnel_weight_follows_the_view_angle() {
    let ctx = validated_context();
    let size = [64, 48];
    // Grazing: 5 cm above flat water, looking level with a narrow field, so every ray meets
    // the water at 85–90° incidence.
    let mut grazing = flat(tank());
    grazing.camera.position = Vec3::new(-1.9, 0.05, 0.0);
    grazing.camera.look_at = Vec3::new(2.0, 0.05, 0.0);
    grazing.camera.fov_y_degrees = 8.0;
    let mean_grazing = check_fresnel(&ctx, &grazing, size);
    assert!(mean_grazing > 0.5, "grazing view: mean reflectance {mean_grazing:.3}, expected mostly reflection");
    // Straight down from 1 m: incidence within ~37°, reflectance about 2 %.
    let mut down = flat(tank());
    down.camera.position = Vec3::new(0.3, 1.0, 0.2);
    down.camera.look_at = Vec3::new(0.3, -2.0, 0.2);
    let mean_down = check_fresnel(&ctx, &down, size);
    assert!(mean_down < 0.05, "view straight down: mean reflectance {mean_down:.3}, expected mostly refraction");
    assert_clean_shutdown(ctx);
}

#[test]
fn highlight_and_its_glow_follow_their_formulas() {
    let ctx = validated_context();
    let size = [64, 48];
    // Straight down over flat water: the sun (16° from the zenith) is reflected inside the
    // view, so its highlight and glow are in the image.
    let mut down = flat(tank());
    down.camera.position = Vec3::new(0.3, 1.0, 0.2);
    down.camera.look_at = Vec3::new(0.3, -2.0, 0.2);
    let (images, _) = render(&ctx, &down, size);
    // The uniforms the frame used: the light's irradiance and direction, and the exposure.
    let extents = underlight::frame::target_extents(&down, size, 64.0, 64.0);
    let u = underlight::frame::uniforms::FrameUniforms::new(&down, down.bounds(), &extents, RENDER_TIME);
    let (e_perp, exposure) = (u.light_strength, u.exposure);
    let to_sun = -Vec3::from_array(u.light_axis).normalize();
    // 1. The highlight (scene colour alpha): F · E⊥ · (n + 2)/(2π) · cos^n of the angle between
    //    the reflected ray and the sun, n = 200.
    let (mut peak, mut worst) = (0f32, 0f32);
    for y in 0..size[1] {
        for x in 0..size[0] {
            let dir = pixel_ray(&down, size, x, y);
            let measured = images.scene_color.at(x, y)[3];
            if flat_water_hit(&down, dir).is_none() || images.albedo_transmittance.at(x, y)[3] <= 0.0 {
                assert_eq!(measured, 0.0, "pixel ({x}, {y}) is no water seen from above but has a highlight");
                continue;
            }
            let fresnel = 1.0 - underlight::shader_math::fresnel_transmittance(-dir.y, down.water.ior);
            let r = Vec3::new(dir.x, -dir.y, dir.z);
            let lobe = 202.0 / (2.0 * std::f32::consts::PI) * r.dot(to_sun).max(0.0).powf(200.0);
            let expected = fresnel * e_perp * lobe;
            let err = (measured - expected).abs();
            assert!(
                err <= 2e-3 * expected + 1e-3 * e_perp,
                "pixel ({x}, {y}): highlight {measured}, formula {expected}"
            );
            worst = worst.max(err / e_perp);
            peak = peak.max(expected);
        }
    }
    // Within 1.9° of the lobe's centre somewhere (cos^200 > 1/2): the sun's reflection is in view.
    let centre = (1.0 - underlight::shader_math::fresnel_transmittance(1.0, down.water.ior)) * e_perp * 202.0
        / (2.0 * std::f32::consts::PI);
    assert!(peak > 0.5 * centre, "the sun's reflection is not in view (peak {peak}, lobe centre {centre})");
    // 2. The output: compose adds the glow, the highlights' mean over the 13 texels on the
    //    diagonals of a 7×7 window (thesis §9.3), then tonemaps. Nothing else adds here: the
    //    surface takes no caustics and every ray starts in the air (no godrays in compose).
    let (w, h) = (size[0] as i32, size[1] as i32);
    let alpha = |x: i32, y: i32| images.scene_color.at(x.clamp(0, w - 1) as u32, y.clamp(0, h - 1) as u32)[3];
    let mut with_glow = images.scene_color.clone();
    let mut without_glow = images.scene_color.clone();
    for y in 0..h {
        for x in 0..w {
            let mut sum = 0.0;
            for k in -3..=3 {
                sum += alpha(x + k, y + k);
                if k != 0 {
                    sum += alpha(x + k, y - k);
                }
            }
            let p = &mut with_glow.pixels[(y * w + x) as usize];
            (0..3).for_each(|c| p[c] += sum / 13.0);
            without_glow.pixels[(y * w + x) as usize][3] = 1.0;
        }
    }
    let expected = underlight::image_io::tonemap_srgb8(&with_glow, exposure);
    let unglowed = underlight::image_io::tonemap_srgb8(&without_glow, exposure);
    let off = |a: &[u8]| a.iter().zip(&images.output).map(|(e, o)| (*e as i32 - *o as i32).abs()).max().unwrap_or(0);
    let (err_glow, err_plain) = (off(&expected), off(&unglowed));
    println!("highlight: peak {:.2} E⊥, worst error {worst:.1e} E⊥; output vs compose with glow: max {err_glow} levels, without: {err_plain}", peak / e_perp);
    // The GPU's sRGB encode and the CPU's round differently by a level at most.
    assert!(err_glow <= 1, "output differs from scene + glow by {err_glow} levels");
    assert!(err_plain >= 4, "the glow changes the output by only {err_plain} levels: not visible");
    assert_clean_shutdown(ctx);
}

/// Pearson correlation of two equally long series.
fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    sab / (saa * sbb).sqrt().max(1e-30)
}

fn luminance(p: [f32; 4]) -> f64 {
    (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) as f64
}

/// The tank's floor height (2 m of water under level 0).
const TANK_FLOOR: f32 = -2.0;

/// Where the refracted ray of pixel (x, y) meets the tank's floor plane, in the camera's uv:
/// the CPU twin's surface (exact height, normal and refraction), for the frame at `time`.
fn refracted_floor_uv(scene: &Scene, size: [u32; 2], x: u32, y: u32, noise: &NoiseTexture, time: f32) -> Option<Vec2> {
    let dir = pixel_ray(scene, size, x, y);
    let w = &scene.water;
    let cam = scene.camera.position;
    let t = water_intersect(w, noise, cam, dir, time);
    if t < 0.0 {
        return None;
    }
    let u = cam + t * dir;
    let hg = water_height_grad(w, noise, Vec2::new(u.x, u.z), time);
    let n = water_normal_from_grad(Vec2::new(hg.y, hg.z));
    let r = refract(dir, n, 1.0 / w.ior);
    if r.y >= -1e-3 {
        return None;
    }
    let p = u + r * ((TANK_FLOOR - u.y) / r.y);
    let (view, proj) = camera_matrices(scene, size[0] as f32 / size[1] as f32);
    let c = proj * view * p.extend(1.0);
    let uv = (c.truncate().truncate() / c.w) * 0.5 + 0.5;
    (uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all()).then_some(uv)
}

/// For the water pixels: what the caustics add to the surface's colour (`lit` less
/// `unlit`), and the caustic buffer read where each pixel's refracted ray meets the floor
/// (`refracted`) or straight behind the pixel (`straight`).
struct CausticSamples {
    added: Vec<f64>,
    refracted: Vec<f64>,
    added_straight: Vec<f64>,
    straight: Vec<f64>,
}

fn caustic_samples(
    scene: &Scene,
    lit: &SceneImages,
    unlit: &SceneImages,
    caustics: &HdrImage,
    time: f32,
) -> CausticSamples {
    let noise = NoiseTexture::generate();
    let size = [lit.width, lit.height];
    let mut s = CausticSamples { added: vec![], refracted: vec![], added_straight: vec![], straight: vec![] };
    for y in 0..size[1] {
        for x in 0..size[0] {
            if lit.albedo_transmittance.at(x, y)[3] <= 0.0 {
                continue; // not the surface from above
            }
            let added = luminance(lit.scene_color.at(x, y)) - luminance(unlit.scene_color.at(x, y));
            let (u, v) = ((x as f32 + 0.5) / size[0] as f32, (y as f32 + 0.5) / size[1] as f32);
            s.added_straight.push(added);
            s.straight.push(luminance(sample_bilinear(caustics, u, v)));
            if let Some(uv) = refracted_floor_uv(scene, size, x, y, &noise, time) {
                s.added.push(added);
                s.refracted.push(luminance(sample_bilinear(caustics, uv.x, uv.y)));
            }
        }
    }
    s
}

#[test]
fn caustic_floor_is_seen_through_the_surface() {
    let ctx = validated_context();
    let size = [96, 96];
    // The tank as shipped (waves and noise), seen from 1.2 m above the water, looking down.
    let mut above = tank();
    above.camera.position = Vec3::new(0.3, 1.2, 0.6);
    above.camera.look_at = Vec3::new(0.3, -2.0, -0.2);
    let (lit, passes) = render(&ctx, &above, size);
    assert!(passes.contains(&PassId::Refraction) && passes.contains(&PassId::Caustics), "passes: {passes:?}");
    let caustics = lit.caustics_filtered.as_ref().or(lit.caustics.as_ref()).expect("caustic buffer");
    // The same view without caustics: the difference is what they add to the surface.
    let mut dark = above.clone();
    dark.effects.caustics = false;
    let (unlit, _) = render(&ctx, &dark, size);
    let s = caustic_samples(&above, &lit, &unlit, caustics, RENDER_TIME);
    let pixels = (size[0] * size[1]) as usize;
    assert!(s.added.len() > pixels / 2, "only {} water pixels over the floor", s.added.len());
    let refracted = correlation(&s.added, &s.refracted);
    let straight = correlation(&s.added_straight, &s.straight);
    println!(
        "what the caustics add to the surface correlates {refracted:.3} with the buffer where the refracted rays meet the floor, {straight:.3} straight behind each pixel ({} px)",
        s.added.len()
    );
    // The rocks and the tessellated surface keep it below 1. A surface that read the
    // refraction view at a fixed offset, or straight through, matches `straight` at best.
    assert!(
        refracted > 0.8,
        "the caustic pattern is not where the refracted rays meet the floor: correlation {refracted:.3}"
    );
    assert!(
        refracted > straight + 0.2,
        "refracted {refracted:.3} against straight {straight:.3}: the surface does not follow the refracted rays"
    );
    assert_clean_shutdown(ctx);
}

/// The side of the water each pixel's ray starts on, decided as the shaders decide it: where
/// the ray leaves the near plane, against the flat water's level.
fn starts_under(scene: &Scene, dir: Vec3) -> bool {
    let c = &scene.camera;
    let forward = (c.look_at - c.position).normalize();
    let start = c.position + dir * (c.z_near / dir.dot(forward));
    start.y < scene.water.level
}

#[test]
fn camera_path_through_the_waterline() {
    let ctx = validated_context();
    let size = [48, 36];
    let extent = vk::Extent2D { width: size[0], height: size[1] };
    // A camera that moves, as in the viewer: the passes for both sides exist, and each frame
    // records those its camera needs.
    let mut scene = tank();
    let options = FrameOptions { camera_moves: true, ..FrameOptions::default() };
    let mut r = SceneRenderer::with_options(&ctx.device, &scene, extent, options).expect("renderer");
    let trough = scene.water.level - scene.water.amplitude.abs() - scene.water.noise_amplitude.abs();
    // From 0.6 m above down to 0.6 m under, through the wave band in centimetre steps.
    let mut heights: Vec<f32> = (0..=12).map(|i| 0.6 - 0.1 * i as f32).collect();
    heights.extend((-5..=5).map(|i| 0.01 * i as f32));
    heights.sort_by(|a, b| b.total_cmp(a));
    for (k, &y) in heights.iter().enumerate() {
        scene.camera.position = Vec3::new(-1.5, y, 1.4);
        scene.camera.look_at = Vec3::new(1.0, y - 0.6, -1.0);
        r.frame.scene_mut().camera = scene.camera;
        let (timings, images) = r.render(1, 1.0 + 0.1 * k as f32, 0.0, true).expect("render");
        let images = images.expect("read back");
        for (name, image) in
            [("scene colour", &images.scene_color), ("albedo × transmittance", &images.albedo_transmittance)]
        {
            if let Some(i) = image.pixels.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
                panic!("camera at y = {y}: {name} pixel {i} is {:?}", image.pixels[i]);
            }
        }
        for (name, image) in [("caustics", &images.caustics), ("godrays", &images.godrays)] {
            let image = image.as_ref().expect("effect buffer");
            assert!(
                image.pixels.iter().all(|p| p.iter().all(|c| c.is_finite())),
                "camera at y = {y}: {name} not finite"
            );
        }
        let recorded: Vec<PassId> = timings.last().expect("frame").passes.iter().map(|p| p.0).collect();
        let above = y + 2.0 * scene.camera.z_near >= trough;
        assert_eq!(recorded.contains(&PassId::Refraction), above, "camera at y = {y}: passes {recorded:?}");
        assert_eq!(recorded.contains(&PassId::Reflection), above, "camera at y = {y}: passes {recorded:?}");
    }
    drop(r);
    assert_clean_shutdown(ctx);
}

#[test]
fn waterline_splits_the_image_where_the_rays_start() {
    let ctx = validated_context();
    let size = [64, 48];
    // Flat water, the camera 4 mm above and under it, looking level: the surface crosses the
    // image at the horizon. Each pixel must take the side its ray starts on: from above,
    // every pixel whose ray meets the water shows it with a Fresnel weight; from below none
    // does (the surface seen from below has no reflection pass to mix).
    for y in [0.004f32, -0.004] {
        let mut scene = flat(tank());
        scene.camera.position = Vec3::new(-1.9, y, 0.1);
        scene.camera.look_at = Vec3::new(2.0, y, 0.1);
        let (images, _) = render(&ctx, &scene, size);
        let (mut wrong, mut water) = (0, 0);
        for py in 0..size[1] {
            for px in 0..size[0] {
                let dir = pixel_ray(&scene, size, px, py);
                let fresnel = images.albedo_transmittance.at(px, py)[3];
                let from_above = dir.y < 0.0 && !starts_under(&scene, dir) && flat_water_hit(&scene, dir).is_some();
                water += from_above as usize;
                // A mesh above the water can hide the surface (alpha 0): only a weight where the
                // ray cannot see the surface from above is wrong, or none on the open water
                // right under the horizon, which nothing hides.
                let near_horizon = dir.y > -0.05;
                if (fresnel > 0.0 && !from_above) || (from_above && near_horizon && fresnel <= 0.0) {
                    wrong += 1;
                }
            }
        }
        println!("camera at y = {y}: {water} pixels see the water from above, {wrong} on the wrong side");
        assert!(wrong <= size[0] as usize, "camera at y = {y}: {wrong} pixels on the wrong side of the waterline");
        if y < 0.0 {
            assert_eq!(water, 0);
        } else {
            assert!(water > 0);
        }
    }
    assert_clean_shutdown(ctx);
}
