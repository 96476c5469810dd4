//! Per-pass GPU timing benchmarks. Criterion's statistics apply to GPU time: `iter_custom`
//! returns the sum of the pass's timestamp durations, not wall time.
//!
//! `cargo bench --bench passes` measures; `cargo test --bench passes` (part of the test
//! command) runs each benchmark once as a smoke test. Two groups: the foundation's grid
//! splat at the paper's grid sizes, and every pass of the frame on the built-in scenes. Validation is off here: the layers
//! would dominate the times. Pick the device with UNDERLIGHT_DEVICE.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::time::Duration;
use underlight::grid_splat::{DemoPass, GridSplatRenderer, GridSplatSettings};
use underlight::headless::SceneRenderer;
use underlight::vk::{vk, Context, ContextDesc};

/// (label, target side, grid, subdivision, point size)
const CONFIGS: &[(&str, u32, u32, u32, f32)] = &[
    // The paper's godray grid and caustic grid at its 512² caustic target.
    ("paper-godray-grid", 512, 100, 2, 5.0),
    ("paper-caustic-grid", 512, 200, 2, 5.0),
    // The paper's high setting: 1M photons, small points.
    ("paper-high-grid", 512, 500, 2, 2.0),
];

fn grid_splat(c: &mut Criterion) {
    let mut desc = ContextDesc::from_env();
    desc.validation = false;
    let ctx = Context::new(&desc).expect("Vulkan context");
    eprintln!("device: {}", ctx.device.info.describe());
    let mut group = c.benchmark_group("grid_splat");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(5));
    for &(label, side, grid, subdivision, point_size) in CONFIGS {
        let settings = GridSplatSettings { grid, subdivision, point_size, energy: 0.05, wave_amplitude: 1.3 };
        let mut renderer =
            GridSplatRenderer::new(&ctx.device, vk::Extent2D { width: side, height: side }, settings).unwrap();
        group.throughput(Throughput::Elements(settings.photon_count()));
        group.bench_function(BenchmarkId::new(label, settings.photon_count()), |b| {
            b.iter_custom(|iters| {
                let (timings, _) = renderer.render(iters as u32, 0.0, 1.0 / 60.0, false).unwrap();
                let ms: f64 = timings.iter().filter_map(|t| t.get(DemoPass::GridSplat)).sum();
                assert!(ms > 0.0, "the pass reported no GPU time");
                Duration::from_secs_f64(ms * 1e-3)
            })
        });
    }
    group.finish();
    let report = ctx.shutdown();
    assert!(report.is_clean(), "{report}");
}

/// Every pass of the method's frame on the built-in scenes at the paper's settings: one
/// benchmark per pass, each returning only that pass's GPU time.
fn frame_passes(c: &mut Criterion) {
    let mut desc = ContextDesc::from_env();
    desc.validation = false;
    let ctx = Context::new(&desc).expect("Vulkan context");
    // UNDERLIGHT_BENCH_SCENES=tank,port,storage picks scenes; the tank alone by default.
    let scenes = std::env::var("UNDERLIGHT_BENCH_SCENES").unwrap_or_else(|_| "tank".into());
    // Each scene twice: from its camera (under the water) and from that camera mirrored
    // above the water, where the refraction and reflection passes run.
    for (name, above) in scenes.split(',').flat_map(|n| [(n, false), (n, true)]) {
        let mut scene = underlight::scene::load(name).expect("scene");
        if above {
            underlight::bench::move_camera_above_water(&mut scene);
        }
        let out = vk::Extent2D { width: scene.output[0], height: scene.output[1] };
        let mut renderer = SceneRenderer::new(&ctx.device, &scene, out).unwrap();
        let mut group = c.benchmark_group(format!("frame/{name}{}", if above { "-above" } else { "" }));
        group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(5));
        for pass in renderer.frame.plan.passes.clone() {
            group.bench_function(pass.name(), |b| {
                b.iter_custom(|iters| {
                    let (timings, _) = renderer.render(iters as u32, 0.0, 1.0 / 60.0, false).unwrap();
                    let ms: f64 = timings.iter().filter_map(|t| t.get(pass)).sum();
                    assert!(ms > 0.0, "{pass} reported no GPU time");
                    Duration::from_secs_f64(ms * 1e-3)
                })
            });
        }
        group.finish();
    }
    let report = ctx.shutdown();
    assert!(report.is_clean(), "{report}");
}

criterion_group!(benches, grid_splat, frame_passes);
criterion_main!(benches);
