//! Scenes: the built-in scenes load and are what they claim to be (dimensions, a camera under
//! water, closed solids whose faces wind outward, lit receivers at several depths); the
//! committed assets are byte for byte what the generator writes; and bad scene files and OBJ
//! files fail with errors that name the file, the line or field, and the allowed range.

use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};
use underlight::scene::{self, generate, obj, GodrayMethod, LightKind, Mesh, Scene, WaterModel};

/// A fresh scratch folder for one test (tests run in parallel in one process, so the tag
/// must be unique per test).
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("underlight-scene-{tag}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The source tree's assets (not `$UNDERLIGHT_ASSETS`): what is committed.
fn source_assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets")
}

fn assert_close(actual: f32, expected: f32, tolerance: f32, what: &str) {
    assert!((actual - expected).abs() <= tolerance, "{what}: {actual} is not within {tolerance} of {expected}");
}

fn mesh<'a>(scene: &'a Scene, name: &str) -> &'a Mesh {
    scene.meshes.iter().find(|m| m.name == name).unwrap_or_else(|| {
        let names: Vec<&str> = scene.meshes.iter().map(|m| m.name.as_str()).collect();
        panic!("{}: no mesh {name:?} in {names:?}", scene.name)
    })
}

fn mesh_bounds(m: &Mesh) -> (Vec3, Vec3) {
    m.positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
}

fn triangles(m: &Mesh) -> impl Iterator<Item = [Vec3; 3]> + '_ {
    m.indices.chunks_exact(3).map(|t| [0, 1, 2].map(|k| m.positions[t[k] as usize]))
}

/// The triangle's normal from its winding (counter-clockwise = front).
fn winding_normal([a, b, c]: [Vec3; 3]) -> Vec3 {
    (b - a).cross(c - a).normalize()
}

/// Number of triangles a ray from `origin` along `dir` crosses (Möller–Trumbore).
fn crossings(m: &Mesh, origin: Vec3, dir: Vec3) -> usize {
    triangles(m)
        .filter(|[a, b, c]| {
            let (e1, e2) = (*b - *a, *c - *a);
            let p = dir.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-12 {
                return false;
            }
            let s = origin - *a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = dir.dot(q) / det;
            let t = e2.dot(q) / det;
            u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0
        })
        .count()
}

/// Whether `p` is inside the (closed) mesh: odd crossings, by a majority of three rays in
/// unrelated directions so that a ray grazing an edge cannot decide alone.
fn inside(m: &Mesh, p: Vec3) -> bool {
    let dirs =
        [Vec3::new(0.3127, 0.8459, 0.4321), Vec3::new(-0.7072, 0.1234, 0.6969), Vec3::new(0.2718, -0.5772, -0.7701)];
    dirs.iter().filter(|d| crossings(m, p, d.normalize()) % 2 == 1).count() >= 2
}

// ---------------------------------------------------------------------------------------------
// The built-in scenes.

fn builtins() -> Vec<Scene> {
    scene::BUILTIN_SCENES.iter().map(|name| scene::load(name).unwrap_or_else(|e| panic!("{name}: {e:#}"))).collect()
}

#[test]
fn every_builtin_scene_loads_with_valid_meshes() {
    let scenes = builtins();
    assert_eq!(scenes.len(), 3);
    for s in &scenes {
        assert!(s.meshes.len() >= 6, "{}: only {} meshes", s.name, s.meshes.len());
        for m in &s.meshes {
            let what = format!("{}/{}", s.name, m.name);
            assert!(!m.indices.is_empty() && m.indices.len() % 3 == 0, "{what}");
            assert_eq!(m.positions.len(), m.normals.len(), "{what}");
            assert!(m.indices.iter().all(|&i| (i as usize) < m.positions.len()), "{what}: index out of range");
            assert!(m.positions.iter().all(|p| p.is_finite()), "{what}: non-finite position");
            for n in &m.normals {
                assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-4, "{what}: normal {n} is not unit");
            }
            assert!(m.albedo.min_element() >= 0.0 && m.albedo.max_element() <= 1.0, "{what}: albedo {}", m.albedo);
            // Vertex normals lean the same way as the winding, so shading and culling agree.
            for t in m.indices.chunks_exact(3) {
                let face = winding_normal([0, 1, 2].map(|k| m.positions[t[k] as usize]));
                for &i in t {
                    assert!(face.dot(m.normals[i as usize]) > 0.0, "{what}: vertex normal against the winding");
                }
            }
        }
        // Distinct materials, not one grey.
        let mut albedos: Vec<[u32; 3]> =
            s.meshes.iter().map(|m| (m.albedo * 1000.0).round().as_uvec3().to_array()).collect();
        albedos.sort();
        albedos.dedup();
        assert!(albedos.len() >= 5, "{}: only {} distinct albedos", s.name, albedos.len());
    }
}

#[test]
fn builtin_meshes_are_closed_solids_with_outward_faces() {
    for s in builtins() {
        for m in &s.meshes {
            // Signed volume (divergence theorem): positive only if faces wind outward overall.
            let volume: f32 = triangles(m).map(|[a, b, c]| a.dot(b.cross(c)) / 6.0).sum();
            assert!(volume > 0.0, "{}/{}: signed volume {volume}", s.name, m.name);
            // And face by face: just behind every (sampled) face is the inside of the mesh.
            let count = m.indices.len() / 3;
            let stride = count.div_ceil(150);
            for t in triangles(m).step_by(stride) {
                let centroid = (t[0] + t[1] + t[2]) / 3.0;
                let behind = centroid - winding_normal(t) * 1e-3;
                assert!(inside(m, behind), "{}/{}: face at {centroid} winds inward", s.name, m.name);
            }
        }
    }
}

#[test]
fn builtin_cameras_are_under_water_inside_the_scene_and_in_no_solid() {
    for s in builtins() {
        let c = s.camera;
        assert!(c.position.y < s.water.level, "{}: camera at {} is not under water", s.name, c.position);
        let (lo, hi) = s.bounds();
        assert!(c.position.cmpgt(lo).all() && c.position.cmplt(hi).all(), "{}: camera outside {lo}..{hi}", s.name);
        let xz = Vec2::new(c.position.x, c.position.z);
        assert!(
            xz.cmpgt(s.water.extent_min).all() && xz.cmplt(s.water.extent_max).all(),
            "{}: camera outside the water",
            s.name
        );
        for m in &s.meshes {
            assert!(!inside(m, c.position), "{}: camera inside {}", s.name, m.name);
        }
        assert!(c.z_far > (hi - lo).length() * 0.5, "{}: z_far {} does not cover the scene", s.name, c.z_far);
        // The paper's light and medium.
        assert_eq!(s.light.kind, LightKind::Directional);
        assert_close(s.light.intensity, 9.2, 1e-6, "intensity");
        assert!(s.light.direction.y < -0.9 && s.light.direction.y > -1.0, "{}: light {}", s.name, s.light.direction);
        assert_close(s.light.direction.length(), 1.0, 1e-6, "light direction length");
        assert_eq!(s.medium.gamma, Vec3::splat(0.13));
        assert_close(s.water.level, 0.0, 0.0, "water level");
    }
}

/// Lit receivers at several depths: up-facing surfaces under water at distinct heights, which
/// is where caustics land and what shadow shafts end on.
#[test]
fn builtin_scenes_have_receivers_at_several_depths() {
    for s in builtins() {
        let mut depths: Vec<i32> = s
            .meshes
            .iter()
            .flat_map(|m| triangles(m).filter(|t| winding_normal(*t).y > 0.9).map(|t| (t[0] + t[1] + t[2]).y / 3.0))
            .filter(|y| *y < s.water.level)
            .map(|y| (y * 10.0).round() as i32)
            .collect();
        depths.sort();
        depths.dedup();
        assert!(depths.len() >= 4, "{}: receivers only at depths {depths:?} dm", s.name);
        // And occluders that reach above the floor into the water column.
        let (lo, _) = s.bounds();
        let tall = s.meshes.iter().filter(|m| {
            let (mlo, mhi) = mesh_bounds(m);
            mhi.y > mlo.y + 0.5 && mhi.y > lo.y + 1.0 && mlo.y < s.water.level
        });
        assert!(tall.count() >= 3, "{}: too few occluders in the water", s.name);
    }
}

#[test]
fn tank_is_a_4m_tank_with_2m_of_water_and_walls_above_it() {
    let s = scene::load("tank").unwrap();
    assert_eq!(s.output, [800, 800]);
    assert_eq!(s.water.model, WaterModel::CircularCosine);
    assert_close(s.water.amplitude, 0.03, 1e-6, "amplitude");
    assert_close(s.water.wavelength, 0.8, 1e-6, "wavelength");
    let (lo, hi) = s.bounds();
    assert!((lo - Vec3::new(-2.1, -2.3, -2.1)).abs().max_element() < 1e-3, "{lo}");
    assert!((hi - Vec3::new(2.1, 0.5, 2.1)).abs().max_element() < 1e-3, "{hi}");
    assert_close(mesh_bounds(mesh(&s, "floor")).1.y, -2.0, 1e-4, "floor top");
    let (wall_lo, wall_hi) = mesh_bounds(mesh(&s, "walls"));
    assert!(wall_lo.y <= -2.0 && wall_hi.y > s.water.level + 0.4, "walls {wall_lo}..{wall_hi}");
    assert_eq!((s.water.extent_min, s.water.extent_max), (Vec2::splat(-2.0), Vec2::splat(2.0)));
    // The ledge is at mid-depth on the east wall.
    let (ledge_lo, ledge_hi) = mesh_bounds(mesh(&s, "ledge"));
    assert!(ledge_hi.x > 1.99 && ledge_hi.y > -1.3 && ledge_hi.y < -0.7, "ledge {ledge_lo}..{ledge_hi}");
    // One pillar breaks the surface, one stays under it.
    assert!(mesh_bounds(mesh(&s, "pillar_tall")).1.y > s.water.level);
    assert!(mesh_bounds(mesh(&s, "pillar_short")).1.y < s.water.level);
    assert_close(s.camera.z_far, 20.0, 1e-6, "z_far");
}

#[test]
fn port_is_a_harbour_with_a_sloping_seabed_piles_and_a_floating_hull() {
    let s = scene::load("port").unwrap();
    assert_eq!(s.output, [1440, 850]);
    assert_eq!(s.water.model, WaterModel::AxisCosineNoise);
    assert_close(s.water.noise_amplitude, 0.08, 1e-6, "noise amplitude");
    let (lo, hi) = s.bounds();
    assert!(lo.x <= -14.9 && hi.x >= 14.9 && lo.z <= -14.9 && hi.z >= 14.9, "{lo}..{hi}");
    // Seabed: about 2 m deep at the quay, 6 m offshore.
    let seabed = mesh(&s, "seabed");
    let top: Vec<Vec3> =
        seabed.positions.iter().zip(&seabed.normals).filter(|(_, n)| n.y > 0.5).map(|(p, _)| *p).collect();
    let near_quay: Vec<f32> = top.iter().filter(|p| p.z < -11.5).map(|p| p.y).collect();
    let offshore: Vec<f32> = top.iter().filter(|p| p.z > 14.5).map(|p| p.y).collect();
    assert!(!near_quay.is_empty() && near_quay.iter().all(|y| (y + 2.0).abs() < 0.35), "{near_quay:?}");
    assert!(!offshore.is_empty() && offshore.iter().all(|y| (y + 6.0).abs() < 0.35), "{offshore:?}");
    // The quay rises above the water; the piles stand from the seabed to above it.
    assert!(mesh_bounds(mesh(&s, "quay")).1.y > 1.0);
    let (piles_lo, piles_hi) = mesh_bounds(mesh(&s, "piles"));
    assert!(piles_lo.y < -2.0 && piles_hi.y > s.water.level, "piles {piles_lo}..{piles_hi}");
    // The hull floats: keel 1.2 m down, deck above the water.
    let (hull_lo, hull_hi) = mesh_bounds(mesh(&s, "hull"));
    assert_close(hull_lo.y, -1.2, 0.01, "keel");
    assert!(hull_hi.y > s.water.level + 0.3, "deck {hull_hi}");
    assert_eq!((s.water.extent_min, s.water.extent_max), (Vec2::new(-15.0, -12.0), Vec2::splat(15.0)));
}

#[test]
fn storage_is_a_flooded_hall_with_racking_under_and_above_water() {
    let s = scene::load("storage").unwrap();
    assert_eq!(s.output, [1440, 850]);
    let (lo, hi) = s.bounds();
    assert!((lo - Vec3::new(-8.2, -3.3, -6.2)).abs().max_element() < 1e-3, "{lo}");
    assert!((hi - Vec3::new(8.2, 2.0, 6.2)).abs().max_element() < 1e-3, "{hi}");
    assert_close(mesh_bounds(mesh(&s, "floor")).1.y, -3.0, 1e-4, "floor top");
    // Shelf boards at three heights: two under water, one above.
    let boards = mesh(&s, "rack_boards");
    let mut tops: Vec<i32> =
        triangles(boards).filter(|t| winding_normal(*t).y > 0.9).map(|t| (t[0].y * 100.0).round() as i32).collect();
    tops.sort();
    tops.dedup();
    assert_eq!(tops.len(), 3, "{tops:?}");
    assert_eq!(tops.iter().filter(|&&y| y < 0).count(), 2, "{tops:?}");
    assert!(!mesh(&s, "crates").indices.is_empty() && !mesh(&s, "columns").indices.is_empty());
    assert_close(s.camera.position.y, -1.5, 1e-6, "camera height");
}

// ---------------------------------------------------------------------------------------------
// The committed assets are the generator's output.

#[test]
fn committed_assets_are_what_the_generator_writes() {
    let fresh = scratch("fresh");
    let written = generate::write_builtin_assets(&fresh).unwrap();
    assert_eq!(written.len(), 9);
    let committed = source_assets().join("scenes");
    for path in &written {
        let name = path.file_name().unwrap();
        let ours = std::fs::read(path).unwrap();
        let theirs = std::fs::read(committed.join(name)).unwrap_or_else(|e| {
            panic!(
                "{} is not committed ({e}): run `cargo test --test scene -- --ignored regenerate`",
                name.to_string_lossy()
            )
        });
        assert!(
            ours == theirs,
            "assets/scenes/{} is stale: run `cargo test --test scene -- --ignored regenerate`",
            name.to_string_lossy()
        );
        assert!(ours.len() < 1 << 20, "{} is over 1 MB", name.to_string_lossy());
    }
    let stale = generate::stale_builtin_assets(&source_assets()).unwrap();
    assert!(stale.is_empty(), "{stale:?}");
    // Same bytes on every run.
    let again = scratch("fresh-again");
    for (a, b) in written.iter().zip(generate::write_builtin_assets(&again).unwrap()) {
        assert_eq!(std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
    }
    std::fs::remove_dir_all(&fresh).ok();
    std::fs::remove_dir_all(&again).ok();
}

#[test]
fn the_freshness_check_reports_changed_missing_and_orphan_files() {
    let dir = scratch("stale");
    generate::write_builtin_assets(&dir).unwrap();
    assert!(generate::stale_builtin_assets(&dir).unwrap().is_empty());
    let scenes = dir.join("scenes");
    let toml = std::fs::read_to_string(scenes.join("tank.toml")).unwrap();
    std::fs::write(scenes.join("tank.toml"), toml.replace("intensity = 9.2\n", "intensity = 9.3\n")).unwrap();
    std::fs::remove_file(scenes.join("port.mtl")).unwrap();
    std::fs::write(scenes.join("extra.obj"), "v 0 0 0\n").unwrap();
    let stale = generate::stale_builtin_assets(&dir).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(stale.len(), 3, "{stale:?}");
    assert!(stale.iter().any(|s| s.contains("tank.toml") && s.contains("differs")), "{stale:?}");
    assert!(stale.iter().any(|s| s.contains("port.mtl") && s.contains("missing")), "{stale:?}");
    assert!(stale.iter().any(|s| s.contains("extra.obj") && s.contains("orphan")), "{stale:?}");
}

/// Not a check: rewrites `assets/scenes/` from the generator.
/// `cargo test --test scene -- --ignored regenerate`
#[test]
#[ignore = "writes into the source tree"]
fn regenerate_builtin_assets() {
    for path in generate::write_builtin_assets(&source_assets()).unwrap() {
        println!("wrote {}", path.display());
    }
}

// ---------------------------------------------------------------------------------------------
// Scene files: a valid one, then one mistake at a time.

const BOX_OBJ: &str = "\
# a 1 m cube on the origin's floor, no normals
v -0.5 0 -0.5
v 0.5 0 -0.5
v 0.5 1 -0.5
v -0.5 1 -0.5
v -0.5 0 0.5
v 0.5 0 0.5
v 0.5 1 0.5
v -0.5 1 0.5
f 1 4 3 2
f 5 6 7 8
f 1 5 8 4
f 2 3 7 6
f 1 2 6 5
f 4 8 7 3
";

const VALID: &str = r#"name = "fixture"

[[objects]]
obj = "box.obj"

[camera]
position = [0.0, -1.0, 3.0]
look_at = [0.0, -1.0, 0.0]
fov_y_degrees = 60.0
z_near = 0.05
z_far = 40.0

[light]
kind = "directional"
direction = [0.2, -1.0, 0.1]
intensity = 9.2

[water]
model = "circular-cosine"
level = 0.0
amplitude = 0.04
wavelength = 1.2
speed = 0.5
noise_amplitude = 0.01
noise_scale = 4.0
extent_min = [-2.0, -2.0]
extent_max = [2.0, 2.0]
"#;

/// A folder holding `box.obj`, for scene files named `<dir>/x.toml`.
fn fixture(tag: &str) -> PathBuf {
    let dir = scratch(tag);
    std::fs::write(dir.join("box.obj"), BOX_OBJ).unwrap();
    dir
}

/// `VALID` with one edit; the edit must apply, or the test would test nothing.
fn edit(from: &str, to: &str) -> String {
    assert!(VALID.contains(from), "{from:?} is not in the valid scene");
    VALID.replacen(from, to, 1)
}

/// Loads `text` as `<dir>/x.toml` and returns the full error chain.
fn error_of(dir: &Path, text: &str) -> String {
    match scene::load_str(text, &dir.join("x.toml")) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => format!("{e:#}"),
    }
}

/// The error names the file, and contains each of `parts`.
fn assert_error(dir: &Path, text: &str, parts: &[&str]) {
    let message = error_of(dir, text);
    assert!(message.contains("x.toml"), "does not name the file: {message}");
    for part in parts {
        assert!(message.contains(part), "{part:?} not in: {message}");
    }
}

#[test]
fn a_valid_scene_file_loads_with_defaults() {
    let dir = fixture("valid");
    let s = scene::load_str(VALID, &dir.join("x.toml")).unwrap();
    assert_eq!(s.name, "fixture");
    assert_eq!(s.output, [800, 800]);
    assert_eq!(s.medium, scene::Medium::default());
    assert_eq!(s.effects, scene::Effects::default());
    assert_eq!(s.water.ior, 1.333);
    assert_eq!(s.water.center, Vec2::ZERO);
    assert_eq!(s.light.distance, 100.0);
    assert!((s.light.direction - Vec3::new(0.2, -1.0, 0.1).normalize()).length() < 1e-6);
    assert_eq!(s.meshes.len(), 1);
    // The quads were triangulated, the missing normals computed.
    assert_eq!(s.meshes[0].indices.len(), 36);
    assert!(s.meshes[0].normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
    // Also through `load` with a path.
    std::fs::write(dir.join("x.toml"), VALID).unwrap();
    assert_eq!(scene::load(dir.join("x.toml").to_str().unwrap()).unwrap().name, "fixture");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn optional_sections_override_the_defaults() {
    let dir = fixture("optional");
    let text = format!(
        "{VALID}\n[output]\nwidth = 320\nheight = 200\n\n[medium]\ngamma = [0.1, 0.2, 0.3]\nscattering = 0.0\nhg_g = -0.5\n\n\
         [effects]\ngodrays = false\ncaustic_grid = 64\nshadow_map_size = 2048\n"
    );
    let s = scene::load_str(&text, &dir.join("x.toml")).unwrap();
    assert_eq!(s.output, [320, 200]);
    assert_eq!(s.medium.gamma, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!((s.medium.scattering, s.medium.hg_g), (0.0, -0.5));
    assert!(!s.effects.godrays && s.effects.caustics);
    assert_eq!((s.effects.caustic_grid, s.effects.shadow_map_size), (64, 2048));
    assert_eq!(s.effects.iterations, scene::Effects::default().iterations);
    // A single gamma applies to all channels.
    let single = format!("{VALID}\n[medium]\ngamma = 0.2\n");
    assert_eq!(scene::load_str(&single, &dir.join("x.toml")).unwrap().medium.gamma, Vec3::splat(0.2));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn objects_are_scaled_then_rotated_then_translated() {
    let dir = fixture("transform");
    let text = edit(
        "obj = \"box.obj\"\n",
        "obj = \"box.obj\"\nscale = 2.0\nrotate_y_degrees = 90.0\ntranslate = [1.0, 2.0, 3.0]\n",
    );
    let s = scene::load_str(&text, &dir.join("x.toml")).unwrap();
    let m = &s.meshes[0];
    // The box corner (0.5, 1, -0.5): scaled (1, 2, -1), turned 90° counter-clockwise seen
    // from above (+x goes to -z): (-1, 2, -1), moved: (0, 4, 2).
    assert!(m.positions.iter().any(|p| (*p - Vec3::new(0.0, 4.0, 2.0)).length() < 1e-5), "{:?}", m.positions);
    let (lo, hi) = mesh_bounds(m);
    assert!(
        (lo - Vec3::new(0.0, 2.0, 2.0)).length() < 1e-5 && (hi - Vec3::new(2.0, 4.0, 4.0)).length() < 1e-5,
        "{lo}..{hi}"
    );
    // Normals turn with the mesh and stay unit.
    assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn unknown_fields_are_errors_naming_the_field() {
    let dir = fixture("unknown");
    assert_error(
        &dir,
        &edit("speed = 0.5\n", "speed = 0.5\ncolour = 1\n"),
        &["water.colour", "unknown field", "x.toml:"],
    );
    assert_error(&dir, &format!("foo = 1\n{VALID}"), &["unknown field `foo`"]);
    assert_error(&dir, &edit("obj = \"box.obj\"\n", "obj = \"box.obj\"\nscael = 2.0\n"), &["objects[0].scael"]);
    assert_error(&dir, &format!("{VALID}\n[lights]\nkind = 1\n"), &["x.toml:29:2: unknown field `lights`"]);
    assert_error(&dir, &format!("{VALID}\n[[objectz]]\nobj = 1\n"), &["unknown field `objectz`"]);
    assert_error(&dir, &edit("speed = 0.5\n", "speed = 0.5\nwater = 1\n"), &["unknown field `water.water`"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn missing_required_fields_are_errors_naming_the_field() {
    let dir = fixture("missing");
    assert_error(&dir, &edit("wavelength = 1.2\n", ""), &["missing required field `water.wavelength`"]);
    assert_error(&dir, &edit("obj = \"box.obj\"\n", "scale = 1.0\n"), &["missing required field `objects[0].obj`"]);
    assert_error(&dir, &edit("name = \"fixture\"\n", ""), &["missing required field `name`"]);
    let no_camera = VALID.replace(
        "[camera]\nposition = [0.0, -1.0, 3.0]\nlook_at = [0.0, -1.0, 0.0]\nfov_y_degrees = 60.0\nz_near = 0.05\nz_far = 40.0\n",
        "",
    );
    assert_ne!(no_camera, VALID);
    assert_error(&dir, &no_camera, &["missing required field `camera`"]);
    assert_error(&dir, &edit("direction = [0.2, -1.0, 0.1]\n", ""), &["light.direction", "directional"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn wrong_types_are_errors_naming_the_field() {
    let dir = fixture("types");
    assert_error(
        &dir,
        &edit("wavelength = 1.2", "wavelength = \"long\""),
        &["water.wavelength", "invalid type", "x.toml:22:"],
    );
    assert_error(
        &dir,
        &edit("look_at = [0.0, -1.0, 0.0]", "look_at = [0.0, -1.0]"),
        &["camera.look_at", "invalid length 2"],
    );
    assert_error(&dir, &format!("{VALID}\n[effects]\ncaustics = 1\n"), &["effects.caustics", "invalid type"]);
    assert_error(&dir, &edit("kind = \"directional\"", "kind = \"spot\""), &["light.kind", "unknown variant `spot`"]);
    assert_error(&dir, &format!("{VALID}\n[effects]\ncaustic_grid = -1\n"), &["effects.caustic_grid"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn out_of_range_values_are_errors_naming_the_field_and_the_range() {
    let dir = fixture("range");
    let cases: &[(&str, &str, &str)] = &[
        ("wavelength = 1.2", "wavelength = 0", "x.toml:22: water.wavelength = 0 is out of range: must be > 0"),
        ("wavelength = 1.2", "wavelength = -1", "water.wavelength = -1 is out of range: must be > 0"),
        (
            "fov_y_degrees = 60.0",
            "fov_y_degrees = 180",
            "camera.fov_y_degrees = 180 is out of range: must be in (0, 180)",
        ),
        ("z_far = 40.0", "z_far = 0.01", "camera.z_far = 0.01 is out of range: must be > camera.z_near (0.05)"),
        ("z_near = 0.05", "z_near = 0", "camera.z_near = 0 is out of range: must be > 0"),
        ("intensity = 9.2", "intensity = 0", "light.intensity = 0 is out of range: must be > 0"),
        ("amplitude = 0.04", "amplitude = -0.1", "water.amplitude = -0.1 is out of range: must be >= 0"),
        (
            "extent_max = [2.0, 2.0]",
            "extent_max = [2.0, -3.0]",
            "water.extent_max[1] = -3 is out of range: must be > water.extent_min[1] (-2)",
        ),
        (
            "direction = [0.2, -1.0, 0.1]",
            "direction = [0.2, 1.0, 0.1]",
            "light.direction = [0.2, 1, 0.1] is out of range: must point downwards (y < 0)",
        ),
        ("direction = [0.2, -1.0, 0.1]", "direction = [0.0, 0.0, 0.0]", "must point downwards"),
        ("look_at = [0.0, -1.0, 0.0]", "look_at = [0.0, -1.0, 3.0]", "camera.look_at equals camera.position"),
        (
            "extent_max = [2.0, 2.0]\n",
            "extent_max = [2.0, 2.0]\nior = 1.0\n",
            "water.ior = 1 is out of range: must be in (1, 3]",
        ),
        ("intensity = 9.2\n", "intensity = 9.2\ndistance = -5\n", "light.distance = -5 is out of range: must be > 0"),
        ("obj = \"box.obj\"\n", "obj = \"box.obj\"\nscale = 0\n", "objects[0].scale = 0 is out of range: must be > 0"),
    ];
    for (from, to, expected) in cases {
        assert_error(&dir, &edit(from, to), &[expected]);
    }
    let appended: &[(&str, &str)] = &[
        ("[medium]\nhg_g = 1.0\n", "medium.hg_g = 1 is out of range: must be in (-1, 1)"),
        ("[medium]\ngamma = -1\n", "medium.gamma = -1 is out of range: must be >= 0"),
        ("[medium]\ngamma = [0.1, -0.2, 0.3]\n", "medium.gamma[1] = -0.2 is out of range: must be >= 0"),
        ("[medium]\nscattering = -0.01\n", "medium.scattering = -0.01 is out of range: must be >= 0"),
        ("[effects]\ncaustic_grid = 0\n", "effects.caustic_grid = 0 is out of range: must be in [1, 4096]"),
        ("[effects]\ngodray_subdivision = 9\n", "effects.godray_subdivision = 9 is out of range: must be in [1, 6]"),
        ("[effects]\niterations = 65\n", "effects.iterations = 65 is out of range: must be in [1, 64]"),
        ("[effects]\nshadow_map_size = 8\n", "effects.shadow_map_size = 8 is out of range: must be in [16, 8192]"),
        (
            "[effects]\ncaustic_target_scale = 0\n",
            "effects.caustic_target_scale = 0 is out of range: must be in (0, 4]",
        ),
        (
            "[effects]\npoint_size_max = 4\n",
            "effects.point_size_max = 4 is out of range: must be >= effects.point_size_min (5)",
        ),
        ("[effects]\nline_width = 0\n", "effects.line_width = 0 is out of range: must be > 0"),
        (
            "[effects]\ncaustic_estimator = \"triangles\"\ncaustic_subdivision = 4\n",
            "effects.caustic_subdivision = 4 is out of range for effects.caustic_estimator = \"triangles\": must be <= 3",
        ),
        ("[effects]\ncaustic_estimator = \"splats\"\n", "effects.caustic_estimator"),
        (
            "[effects]\ncaustic_estimator = \"footprint\"\ncaustic_subdivision = 1\n",
            "effects.caustic_subdivision = 1 is out of range for effects.caustic_estimator = \"footprint\": must be >= 2",
        ),
        (
            "[effects]\ncaustic_estimator = \"footprint\"\ncaustic_refinement = true\n",
            "effects.caustic_refinement = true refines the triangle estimator's mesh: it needs effects.caustic_estimator = \"triangles\" (here \"footprint\")",
        ),
        (
            "[effects]\ncaustic_estimator = \"paper\"\ncaustic_refinement = true\n",
            "effects.caustic_refinement = true refines the triangle estimator's mesh: it needs effects.caustic_estimator = \"triangles\" (here \"paper\")",
        ),
        (
            "[effects]\ncaustic_estimator = \"triangles\"\ncaustic_receiver_test = true\n",
            "effects.caustic_receiver_test = true holds the footprint points' hats to their receivers: it needs effects.caustic_estimator = \"footprint\" (here \"triangles\")",
        ),
        (
            "[effects]\ngodray_method = \"footprint\"\ngodray_subdivision = 5\n",
            "effects.godray_subdivision = 5 is out of range for effects.godray_method = \"footprint\": must be <= 4",
        ),
        ("[output]\nwidth = 0\nheight = 10\n", "output.width = 0 is out of range: must be in [1, 16384]"),
    ];
    for (section, expected) in appended {
        assert_error(&dir, &format!("{VALID}\n{section}"), &[expected]);
    }
    // An inline table (at the top: after `[water]` it would belong to the water table).
    assert_error(&dir, &format!("medium = {{ hg_g = 2.0 }}\n{VALID}"), &["x.toml:1: medium.hg_g = 2 is out of range"]);
    // A second object is `objects[1]`.
    let two = edit("obj = \"box.obj\"\n", "obj = \"box.obj\"\n\n[[objects]]\nobj = \"box.obj\"\nscale = -2\n");
    assert_error(&dir, &two, &["objects[1].scale = -2 is out of range: must be > 0"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn nan_and_infinity_are_rejected() {
    let dir = fixture("nan");
    assert_error(
        &dir,
        &edit("wavelength = 1.2", "wavelength = nan"),
        &["water.wavelength = NaN is out of range: must be > 0"],
    );
    assert_error(
        &dir,
        &edit("level = 0.0", "level = inf"),
        &["water.level = inf is out of range: must be a finite number"],
    );
    assert_error(&dir, &edit("speed = 0.5", "speed = -inf"), &["water.speed = -inf is out of range"]);
    assert_error(
        &dir,
        &edit("position = [0.0, -1.0, 3.0]", "position = [0.0, nan, 3.0]"),
        &["camera.position[1] = NaN"],
    );
    assert_error(&dir, &format!("{VALID}\n[medium]\nhg_g = nan\n"), &["medium.hg_g = NaN"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn syntax_errors_name_the_line() {
    let dir = fixture("syntax");
    assert_error(&dir, &edit("[water]", "[water"), &["x.toml:18:"]);
    assert_error(&dir, &edit("speed = 0.5", "speed = "), &["x.toml:23:"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn light_fields_must_fit_the_kind() {
    let dir = fixture("light");
    assert_error(
        &dir,
        &edit("intensity = 9.2\n", "intensity = 9.2\nposition = [0.0, 5.0, 0.0]\n"),
        &["light.position does not apply to a directional light"],
    );
    let point = edit(
        "kind = \"directional\"\ndirection = [0.2, -1.0, 0.1]\n",
        "kind = \"point\"\nposition = [0.0, 5.0, 0.0]\n",
    );
    let s = scene::load_str(&point, &dir.join("x.toml")).unwrap();
    assert_eq!((s.light.kind, s.light.position), (LightKind::Point, Vec3::new(0.0, 5.0, 0.0)));
    assert_error(
        &dir,
        &point.replace("intensity = 9.2\n", "intensity = 9.2\ndirection = [0.0, -1.0, 0.0]\n"),
        &["light.direction does not apply to a point light"],
    );
    assert_error(
        &dir,
        &point.replace("intensity = 9.2\n", "intensity = 9.2\ndistance = 10\n"),
        &["light.distance does not apply to a point light"],
    );
    assert_error(&dir, &point.replace("position = [0.0, 5.0, 0.0]\n", ""), &["light.position", "point"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn godray_method_is_read_and_marched_needs_a_directional_light() {
    let dir = fixture("godray-method");
    let marched = format!("{VALID}\n[effects]\ngodray_method = \"marched\"\n");
    let s = scene::load_str(&marched, &dir.join("x.toml")).unwrap();
    assert_eq!(s.effects.godray_method, GodrayMethod::Marched);
    let beams = format!("{VALID}\n[effects]\ngodray_method = \"beams\"\n");
    assert_eq!(scene::load_str(&beams, &dir.join("x.toml")).unwrap().effects.godray_method, GodrayMethod::Beams);
    let footprint = format!("{VALID}\n[effects]\ngodray_method = \"footprint\"\n");
    let s = scene::load_str(&footprint, &dir.join("x.toml")).unwrap();
    assert_eq!(s.effects.godray_method, GodrayMethod::Footprint);
    // A wrong name: the file, the line and column of the value, the field and the valid names.
    assert_error(
        &dir,
        &format!("{VALID}\n[effects]\ngodray_method = \"rays\"\n"),
        &["x.toml:30:17: effects.godray_method: unknown variant `rays`, expected one of `beams`, `footprint`, `marched`"],
    );
    assert_error(&dir, &format!("{VALID}\n[effects]\ngodray_method = 2\n"), &["effects.godray_method", "invalid type"]);
    // The march lights its steps along the sun's one direction: a point light is refused.
    let point = edit(
        "kind = \"directional\"\ndirection = [0.2, -1.0, 0.1]\n",
        "kind = \"point\"\nposition = [0.0, 5.0, 0.0]\n",
    );
    assert_error(
        &dir,
        &format!("{point}\n[effects]\ngodray_method = \"marched\"\n"),
        &["x.toml:30: effects.godray_method = \"marched\" needs a directional light, and light.kind is \"point\""],
    );
    let s = scene::load_str(&format!("{point}\n[effects]\ngodray_method = \"beams\"\n"), &dir.join("x.toml")).unwrap();
    assert_eq!((s.light.kind, s.effects.godray_method), (LightKind::Point, GodrayMethod::Beams));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn gamma_is_a_number_or_three_numbers() {
    let dir = fixture("gamma");
    let ok = format!("{VALID}\n[medium]\ngamma = [0.1, 0.2, 0.3]\n");
    assert_eq!(scene::load_str(&ok, &dir.join("x.toml")).unwrap().medium.gamma, Vec3::new(0.1, 0.2, 0.3));
    assert_error(
        &dir,
        &format!("{VALID}\n[medium]\ngamma = [0.1, 0.2]\n"),
        &["medium.gamma", "invalid length 2", "array of 3 numbers"],
    );
    assert_error(
        &dir,
        &format!("{VALID}\n[medium]\ngamma = [0.1, 0.2, 0.3, 0.4]\n"),
        &["medium.gamma", "invalid length 4"],
    );
    assert_error(&dir, &format!("{VALID}\n[medium]\ngamma = \"blue\"\n"), &["medium.gamma", "invalid type"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn objects_must_exist_and_hold_triangles() {
    let dir = fixture("objects");
    let missing = error_of(&dir, &edit("obj = \"box.obj\"", "obj = \"nothere.obj\""));
    let resolved = dir.join("nothere.obj");
    for part in ["x.toml", "objects[0].obj", "nothere.obj", &resolved.display().to_string()] {
        assert!(missing.contains(part), "{part:?} not in: {missing}");
    }
    assert_error(&dir, &edit("[[objects]]\nobj = \"box.obj\"\n", "objects = []\n"), &["objects is empty"]);
    // An OBJ with vertices but no faces.
    std::fs::write(dir.join("empty.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    assert_error(
        &dir,
        &edit("obj = \"box.obj\"", "obj = \"empty.obj\""),
        &["objects[0].obj", "empty.obj", "no triangles"],
    );
    // A broken OBJ is reported with the scene file, the object and the OBJ's line.
    std::fs::write(dir.join("broken.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    assert_error(
        &dir,
        &edit("obj = \"box.obj\"", "obj = \"broken.obj\""),
        &["objects[0].obj", "broken.obj:4:", "vertex index 7"],
    );
    // Built-in names that are not built in are paths; a missing one says so.
    let unknown = format!("{:#}", scene::load("no-such-scene").unwrap_err());
    assert!(unknown.contains("no-such-scene") && unknown.contains("tank, port, storage"), "{unknown}");
    std::fs::remove_dir_all(&dir).ok();
}

// ---------------------------------------------------------------------------------------------
// OBJ loading.

fn write_obj(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn malformed_obj_files_are_errors_naming_the_file_and_line() {
    let dir = scratch("obj-malformed");
    let cases: &[(&str, &str)] = &[
        ("v 0 0 0\nv 1 0 x\nv 0 1 0\nf 1 2 3\n", "bad-position.obj:2: `v` coordinate `x` is not a number"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "bad-position.obj:4: f `9`: vertex index 9 is out of range"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 1 0\nf 1//1 2//2 3//1\n", "normal index 2 is out of range"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "vertex index 0 is out of range"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "vertex index -4 is out of range"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/x\n", "bad-position.obj:4:"),
        ("v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n", "bad-position.obj:2: non-finite"),
    ];
    for (text, expected) in cases {
        let path = write_obj(&dir, "bad-position.obj", text);
        let message = format!("{:#}", obj::load_obj(&path).unwrap_err());
        assert!(message.contains(expected), "{expected:?} not in: {message}");
    }
    let missing = format!("{:#}", obj::load_obj(&dir.join("absent.obj")).unwrap_err());
    assert!(missing.contains("absent.obj"), "{missing}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn obj_without_normals_gets_unit_normals_from_its_faces() {
    let dir = scratch("obj-normals");
    // A square in the xz plane, counter-clockwise seen from above: normals are +y.
    let path = write_obj(&dir, "square.obj", "v 0 0 0\nv 0 0 1\nv 1 0 1\nv 1 0 0\nf 1 2 3 4\n");
    let meshes = obj::load_obj(&path).unwrap().meshes;
    assert_eq!(meshes.len(), 1);
    assert!(meshes[0].normals.iter().all(|n| (*n - Vec3::Y).length() < 1e-6), "{:?}", meshes[0].normals);
    // A tent of two triangles sharing the ridge A-B, sloping up-left (normal ∝ (-1, 1, 0))
    // and up-right (∝ (1, 1, 0)). Equal areas: the ridge normals point straight up.
    let ridge = "v 1 1 0\nv 1 1 1\nv 0 0 0.5\n";
    let tent = write_obj(&dir, "tent.obj", &format!("{ridge}v 2 0 0.5\nf 3 2 1\nf 4 1 2\n"));
    let m = &obj::load_obj(&tent).unwrap().meshes[0];
    for (p, n) in m.positions.iter().zip(&m.normals) {
        assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-5, "{n}");
        if p.y == 1.0 {
            assert!((*n - Vec3::Y).length() < 1e-5, "ridge normal {n}");
        }
    }
    // The right face twice as large: it weighs twice, (-1, 1, 0) + 2 (1, 1, 0) ∝ (1, 3, 0).
    let lopsided = write_obj(&dir, "lopsided.obj", &format!("{ridge}v 3 -1 0.5\nf 3 2 1\nf 4 1 2\n"));
    let m = &obj::load_obj(&lopsided).unwrap().meshes[0];
    let expected = Vec3::new(1.0, 3.0, 0.0).normalize();
    for (p, n) in m.positions.iter().zip(&m.normals) {
        if p.y == 1.0 {
            assert!((*n - expected).length() < 1e-5, "ridge normal {n}, expected {expected}");
        }
    }
    // Given normals are kept, made unit.
    let given = write_obj(&dir, "given.obj", "v 0 0 0\nv 0 0 1\nv 1 0 1\nvn 0 2 0\nf 1//1 2//1 3//1\n");
    assert_eq!(obj::load_obj(&given).unwrap().meshes[0].normals, vec![Vec3::Y; 3]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn obj_quads_are_triangulated_and_degenerate_triangles_dropped() {
    let dir = scratch("obj-triangles");
    let quad = write_obj(&dir, "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    let m = &obj::load_obj(&quad).unwrap().meshes[0];
    assert_eq!((m.positions.len(), m.indices.len()), (4, 6));
    // One real triangle, one with collinear corners, one with a repeated corner.
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 1 3\n";
    let m = &obj::load_obj(&write_obj(&dir, "degenerate.obj", text)).unwrap().meshes[0];
    assert_eq!(m.indices.len(), 3, "{:?}", m.indices);
    assert_eq!(m.positions.len(), 3, "the vertex only the dropped triangles used is gone");
    // Only degenerate triangles: no mesh at all.
    let flat = write_obj(&dir, "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    assert!(obj::load_obj(&flat).unwrap().meshes.is_empty());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn mtl_diffuse_colour_becomes_the_albedo() {
    let dir = scratch("obj-mtl");
    std::fs::write(dir.join("colours.mtl"), "newmtl red\nKd 0.9 0.1 0.2\n\nnewmtl plain\nKs 1 1 1\n").unwrap();
    // (`usemtl` is a state that carries over into later objects, so the grey one comes first.)
    let text = "mtllib colours.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n\
                o grey_one\nf 1 3 2\n\
                o red_one\nusemtl red\nf 1 2 3\n\
                o plain_one\nusemtl plain\nf 1 2 3\n";
    let meshes = obj::load_obj(&write_obj(&dir, "coloured.obj", text)).unwrap().meshes;
    let names: Vec<&str> = meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["grey_one", "red_one", "plain_one"]);
    assert_eq!(meshes[0].albedo, obj::DEFAULT_ALBEDO, "no material is grey");
    assert_eq!(meshes[1].albedo, Vec3::new(0.9, 0.1, 0.2));
    assert_eq!(meshes[2].albedo, obj::DEFAULT_ALBEDO, "a material without Kd is grey");
    // A missing MTL file is a warning naming it, and the default material; a broken one is
    // an error naming it.
    let missing =
        write_obj(&dir, "missing-mtl.obj", "mtllib nothere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    let model = obj::load_obj(&missing).unwrap();
    assert_eq!(model.meshes[0].albedo, obj::DEFAULT_ALBEDO);
    assert!(
        model.warnings.iter().any(|w| w.contains("nothere.mtl") && w.contains("does not exist")),
        "{:?}",
        model.warnings
    );
    std::fs::write(dir.join("bright.mtl"), "newmtl bright\nKd 1.5 0.5 0.5\n").unwrap();
    let bright =
        write_obj(&dir, "bright.obj", "mtllib bright.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl bright\nf 1 2 3\n");
    let message = format!("{:#}", obj::load_obj(&bright).unwrap_err());
    assert!(message.contains("bright") && message.contains("must be in [0, 1]"), "{message}");
    std::fs::write(dir.join("broken.mtl"), "newmtl broken\nKd 0.5 x 0.5\n").unwrap();
    let broken = write_obj(&dir, "broken-mtl.obj", "mtllib broken.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let message = format!("{:#}", obj::load_obj(&broken).unwrap_err());
    assert!(message.contains("broken.mtl:2:") && message.contains("`x`"), "{message}");
    std::fs::remove_dir_all(&dir).ok();
}

/// OBJ files as exporters write them (issue 14's cases): each loads, with a warning naming
/// what was repaired or ignored, or fails with the file, the line and the offending token.
#[test]
fn obj_files_as_exporters_write_them() {
    let dir = scratch("obj-wild");
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    // A Latin-1 byte (é = 0xE9) in a material name, in the OBJ and in its MTL.
    std::fs::write(dir.join("latin.mtl"), b"newmtl caf\xE9\nKd 0.2 0.4 0.6\n").unwrap();
    let mut bytes = b"mtllib latin.mtl\n".to_vec();
    bytes.extend_from_slice(tri.as_bytes());
    bytes.extend_from_slice(b"usemtl caf\xE9\nf 1 2 3\n");
    std::fs::write(dir.join("latin.obj"), &bytes).unwrap();
    let model = obj::load_obj(&dir.join("latin.obj")).unwrap();
    assert_eq!(model.meshes[0].albedo, Vec3::new(0.2, 0.4, 0.6), "the Latin-1 name still finds its material");
    assert!(model.warnings.iter().any(|w| w.contains("latin.obj:5") && w.contains("Latin-1")), "{:?}", model.warnings);
    assert!(model.warnings.iter().any(|w| w.contains("latin.mtl:1") && w.contains("Latin-1")), "{:?}", model.warnings);

    // UTF-16, little-endian with a byte-order mark, and big-endian without one.
    let text = format!("{tri}f 1 2 3\n");
    let mut le = vec![0xFF, 0xFE];
    le.extend(text.encode_utf16().flat_map(|u| u.to_le_bytes()));
    std::fs::write(dir.join("utf16le.obj"), &le).unwrap();
    let be: Vec<u8> = text.encode_utf16().flat_map(|u| u.to_be_bytes()).collect();
    std::fs::write(dir.join("utf16be.obj"), &be).unwrap();
    for name in ["utf16le.obj", "utf16be.obj"] {
        let model = obj::load_obj(&dir.join(name)).unwrap();
        assert_eq!(model.meshes[0].indices.len(), 3, "{name}");
        assert!(model.warnings.iter().any(|w| w.contains("UTF-16")), "{name}: {:?}", model.warnings);
    }

    // One zero-length normal among many: that corner takes the face's normal.
    let mut text = String::from(tri);
    for _ in 0..300 {
        text.push_str("vn 0 0 1\n");
    }
    text.push_str("vn 0 0 0\nf 1//1 2//301 3//2\n");
    let model = obj::load_obj(&write_obj(&dir, "zero-normal.obj", &text)).unwrap();
    let m = &model.meshes[0];
    assert!(m.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6), "{:?}", m.normals);
    assert!(
        model.warnings.iter().any(|w| w.contains("1 face corner(s) had a zero-length normal")),
        "{:?}",
        model.warnings
    );

    // `newmtl` with an empty name, used by an empty `usemtl`.
    std::fs::write(dir.join("empty-name.mtl"), "newmtl\nKd 0.1 0.2 0.3\n").unwrap();
    let text = format!("mtllib empty-name.mtl\n{tri}usemtl\nf 1 2 3\n");
    let model = obj::load_obj(&write_obj(&dir, "empty-name.obj", &text)).unwrap();
    assert_eq!(model.meshes[0].albedo, Vec3::new(0.1, 0.2, 0.3));

    // A square ring bridged to its square hole, as one polygon: ear clipping leaves the hole
    // open (a fan from the first corner covers it).
    let ring = "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nv 1 1 0\nv 1 3 0\nv 3 3 0\nv 3 1 0\nf 1 2 3 4 1 5 6 7 8 5\n";
    let m = &obj::load_obj(&write_obj(&dir, "ring.obj", ring)).unwrap().meshes[0];
    let centre = Vec3::new(2.5, 1.5, 0.0); // inside the hole, off the square's diagonals
    let area: f32 = triangles(m).map(|[a, b, c]| (b - a).cross(c - a).length() / 2.0).sum();
    assert!((area - 12.0).abs() < 1e-4, "area {area}: the ring is 16 − 4 m²");
    let dist = Vec3::new(0.0, 0.0, 1.0);
    assert_eq!(crossings(m, centre - dist, dist), 0, "a triangle covers the hole");

    // Polylines and points are ignored with a warning; a file of nothing else has no triangles.
    let text = format!("{tri}l 1 2 3\np 1\nf 1 2 3\n");
    let model = obj::load_obj(&write_obj(&dir, "lines.obj", &text)).unwrap();
    assert_eq!(model.meshes[0].indices.len(), 3, "the polyline is not a face");
    assert!(
        model.warnings.iter().any(|w| w.contains("ignored 2 polyline/point record(s)") && w.contains("lines 4, 5")),
        "{:?}",
        model.warnings
    );
    write_obj(&dir, "only-lines.obj", &format!("{tri}l 1 2 3\n"));
    let scene_text = VALID.replacen("box.obj", "only-lines.obj", 1);
    assert!(scene_text != VALID, "the valid scene names box.obj");
    assert_error(&dir, &scene_text, &["only-lines.obj has no triangles"]);

    // A parse error quotes the token, with the file and line.
    let message = format!("{:#}", obj::load_obj(&write_obj(&dir, "token.obj", "v 0 0 0\nv 1 0,5 0\n")).unwrap_err());
    assert!(message.contains("token.obj:2:") && message.contains("`0,5`"), "{message}");
    std::fs::remove_dir_all(&dir).ok();
}
