//! The geometry-shader photon grid, end to end on the real driver: every texel of the
//! read-back target must equal a CPU rasterisation of the same photons (positions from the
//! Rust twin of the shader math, Vulkan's point-coverage rule), exactly. A wrong
//! subdivision constant, a lost photon, a wrong point size or broken blending changes texels.

mod common;

use common::{assert_clean_shutdown, validated_context};
use glam::{UVec2, Vec2};
use std::time::Instant;
use underlight::grid_splat::{render_grid_splat, DemoPass, GridSplatRenderer, GridSplatSettings};
use underlight::image_io::HdrImage;
use underlight::shader_math::photon_grid_uv;
use underlight::vk::vk;
use underlight::Error;

/// CPU rasterisation of the pass with wave displacement off: photon k of cell c sits at
/// `photon_grid_uv` × extent; a point of size s covers the texels whose centres lie inside
/// the s×s square around it (Vulkan's point rule). Returns (energy image, photons that fell
/// exactly on a coverage edge — which would make the expectation ambiguous).
fn cpu_splat(settings: &GridSplatSettings, extent: UVec2) -> (Vec<[f32; 4]>, usize) {
    let mut image = vec![[0.0f32; 4]; (extent.x * extent.y) as usize];
    let mut ambiguous = 0;
    let half = settings.point_size / 2.0;
    let grid = UVec2::splat(settings.grid);
    for cy in 0..settings.grid {
        for cx in 0..settings.grid {
            for sy in 0..settings.subdivision {
                for sx in 0..settings.subdivision {
                    let uv = photon_grid_uv(UVec2::new(cx, cy), UVec2::new(sx, sy), settings.subdivision, grid);
                    let p = uv * extent.as_vec2();
                    for y in 0..extent.y {
                        for x in 0..extent.x {
                            let d = (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - p).abs();
                            if (d.x - half).abs() < 1e-3 || (d.y - half).abs() < 1e-3 {
                                ambiguous += 1;
                            }
                            if d.x < half && d.y < half {
                                let t = &mut image[(y * extent.x + x) as usize];
                                for c in &mut t[..3] {
                                    *c += settings.energy;
                                }
                                t[3] += 1.0;
                            }
                        }
                    }
                }
            }
        }
    }
    (image, ambiguous)
}

fn check_exact(settings: GridSplatSettings, spacing: u32) {
    // The target is grid × subdivision × spacing texels wide, so photons sit on texel centres
    // `spacing` apart (spacing odd), and odd point sizes cover whole texels.
    let side = settings.grid * settings.subdivision * spacing;
    let extent = vk::Extent2D { width: side, height: side };
    let (expected, ambiguous) = cpu_splat(&settings, UVec2::splat(side));
    assert_eq!(ambiguous, 0, "test set-up puts a texel centre on a point edge");

    let ctx = validated_context();
    let (image, timings) = render_grid_splat(&ctx.device, extent, settings, 3, 0.0, 0.0).unwrap();
    let HdrImage { width, height, pixels } = &image;
    assert_eq!((*width, *height), (side, side));
    let mut wrong = 0;
    for (i, (got, want)) in pixels.iter().zip(&expected).enumerate() {
        if got != want {
            if wrong < 5 {
                eprintln!("texel ({}, {}): got {got:?}, want {want:?}", i as u32 % side, i as u32 / side);
            }
            wrong += 1;
        }
    }
    assert_eq!(wrong, 0, "{wrong} texels differ from the CPU rasterisation for {settings:?}");
    // The figure a correct pipeline gives: every photon adds point_size² texels.
    let photons = settings.photon_count() as f64;
    let coverage = image.channel_sums()[3];
    let per_photon = (settings.point_size as f64).powi(2);
    if spacing as f64 >= settings.point_size as f64 {
        assert_eq!(coverage, photons * per_photon);
    }
    // Every frame was timed, each pass with a positive GPU time.
    assert_eq!(timings.len(), 3);
    for t in &timings {
        assert!(t.get(DemoPass::GridSplat).unwrap() > 0.0, "{t}");
    }
    assert!(timings.last().unwrap().get(DemoPass::Readback).unwrap() > 0.0);
    assert_clean_shutdown(ctx);
}

fn settings(grid: u32, subdivision: u32, point_size: f32) -> GridSplatSettings {
    GridSplatSettings { grid, subdivision, point_size, energy: 0.25, wave_amplitude: 0.0 }
}

#[test]
fn one_texel_points_tile_the_target_exactly() {
    check_exact(settings(8, 2, 1.0), 1);
}

#[test]
fn separated_points_cover_point_size_squared_texels() {
    check_exact(settings(4, 3, 3.0), 5);
}

#[test]
fn overlapping_points_add_up() {
    check_exact(settings(3, 2, 7.0), 5);
}

#[test]
fn largest_subdivision_emits_every_photon() {
    check_exact(settings(2, 8, 1.0), 3);
}

#[test]
fn timings_are_plausible_against_wall_clock() {
    // GPU time of the passes cannot exceed the wall time of the frames that contain them; a
    // wrong timestampPeriod scale or unmasked garbage bits would.
    let ctx = validated_context();
    let s = GridSplatSettings { grid: 64, subdivision: 2, point_size: 5.0, energy: 0.1, wave_amplitude: 1.0 };
    let mut renderer = GridSplatRenderer::new(&ctx.device, vk::Extent2D { width: 256, height: 256 }, s).unwrap();
    let start = Instant::now();
    let (timings, image) = renderer.render(6, 0.0, 0.1, false).unwrap();
    let wall_ms = start.elapsed().as_secs_f64() * 1e3;
    assert!(image.is_none());
    assert_eq!(timings.len(), 6, "one timing table per frame");
    let gpu_ms: f64 = timings.iter().map(|t| t.total_ms()).sum();
    assert!(gpu_ms > 0.0 && gpu_ms <= wall_ms, "GPU {gpu_ms} ms vs wall {wall_ms} ms");
    drop(renderer);
    assert_clean_shutdown(ctx);
}

#[test]
fn out_of_range_settings_are_named_errors() {
    let ctx = validated_context();
    let extent = vk::Extent2D { width: 16, height: 16 };
    for (s, name) in [
        (settings(4, 9, 1.0), "subdivision"),
        (settings(4, 0, 1.0), "subdivision"),
        (settings(0, 2, 1.0), "grid"),
        (settings(4, 2, 1.0e6), "point_size"),
        (settings(4, 2, f32::NAN), "point_size"),
    ] {
        match GridSplatRenderer::new(&ctx.device, extent, s) {
            Err(Error::InvalidParameter { name: n, message }) => {
                assert_eq!(n, name, "{message}");
                assert!(!message.is_empty());
            }
            Err(e) => panic!("{s:?}: expected an InvalidParameter error naming {name}, got {e}"),
            Ok(_) => panic!("{s:?} was accepted"),
        }
    }
    assert_clean_shutdown(ctx);
}
