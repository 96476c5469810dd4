//! The scene-file format (TOML) and loading.
//!
//! A scene file names its OBJ meshes (relative to the file), the camera, the light, the water
//! surface, the medium and the effect settings; see `assets/scenes/*.toml` for complete
//! examples. Parsing is strict: unknown fields, fields that do not apply (a `position` on a
//! directional light), wrong types and values outside their documented range (NaN and ±inf
//! included, which TOML allows) are errors that name the file, the line, the field as a
//! dotted path (`water.wavelength`, `objects[1].scale`) and the allowed range.

use super::{Camera, CausticEstimator, Effects, Light, LightKind, Medium, Mesh, Scene, Water, WaterModel};
use anyhow::{anyhow, bail, Context as _, Result};
use glam::{Mat3, Vec2, Vec3};
use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The scenes shipped in `assets/scenes/`, loadable by name.
pub const BUILTIN_SCENES: &[&str] = &["tank", "port", "storage"];

/// Output resolution when a scene file has no `[output]` section.
const DEFAULT_OUTPUT: [u32; 2] = [800, 800];
/// Directional light: default distance of the tracking light from what it looks at, m.
const DEFAULT_LIGHT_DISTANCE: f32 = 100.0;
/// Refractive index of water when the file gives none (the paper's value).
const DEFAULT_IOR: f32 = 1.333;

/// The assets folder: `$UNDERLIGHT_ASSETS` if set, else this crate's `assets/`.
pub fn assets_dir() -> PathBuf {
    resolve_assets_dir(std::env::var_os("UNDERLIGHT_ASSETS"))
}

fn resolve_assets_dir(overridden: Option<std::ffi::OsString>) -> PathBuf {
    match overridden {
        Some(dir) if !dir.is_empty() => PathBuf::from(dir),
        _ => PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/assets")),
    }
}

/// Where `name_or_path` lives: a built-in name resolves to `<assets>/scenes/<name>.toml`,
/// anything else is taken as a path.
pub fn scene_path(name_or_path: &str) -> PathBuf {
    if BUILTIN_SCENES.contains(&name_or_path) {
        assets_dir().join("scenes").join(format!("{name_or_path}.toml"))
    } else {
        PathBuf::from(name_or_path)
    }
}

/// Loads a scene: `name_or_path` is a built-in name (resolved to
/// `<assets>/scenes/<name>.toml`) or a path to a `.toml` file.
/// `<assets>` is `$UNDERLIGHT_ASSETS` if set, else this crate's `assets/`.
pub fn load(name_or_path: &str) -> Result<Scene> {
    let path = scene_path(name_or_path);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound && !BUILTIN_SCENES.contains(&name_or_path) {
            anyhow!("no scene {name_or_path:?}: not a built-in scene ({}) and no such file", BUILTIN_SCENES.join(", "))
        } else {
            anyhow!("cannot read scene file {}: {e}", path.display())
        }
    })?;
    load_str(&text, &path)
}

/// Parses scene TOML text; `origin` is the file path used in error messages and as the base
/// directory for relative OBJ paths.
pub fn load_str(text: &str, origin: &Path) -> Result<Scene> {
    let ctx = Context::new(text, origin);
    let file: SceneFile = toml::from_str(text).map_err(|e| ctx.toml_error(&e))?;
    file.validate(&ctx)
}

// ---------------------------------------------------------------------------------------------
// The file's shape. Every struct denies unknown fields so that a typo is an error rather than
// a silently ignored setting; optional fields are `Option` so that "absent" can be told apart
// from "present but not applicable" (light fields) and defaults live in one place.

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    name: String,
    output: Option<OutputFile>,
    objects: Vec<ObjectFile>,
    camera: CameraFile,
    light: LightFile,
    water: WaterFile,
    medium: Option<MediumFile>,
    effects: Option<EffectsFile>,
}

/// The top-level keys, so that a missing-field error is attributed to the root table
/// rather than to whichever table happens to share its span (see `Context::toml_error`).
const TOP_LEVEL_FIELDS: &[&str] = &["name", "output", "objects", "camera", "light", "water", "medium", "effects"];

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct OutputFile {
    width: u32,
    height: u32,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectFile {
    obj: String,
    translate: Option<[f32; 3]>,
    rotate_y_degrees: Option<f32>,
    scale: Option<f32>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraFile {
    position: [f32; 3],
    look_at: [f32; 3],
    fov_y_degrees: f32,
    z_near: f32,
    z_far: f32,
}

#[derive(serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
enum LightKindFile {
    Directional,
    Point,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct LightFile {
    kind: LightKindFile,
    direction: Option<[f32; 3]>,
    position: Option<[f32; 3]>,
    intensity: f32,
    distance: Option<f32>,
}

#[derive(serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
enum WaterModelFile {
    CircularCosine,
    AxisCosineNoise,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct WaterFile {
    model: WaterModelFile,
    level: f32,
    amplitude: f32,
    wavelength: f32,
    speed: f32,
    noise_amplitude: f32,
    noise_scale: f32,
    center: Option<[f32; 2]>,
    extent_min: [f32; 2],
    extent_max: [f32; 2],
    ior: Option<f32>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct MediumFile {
    gamma: Option<Gamma>,
    scattering: Option<f32>,
    hg_g: Option<f32>,
}

#[derive(serde::Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum CausticEstimatorFile {
    Paper,
    Triangles,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct EffectsFile {
    caustics: Option<bool>,
    godrays: Option<bool>,
    filter: Option<bool>,
    caustic_grid: Option<u32>,
    caustic_subdivision: Option<u32>,
    caustic_estimator: Option<CausticEstimatorFile>,
    godray_grid: Option<u32>,
    godray_subdivision: Option<u32>,
    caustic_target_scale: Option<f32>,
    godray_target_scale: Option<f32>,
    point_size_min: Option<f32>,
    point_size_max: Option<f32>,
    line_width: Option<f32>,
    iterations: Option<u32>,
    shadow_map_size: Option<u32>,
}

/// `medium.gamma`: one coefficient for all channels, or `[r, g, b]`. Hand-written rather than
/// an untagged enum so that a wrong array length gets a precise message instead of serde's
/// "did not match any variant".
struct Gamma {
    rgb: [f32; 3],
    /// Written as `[r, g, b]` (errors then name the component).
    array: bool,
}

impl<'de> Deserialize<'de> for Gamma {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct GammaVisitor;
        impl<'de> Visitor<'de> for GammaVisitor {
            type Value = Gamma;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or an array of 3 numbers [r, g, b]")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Gamma, E> {
                Ok(Gamma { rgb: [v as f32; 3], array: false })
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Gamma, E> {
                Ok(Gamma { rgb: [v as f32; 3], array: false })
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Gamma, E> {
                Ok(Gamma { rgb: [v as f32; 3], array: false })
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Gamma, A::Error> {
                let mut rgb = Vec::with_capacity(3);
                while let Some(c) = seq.next_element::<f32>()? {
                    rgb.push(c);
                }
                let len = rgb.len();
                let rgb = rgb.try_into().map_err(|_| de::Error::invalid_length(len, &GammaVisitor))?;
                Ok(Gamma { rgb, array: true })
            }
        }
        deserializer.deserialize_any(GammaVisitor)
    }
}

// ---------------------------------------------------------------------------------------------
// Error context: where each field sits in the text, so that every error can name the line and
// the dotted path of the field.

/// The text being loaded, its file name, and the span of every value in it by dotted path.
struct Context<'a> {
    text: &'a str,
    origin: &'a Path,
    /// (dotted path, byte span of the value). Empty when the text could not be indexed.
    spans: Vec<(String, Range<usize>)>,
}

impl<'a> Context<'a> {
    fn new(text: &'a str, origin: &'a Path) -> Self {
        // toml reports spans but not key paths, so index the document once more as an untyped
        // tree of spanned values. This fails for constructs the index cannot span (dotted keys
        // such as `water.level = 0`, dates); errors then name the line and column only.
        let mut spans = Vec::new();
        if let Ok(root) = toml::from_str::<toml::Spanned<SpanTree>>(text) {
            root.get_ref().collect("", &mut spans);
        }
        Self { text, origin, spans }
    }

    /// 1-based line and column (in characters) of a byte offset.
    fn line_col(&self, offset: usize) -> (usize, usize) {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &self.text[..offset];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, column)
    }

    /// `file:line` for a field, or just `file` when the field has no known position (absent,
    /// or the text could not be indexed).
    fn at(&self, path: &str) -> String {
        match self.spans.iter().find(|(p, _)| p == path) {
            Some((_, span)) => format!("{}:{}", self.origin.display(), self.line_col(span.start).0),
            None => self.origin.display().to_string(),
        }
    }

    /// A validation error about the field at `path`.
    fn error(&self, path: &str, message: impl fmt::Display) -> anyhow::Error {
        anyhow!("{}: {path} {message}", self.at(path))
    }

    /// Rewrites a toml/serde error so that it names the field by its dotted path.
    fn toml_error(&self, e: &toml::de::Error) -> anyhow::Error {
        let message = e.message().trim().replace('\n', "; ");
        let Some(span) = e.span() else {
            return anyhow!("{}: {message}", self.origin.display());
        };
        let (line, column) = self.line_col(span.start);
        let at = format!("{}:{line}:{column}", self.origin.display());
        // The innermost indexed value whose span holds the error's span is the field (type
        // errors: the value), or the table the field belongs to (unknown field: the key;
        // missing field: the table).
        let owner = self
            .spans
            .iter()
            .filter(|(_, s)| s.start <= span.start && span.end <= s.end)
            // On a tie (the only table of an array of tables spans the same text as the
            // array) the deeper path is the more precise one.
            .min_by_key(|(p, s)| (s.end - s.start, std::cmp::Reverse(p.len())))
            .map(|(p, _)| p.as_str());
        let join =
            |table: &str, field: &str| if table.is_empty() { field.to_owned() } else { format!("{table}.{field}") };
        if let Some(rest) = message.strip_prefix("unknown field `") {
            if let Some((field, expected)) = rest.split_once('`') {
                let mut table = owner.unwrap_or("");
                // The key of a table header (`[lights]`) lies inside the table it opens; it
                // belongs to that table's parent. (Unless the table really holds a key of its
                // own name, `[water]` then `water = 1`, which the index shows.)
                if let Some(parent) = parent_if_named(table, field) {
                    if !self.spans.iter().any(|(p, _)| *p == join(table, field)) {
                        table = parent;
                    }
                }
                let path = join(table, field);
                let expected = expected.trim_start_matches(',').trim();
                return anyhow!("{at}: unknown field `{path}` ({expected})");
            }
        }
        if let Some(rest) = message.strip_prefix("missing field `") {
            if let Some((field, _)) = rest.split_once('`') {
                // A missing top-level field is reported on the whole document's span, which a
                // table at the start of the file may share.
                let table = if TOP_LEVEL_FIELDS.contains(&field) { "" } else { owner.unwrap_or("") };
                return anyhow!("{}: missing required field `{}`", self.origin.display(), join(table, field));
            }
        }
        match owner {
            Some(path) => anyhow!("{at}: {path}: {message}"),
            None => anyhow!("{at}: {message}"),
        }
    }
}

/// If the last key of `path` (ignoring array indices) is `key`, the path of its parent.
fn parent_if_named<'p>(path: &'p str, key: &str) -> Option<&'p str> {
    let mut base = path;
    while base.ends_with(']') {
        base = &base[..base.rfind('[')?];
    }
    if base == key {
        Some("")
    } else {
        base.strip_suffix(key)?.strip_suffix('.')
    }
}

/// An untyped TOML value with the span of every value in it, for `Context`.
enum SpanTree {
    Table(Vec<(String, toml::Spanned<SpanTree>)>),
    Array(Vec<toml::Spanned<SpanTree>>),
    Scalar,
}

impl SpanTree {
    fn collect(&self, path: &str, out: &mut Vec<(String, Range<usize>)>) {
        match self {
            SpanTree::Table(entries) => {
                for (key, value) in entries {
                    let child = if path.is_empty() { key.clone() } else { format!("{path}.{key}") };
                    out.push((child.clone(), value.span()));
                    value.get_ref().collect(&child, out);
                }
            }
            SpanTree::Array(items) => {
                for (i, value) in items.iter().enumerate() {
                    let child = format!("{path}[{i}]");
                    out.push((child.clone(), value.span()));
                    value.get_ref().collect(&child, out);
                }
            }
            SpanTree::Scalar => {}
        }
    }
}

impl<'de> Deserialize<'de> for SpanTree {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct TreeVisitor;
        impl<'de> Visitor<'de> for TreeVisitor {
            type Value = SpanTree;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("any TOML value")
            }
            fn visit_bool<E>(self, _: bool) -> Result<SpanTree, E> {
                Ok(SpanTree::Scalar)
            }
            fn visit_i64<E>(self, _: i64) -> Result<SpanTree, E> {
                Ok(SpanTree::Scalar)
            }
            fn visit_u64<E>(self, _: u64) -> Result<SpanTree, E> {
                Ok(SpanTree::Scalar)
            }
            fn visit_f64<E>(self, _: f64) -> Result<SpanTree, E> {
                Ok(SpanTree::Scalar)
            }
            fn visit_str<E>(self, _: &str) -> Result<SpanTree, E> {
                Ok(SpanTree::Scalar)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<SpanTree, A::Error> {
                let mut items = Vec::new();
                while let Some(item) = seq.next_element()? {
                    items.push(item);
                }
                Ok(SpanTree::Array(items))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<SpanTree, A::Error> {
                let mut entries = Vec::new();
                while let Some(entry) = map.next_entry()? {
                    entries.push(entry);
                }
                Ok(SpanTree::Table(entries))
            }
        }
        deserializer.deserialize_any(TreeVisitor)
    }
}

// ---------------------------------------------------------------------------------------------
// Validation: turn the file's shape into the scene model, checking every range.

/// An allowed range of a number, printed the way error messages state it.
#[derive(Clone, Copy)]
struct Bounds {
    /// (bound, inclusive)
    lo: Option<(f64, bool)>,
    hi: Option<(f64, bool)>,
}

impl Bounds {
    const FINITE: Bounds = Bounds { lo: None, hi: None };
    const fn gt(lo: f64) -> Self {
        Bounds { lo: Some((lo, false)), hi: None }
    }
    const fn ge(lo: f64) -> Self {
        Bounds { lo: Some((lo, true)), hi: None }
    }
    const fn open(lo: f64, hi: f64) -> Self {
        Bounds { lo: Some((lo, false)), hi: Some((hi, false)) }
    }
    const fn left_open(lo: f64, hi: f64) -> Self {
        Bounds { lo: Some((lo, false)), hi: Some((hi, true)) }
    }

    /// NaN fails every comparison and so every range; infinities are excluded explicitly
    /// because the renderer assumes finite values even where a range is unbounded.
    fn contains(&self, v: f64) -> bool {
        v.is_finite()
            && self.lo.is_none_or(|(lo, inclusive)| if inclusive { v >= lo } else { v > lo })
            && self.hi.is_none_or(|(hi, inclusive)| if inclusive { v <= hi } else { v < hi })
    }
}

impl fmt::Display for Bounds {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match (self.lo, self.hi) {
            (None, None) => write!(f, "must be a finite number"),
            (Some((lo, inc)), None) => write!(f, "must be {} {lo}", if inc { ">=" } else { ">" }),
            (None, Some((hi, inc))) => write!(f, "must be {} {hi}", if inc { "<=" } else { "<" }),
            (Some((lo, li)), Some((hi, hi_inc))) => {
                write!(f, "must be in {}{lo}, {hi}{}", if li { "[" } else { "(" }, if hi_inc { "]" } else { ")" })
            }
        }
    }
}

impl Context<'_> {
    fn float(&self, path: &str, v: f32, bounds: Bounds) -> Result<f32> {
        if bounds.contains(f64::from(v)) {
            Ok(v)
        } else {
            Err(self.error(path, format_args!("= {v} is out of range: {bounds}")))
        }
    }

    fn int(&self, path: &str, v: u32, lo: u32, hi: u32) -> Result<u32> {
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(self.error(path, format_args!("= {v} is out of range: must be in [{lo}, {hi}]")))
        }
    }

    fn vec3(&self, path: &str, v: [f32; 3]) -> Result<Vec3> {
        for (i, c) in v.iter().enumerate() {
            self.float(&format!("{path}[{i}]"), *c, Bounds::FINITE)?;
        }
        Ok(Vec3::from_array(v))
    }

    fn vec2(&self, path: &str, v: [f32; 2]) -> Result<Vec2> {
        for (i, c) in v.iter().enumerate() {
            self.float(&format!("{path}[{i}]"), *c, Bounds::FINITE)?;
        }
        Ok(Vec2::from_array(v))
    }
}

/// Formats a vector the way it is written in the file, for error messages.
fn list(v: &[f32]) -> String {
    let parts: Vec<String> = v.iter().map(|c| c.to_string()).collect();
    format!("[{}]", parts.join(", "))
}

impl SceneFile {
    fn validate(self, ctx: &Context) -> Result<Scene> {
        if self.name.trim().is_empty() {
            return Err(ctx.error("name", "is empty: give the scene a name"));
        }
        let output = match &self.output {
            Some(o) => [ctx.int("output.width", o.width, 1, 16384)?, ctx.int("output.height", o.height, 1, 16384)?],
            None => DEFAULT_OUTPUT,
        };
        // Cheap checks first, so that a typo in the camera does not wait for mesh loading.
        let camera = self.camera.validate(ctx)?;
        let light = self.light.validate(ctx)?;
        let water = self.water.validate(ctx)?;
        let medium = self.medium.map_or(Ok(Medium::default()), |m| m.validate(ctx))?;
        let effects = self.effects.map_or(Ok(Effects::default()), |e| e.validate(ctx))?;
        if self.objects.is_empty() {
            return Err(ctx.error("objects", "is empty: a scene needs at least one [[objects]] entry"));
        }
        let mut meshes = Vec::new();
        for (i, object) in self.objects.iter().enumerate() {
            meshes.extend(object.load(ctx, i)?);
        }
        if meshes.iter().all(|m| m.indices.is_empty()) {
            bail!("{}: the scene's objects contain no triangles", ctx.origin.display());
        }
        Ok(Scene { name: self.name, output, camera, light, water, medium, effects, meshes })
    }
}

impl ObjectFile {
    /// Loads the OBJ and moves its meshes into world space: scale, then rotate about +y
    /// (counter-clockwise seen from above), then translate.
    fn load(&self, ctx: &Context, index: usize) -> Result<Vec<Mesh>> {
        let field = |name: &str| format!("objects[{index}].{name}");
        let translate = ctx.vec3(&field("translate"), self.translate.unwrap_or([0.0; 3]))?;
        let degrees = ctx.float(&field("rotate_y_degrees"), self.rotate_y_degrees.unwrap_or(0.0), Bounds::FINITE)?;
        let scale = ctx.float(&field("scale"), self.scale.unwrap_or(1.0), Bounds::gt(0.0))?;
        if self.obj.trim().is_empty() {
            return Err(ctx.error(&field("obj"), "is empty: name an OBJ file"));
        }
        let base = ctx.origin.parent().unwrap_or(Path::new(""));
        let path = base.join(&self.obj);
        let model = super::obj::load_obj(&path)
            .with_context(|| format!("{}: objects[{index}].obj = {:?}", ctx.at(&field("obj")), self.obj))?;
        for w in &model.warnings {
            eprintln!("warning: objects[{index}].obj: {w}");
        }
        let mut meshes = model.meshes;
        if meshes.is_empty() {
            return Err(ctx.error(&field("obj"), format_args!("= {:?}: {} has no triangles", self.obj, path.display())));
        }
        let rotation = Mat3::from_rotation_y(degrees.to_radians());
        for mesh in &mut meshes {
            for p in &mut mesh.positions {
                *p = rotation * (*p * scale) + translate;
            }
            // Finite in the file, but a large scale can still overflow.
            if let Some(p) = mesh.positions.iter().find(|p| !p.is_finite()) {
                return Err(ctx.error(
                    &field("scale"),
                    format_args!(
                        "= {scale} takes mesh `{}` out of the finite range (a vertex lands at {p})",
                        mesh.name
                    ),
                ));
            }
            for n in &mut mesh.normals {
                // A rotation keeps unit length; renormalising only removes rounding drift.
                *n = (rotation * *n).normalize();
            }
        }
        Ok(meshes)
    }
}

impl CameraFile {
    fn validate(&self, ctx: &Context) -> Result<Camera> {
        let position = ctx.vec3("camera.position", self.position)?;
        let look_at = ctx.vec3("camera.look_at", self.look_at)?;
        if position == look_at {
            return Err(ctx.error("camera.look_at", "equals camera.position: the camera needs a direction to look in"));
        }
        let fov_y_degrees = ctx.float("camera.fov_y_degrees", self.fov_y_degrees, Bounds::open(0.0, 180.0))?;
        let z_near = ctx.float("camera.z_near", self.z_near, Bounds::gt(0.0))?;
        let z_far = ctx.float("camera.z_far", self.z_far, Bounds::gt(0.0))?;
        if z_far <= z_near {
            return Err(ctx
                .error("camera.z_far", format_args!("= {z_far} is out of range: must be > camera.z_near ({z_near})")));
        }
        Ok(Camera { position, look_at, fov_y_degrees, z_near, z_far })
    }
}

impl LightFile {
    fn validate(&self, ctx: &Context) -> Result<Light> {
        let intensity = ctx.float("light.intensity", self.intensity, Bounds::gt(0.0))?;
        // A field that does not apply to the kind is an error rather than ignored: it means
        // the author expects an effect that will not happen.
        let not_for =
            |field: &str, kind: &str| ctx.error(field, format_args!("does not apply to a {kind} light: remove it"));
        match self.kind {
            LightKindFile::Directional => {
                if self.position.is_some() {
                    return Err(not_for("light.position", "directional"));
                }
                let Some(direction) = self.direction else {
                    bail!("{}: missing required field `light.direction` (directional light)", ctx.origin.display());
                };
                let unit = ctx.vec3("light.direction", direction)?.normalize_or_zero();
                if unit.y >= 0.0 {
                    return Err(ctx.error(
                        "light.direction",
                        format_args!("= {} is out of range: must point downwards (y < 0)", list(&direction)),
                    ));
                }
                let distance =
                    ctx.float("light.distance", self.distance.unwrap_or(DEFAULT_LIGHT_DISTANCE), Bounds::gt(0.0))?;
                Ok(Light { kind: LightKind::Directional, direction: unit, position: Vec3::ZERO, intensity, distance })
            }
            LightKindFile::Point => {
                if self.direction.is_some() {
                    return Err(not_for("light.direction", "point"));
                }
                if self.distance.is_some() {
                    return Err(not_for("light.distance", "point"));
                }
                let Some(position) = self.position else {
                    bail!("{}: missing required field `light.position` (point light)", ctx.origin.display());
                };
                let position = ctx.vec3("light.position", position)?;
                // The unused fields get harmless values rather than zeros a shader could divide by.
                Ok(Light {
                    kind: LightKind::Point,
                    direction: Vec3::NEG_Y,
                    position,
                    intensity,
                    distance: DEFAULT_LIGHT_DISTANCE,
                })
            }
        }
    }
}

impl WaterFile {
    fn validate(&self, ctx: &Context) -> Result<Water> {
        let model = match self.model {
            WaterModelFile::CircularCosine => WaterModel::CircularCosine,
            WaterModelFile::AxisCosineNoise => WaterModel::AxisCosineNoise,
        };
        let extent_min = ctx.vec2("water.extent_min", self.extent_min)?;
        let extent_max = ctx.vec2("water.extent_max", self.extent_max)?;
        for axis in 0..2 {
            if extent_max[axis] <= extent_min[axis] {
                return Err(ctx.error(
                    &format!("water.extent_max[{axis}]"),
                    format_args!(
                        "= {} is out of range: must be > water.extent_min[{axis}] ({})",
                        extent_max[axis], extent_min[axis]
                    ),
                ));
            }
        }
        Ok(Water {
            model,
            level: ctx.float("water.level", self.level, Bounds::FINITE)?,
            amplitude: ctx.float("water.amplitude", self.amplitude, Bounds::ge(0.0))?,
            wavelength: ctx.float("water.wavelength", self.wavelength, Bounds::gt(0.0))?,
            speed: ctx.float("water.speed", self.speed, Bounds::FINITE)?,
            noise_amplitude: ctx.float("water.noise_amplitude", self.noise_amplitude, Bounds::ge(0.0))?,
            noise_scale: ctx.float("water.noise_scale", self.noise_scale, Bounds::gt(0.0))?,
            center: ctx.vec2("water.center", self.center.unwrap_or([0.0; 2]))?,
            extent_min,
            extent_max,
            ior: ctx.float("water.ior", self.ior.unwrap_or(DEFAULT_IOR), Bounds::left_open(1.0, 3.0))?,
        })
    }
}

impl MediumFile {
    fn validate(&self, ctx: &Context) -> Result<Medium> {
        let defaults = Medium::default();
        let gamma = match &self.gamma {
            None => defaults.gamma,
            Some(Gamma { rgb, array }) => {
                for (i, c) in rgb.iter().enumerate() {
                    let path = if *array { format!("medium.gamma[{i}]") } else { "medium.gamma".to_owned() };
                    ctx.float(&path, *c, Bounds::ge(0.0))?;
                }
                Vec3::from_array(*rgb)
            }
        };
        Ok(Medium {
            gamma,
            scattering: ctx.float(
                "medium.scattering",
                self.scattering.unwrap_or(defaults.scattering),
                Bounds::ge(0.0),
            )?,
            hg_g: ctx.float("medium.hg_g", self.hg_g.unwrap_or(defaults.hg_g), Bounds::open(-1.0, 1.0))?,
        })
    }
}

impl EffectsFile {
    fn validate(&self, ctx: &Context) -> Result<Effects> {
        let d = Effects::default();
        let int = |name: &str, v: Option<u32>, default: u32, lo: u32, hi: u32| {
            ctx.int(&format!("effects.{name}"), v.unwrap_or(default), lo, hi)
        };
        let float = |name: &str, v: Option<f32>, default: f32, bounds: Bounds| {
            ctx.float(&format!("effects.{name}"), v.unwrap_or(default), bounds)
        };
        let effects = Effects {
            caustics: self.caustics.unwrap_or(d.caustics),
            godrays: self.godrays.unwrap_or(d.godrays),
            filter: self.filter.unwrap_or(d.filter),
            caustic_grid: int("caustic_grid", self.caustic_grid, d.caustic_grid, 1, 4096)?,
            // The geometry shaders' output limits (see shader_math).
            caustic_subdivision: int(
                "caustic_subdivision",
                self.caustic_subdivision,
                d.caustic_subdivision,
                1,
                crate::shader_math::MAX_SUBDIVISION,
            )?,
            caustic_estimator: match self.caustic_estimator {
                None => d.caustic_estimator,
                Some(CausticEstimatorFile::Paper) => CausticEstimator::Paper,
                Some(CausticEstimatorFile::Triangles) => CausticEstimator::Triangles,
            },
            godray_grid: int("godray_grid", self.godray_grid, d.godray_grid, 1, 4096)?,
            godray_subdivision: int(
                "godray_subdivision",
                self.godray_subdivision,
                d.godray_subdivision,
                1,
                crate::shader_math::GODRAY_MAX_SUBDIVISION,
            )?,
            caustic_target_scale: float(
                "caustic_target_scale",
                self.caustic_target_scale,
                d.caustic_target_scale,
                Bounds::left_open(0.0, 4.0),
            )?,
            godray_target_scale: float(
                "godray_target_scale",
                self.godray_target_scale,
                d.godray_target_scale,
                Bounds::left_open(0.0, 4.0),
            )?,
            point_size_min: float("point_size_min", self.point_size_min, d.point_size_min, Bounds::gt(0.0))?,
            point_size_max: float("point_size_max", self.point_size_max, d.point_size_max, Bounds::gt(0.0))?,
            line_width: float("line_width", self.line_width, d.line_width, Bounds::gt(0.0))?,
            iterations: int("iterations", self.iterations, d.iterations, 1, 64)?,
            shadow_map_size: int("shadow_map_size", self.shadow_map_size, d.shadow_map_size, 16, 8192)?,
        };
        let triangle_max = crate::shader_math::TRIANGLE_MAX_SUBDIVISION;
        if effects.caustic_estimator == CausticEstimator::Triangles && effects.caustic_subdivision > triangle_max {
            return Err(ctx.error(
                "effects.caustic_subdivision",
                format_args!(
                    "= {} is out of range for effects.caustic_estimator = \"triangles\": must be <= {triangle_max} (the geometry shader's output limit)",
                    effects.caustic_subdivision
                ),
            ));
        }
        if effects.point_size_max < effects.point_size_min {
            return Err(ctx.error(
                "effects.point_size_max",
                format_args!(
                    "= {} is out of range: must be >= effects.point_size_min ({})",
                    effects.point_size_max, effects.point_size_min
                ),
            ));
        }
        Ok(effects)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assets_dir_prefers_the_override() {
        assert_eq!(resolve_assets_dir(Some("/elsewhere".into())), PathBuf::from("/elsewhere"));
        let default = resolve_assets_dir(None);
        assert!(default.ends_with("assets"), "{}", default.display());
        assert_eq!(resolve_assets_dir(Some("".into())), default, "an empty override is no override");
    }

    #[test]
    fn builtin_names_resolve_into_the_assets_folder_and_other_names_are_paths() {
        let tank = scene_path("tank");
        assert!(tank.ends_with("scenes/tank.toml"), "{}", tank.display());
        assert_eq!(scene_path("my/scene.toml"), PathBuf::from("my/scene.toml"));
    }

    #[test]
    fn bounds_reject_nan_and_infinity_and_print_as_intervals() {
        assert!(!Bounds::FINITE.contains(f64::NAN));
        assert!(!Bounds::FINITE.contains(f64::INFINITY));
        assert!(!Bounds::gt(0.0).contains(f64::INFINITY));
        assert!(Bounds::gt(0.0).contains(1e-9) && !Bounds::gt(0.0).contains(0.0));
        assert!(Bounds::ge(0.0).contains(0.0));
        assert!(Bounds::left_open(1.0, 3.0).contains(3.0) && !Bounds::left_open(1.0, 3.0).contains(1.0));
        assert!(!Bounds::open(-1.0, 1.0).contains(1.0));
        assert_eq!(Bounds::gt(0.0).to_string(), "must be > 0");
        assert_eq!(Bounds::ge(0.5).to_string(), "must be >= 0.5");
        assert_eq!(Bounds::open(0.0, 180.0).to_string(), "must be in (0, 180)");
        assert_eq!(Bounds::left_open(1.0, 3.0).to_string(), "must be in (1, 3]");
    }

    #[test]
    fn parents_of_named_paths() {
        assert_eq!(parent_if_named("lights", "lights"), Some(""));
        assert_eq!(parent_if_named("objectz[0]", "objectz"), Some(""));
        assert_eq!(parent_if_named("water.extra", "extra"), Some("water"));
        assert_eq!(parent_if_named("water", "extra"), None);
        assert_eq!(parent_if_named("water.xextra", "extra"), None);
    }

    #[test]
    fn the_span_index_names_nested_fields() {
        let text = "name = 'x'\n[water]\nlevel = 0\n[[objects]]\nobj = 'a'\n[[objects]]\nobj = 'b'\nscale = 2\n[medium]\ngamma = [1, 2, 3]\n";
        let ctx = Context::new(text, Path::new("t.toml"));
        let paths: Vec<&str> = ctx.spans.iter().map(|(p, _)| p.as_str()).collect();
        for expected in ["name", "water", "water.level", "objects[1].scale", "medium.gamma[2]"] {
            assert!(paths.contains(&expected), "{expected} not in {paths:?}");
        }
        assert_eq!(ctx.at("objects[1].scale"), "t.toml:8");
        assert_eq!(ctx.at("camera.position"), "t.toml", "absent fields have no line");
    }
}
