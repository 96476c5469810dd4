//! The scene-file format (TOML) and loading.
//!
//! A scene file names its OBJ meshes (relative to the file), the camera, the light, the water
//! surface, the medium and the effect settings; see `assets/scenes/*.toml` for complete
//! examples. Parsing is strict: unknown fields, fields that do not apply (a `position` on a
//! directional light), wrong types and array lengths, and values outside their documented
//! range (NaN and ±inf included, which TOML allows) are errors that name the file, the line,
//! the field as a dotted path (`water.wavelength`, `objects[1].scale`) and the allowed range.

use super::{
    Camera, CausticEstimator, Effects, GodrayMethod, Light, LightKind, Medium, Mesh, PhotonSpread, Scene, Water,
    WaterModel,
};
use anyhow::{anyhow, bail, Context as _, Result};
use glam::{Mat3, Vec2, Vec3};
use serde::de::value::{MapDeserializer, SeqDeserializer};
use serde::de::{self, Deserializer, IntoDeserializer, SeqAccess, Unexpected, Visitor};
use serde::{Deserialize, Serialize};
use serde_path_to_error::Segment;
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml_edit::{ImDocument, Item, Table, Value};

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
    let doc = ImDocument::parse(text).map_err(|e| {
        let message = e.message().trim().replace('\n', "; ");
        anyhow!("{}: {message}", position(text, origin, e.span()))
    })?;
    let ctx = Context { text, origin, doc };
    let file: SceneFile =
        serde_path_to_error::deserialize(Node::Table(ctx.doc.as_table())).map_err(|e| ctx.schema_error(e))?;
    file.validate(&ctx)
}

// ---------------------------------------------------------------------------------------------
// The file's shape: what `load` reads and what the generator (`generate.rs`) builds and
// serializes, so the two cannot drift apart. Every struct denies unknown fields so that a typo
// is an error rather than a silently ignored setting; optional fields are `Option` so that
// "absent" can be told apart from "present but not applicable" (light fields) and defaults
// live in one place. Numbers are f64, as TOML holds them: the generator's values are written
// as they are (an f32 0.05 would be written 0.05000000074505806), and validation narrows them
// to the renderer's f32 before checking their range.

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneFile {
    pub name: String,
    pub output: Option<OutputFile>,
    pub objects: Vec<ObjectFile>,
    pub camera: CameraFile,
    pub light: LightFile,
    pub water: WaterFile,
    pub medium: Option<MediumFile>,
    pub effects: Option<EffectsFile>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct OutputFile {
    pub width: u32,
    pub height: u32,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ObjectFile {
    pub obj: String,
    pub translate: Option<[f64; 3]>,
    pub rotate_y_degrees: Option<f64>,
    pub scale: Option<f64>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraFile {
    pub position: [f64; 3],
    pub look_at: [f64; 3],
    pub fov_y_degrees: f64,
    pub z_near: f64,
    pub z_far: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum LightKindFile {
    Directional,
    Point,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LightFile {
    pub kind: LightKindFile,
    pub direction: Option<[f64; 3]>,
    pub position: Option<[f64; 3]>,
    pub intensity: f64,
    pub distance: Option<f64>,
}

#[derive(Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub(super) enum WaterModelFile {
    CircularCosine,
    AxisCosineNoise,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct WaterFile {
    pub model: WaterModelFile,
    pub level: f64,
    pub amplitude: f64,
    pub wavelength: f64,
    pub speed: f64,
    pub noise_amplitude: f64,
    pub noise_scale: f64,
    pub center: Option<[f64; 2]>,
    pub extent_min: [f64; 2],
    pub extent_max: [f64; 2],
    pub ior: Option<f64>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MediumFile {
    pub gamma: Option<Gamma>,
    pub scattering: Option<f64>,
    pub hg_g: Option<f64>,
}

#[derive(Serialize, Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub(super) enum CausticEstimatorFile {
    Paper,
    Footprint,
    Triangles,
}

#[derive(Serialize, Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub(super) enum PhotonSpreadFile {
    Even,
    View,
}

impl From<PhotonSpreadFile> for PhotonSpread {
    fn from(f: PhotonSpreadFile) -> Self {
        match f {
            PhotonSpreadFile::Even => PhotonSpread::Even,
            PhotonSpreadFile::View => PhotonSpread::View,
        }
    }
}

#[derive(Serialize, Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
pub(super) enum GodrayMethodFile {
    Beams,
    Footprint,
    Marched,
}

#[derive(Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct EffectsFile {
    pub caustics: Option<bool>,
    pub godrays: Option<bool>,
    pub filter: Option<bool>,
    // Ahead of the grid and subdivision, whose limits it sets (and under the built-in scenes'
    // comment about it).
    pub caustic_estimator: Option<CausticEstimatorFile>,
    pub caustic_grid: Option<u32>,
    pub caustic_subdivision: Option<u32>,
    pub caustic_photon_density: Option<PhotonSpreadFile>,
    pub caustic_refinement: Option<bool>,
    pub caustic_receiver_test: Option<bool>,
    pub photon_jitter: Option<bool>,
    // Ahead of the godray grid and subdivision: they are the beams' photons, which the
    // marched godrays do not use.
    pub godray_method: Option<GodrayMethodFile>,
    pub godray_photon_density: Option<PhotonSpreadFile>,
    pub godray_grid: Option<u32>,
    pub godray_subdivision: Option<u32>,
    pub caustic_target_scale: Option<f64>,
    pub godray_target_scale: Option<f64>,
    pub point_size_min: Option<f64>,
    pub point_size_max: Option<f64>,
    pub line_width: Option<f64>,
    pub iterations: Option<u32>,
    pub shadow_map_size: Option<u32>,
}

/// `medium.gamma`: one coefficient for all channels, or `[r, g, b]` (errors then name the
/// component).
#[derive(Serialize)]
#[serde(untagged)]
pub(super) enum Gamma {
    Uniform(f64),
    Rgb([f64; 3]),
}

/// Hand-written rather than derived (untagged) so that a wrong array length gets a precise
/// message instead of serde's "did not match any variant".
impl<'de> Deserialize<'de> for Gamma {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct GammaVisitor;
        impl<'de> Visitor<'de> for GammaVisitor {
            type Value = Gamma;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or an array of 3 numbers [r, g, b]")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Gamma, E> {
                Ok(Gamma::Uniform(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Gamma, E> {
                Ok(Gamma::Uniform(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Gamma, E> {
                Ok(Gamma::Uniform(v as f64))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Gamma, A::Error> {
                let mut rgb = Vec::with_capacity(3);
                while let Some(c) = seq.next_element::<f64>()? {
                    rgb.push(c);
                }
                let len = rgb.len();
                let rgb = rgb.try_into().map_err(|_| de::Error::invalid_length(len, &GammaVisitor))?;
                Ok(Gamma::Rgb(rgb))
            }
        }
        deserializer.deserialize_any(GammaVisitor)
    }
}

// ---------------------------------------------------------------------------------------------
// Reading the file: toml_edit parses it (syntax errors, and the span of every key and value),
// serde's derived code checks its shape against the structs above, and serde_path_to_error
// tracks the dotted path of the field that failed. The document is handed to serde through
// serde's own value deserializers rather than toml's deserializer because toml's error keeps
// only a message: `SchemaError` keeps the unknown or missing field's name and the allowed
// names apart, so messages name the field by its full path without reading serde's wording.

/// The text being loaded, its file name, and its parsed document (for the line of a field).
struct Context<'a> {
    text: &'a str,
    origin: &'a Path,
    doc: ImDocument<&'a str>,
}

/// One step of a field's path: a key, or an index into an array.
#[derive(Clone, Copy)]
enum Step<'p> {
    Key(&'p str),
    Index(usize),
}

/// The steps of a path as validation writes it: `camera.z_far`, `objects[1].scale`,
/// `water.extent_max[0]`.
fn steps(path: &str) -> Vec<Step<'_>> {
    let mut steps = Vec::new();
    for part in path.split('.') {
        let mut pieces = part.split('[');
        steps.extend(pieces.next().map(Step::Key));
        steps.extend(pieces.filter_map(|index| index.strip_suffix(']')?.parse().ok()).map(Step::Index));
    }
    steps
}

/// 1-based line and column (in characters) of a byte offset.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// `file:line:column` of a span, or just `file` without one.
fn position(text: &str, origin: &Path, span: Option<Range<usize>>) -> String {
    match span {
        Some(span) => {
            let (line, column) = line_col(text, span.start);
            format!("{}:{line}:{column}", origin.display())
        }
        None => origin.display().to_string(),
    }
}

impl Context<'_> {
    /// The span of the value at `path`, or of the key that names it when `key` is set. None
    /// when the path is not in the document (an absent field).
    fn span<'p>(&self, path: impl IntoIterator<Item = Step<'p>>, key: bool) -> Option<Range<usize>> {
        let mut item = self.doc.as_item();
        let mut key_span = None;
        for step in path {
            item = match step {
                Step::Key(name) => {
                    key_span = item.as_table_like()?.key(name)?.span();
                    item.get(name)?
                }
                Step::Index(i) => item.get(i)?,
            };
        }
        if key {
            key_span
        } else {
            item.span()
        }
    }

    /// `file:line` for a field, or just `file` when the field is not in the document.
    fn at(&self, path: &str) -> String {
        match self.span(steps(path), false) {
            Some(span) => format!("{}:{}", self.origin.display(), line_col(self.text, span.start).0),
            None => self.origin.display().to_string(),
        }
    }

    /// A validation error about the field at `path`.
    fn error(&self, path: &str, message: impl fmt::Display) -> anyhow::Error {
        anyhow!("{}: {path} {message}", self.at(path))
    }

    /// A schema error (unknown or missing field, wrong type), naming the field by its path.
    fn schema_error(&self, e: serde_path_to_error::Error<SchemaError>) -> anyhow::Error {
        // Paths hold keys and indices only: the schema's enums are plain strings.
        let path: Option<Vec<Step>> = e
            .path()
            .iter()
            .map(|segment| match segment {
                Segment::Map { key } => Some(Step::Key(key)),
                Segment::Seq { index } => Some(Step::Index(*index)),
                Segment::Enum { .. } | Segment::Unknown => None,
            })
            .collect();
        // (serde_path_to_error writes the root as ".")
        let dotted = if e.path().iter().next().is_none() { String::new() } else { e.path().to_string() };
        let at =
            |key: bool| position(self.text, self.origin, path.as_ref().and_then(|p| self.span(p.iter().copied(), key)));
        match e.inner() {
            // The path ends with the unknown key; the error is at the key.
            SchemaError::UnknownField { expected, .. } => {
                anyhow!("{}: unknown field `{dotted}` (expected {})", at(true), one_of(expected))
            }
            // The path is the table's; the field has no position of its own.
            SchemaError::MissingField(field) => {
                let field = if dotted.is_empty() { field.to_string() } else { format!("{dotted}.{field}") };
                anyhow!("{}: missing required field `{field}`", self.origin.display())
            }
            SchemaError::Other(message) if dotted.is_empty() => anyhow!("{}: {message}", at(false)),
            SchemaError::Other(message) => anyhow!("{}: {dotted}: {message}", at(false)),
        }
    }
}

/// "one of `a`, `b`".
fn one_of(names: &[&str]) -> String {
    let names: Vec<String> = names.iter().map(|name| format!("`{name}`")).collect();
    format!("one of {}", names.join(", "))
}

/// A schema error as serde reports it, with the field names kept apart from the message.
#[derive(Debug)]
enum SchemaError {
    UnknownField { field: String, expected: &'static [&'static str] },
    MissingField(&'static str),
    Other(String),
}

impl de::Error for SchemaError {
    fn custom<T: fmt::Display>(message: T) -> Self {
        SchemaError::Other(message.to_string())
    }
    fn unknown_field(field: &str, expected: &'static [&'static str]) -> Self {
        SchemaError::UnknownField { field: field.to_owned(), expected }
    }
    fn missing_field(field: &'static str) -> Self {
        SchemaError::MissingField(field)
    }
}

impl fmt::Display for SchemaError {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            SchemaError::UnknownField { field, .. } => write!(f, "unknown field `{field}`"),
            SchemaError::MissingField(field) => write!(f, "missing field `{field}`"),
            SchemaError::Other(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for SchemaError {}

/// A node of the parsed document, as serde input. Tables become maps and arrays sequences
/// through serde's value deserializers; both check that every entry was consumed, so a fourth
/// component of a `[x, y, z]` is an error rather than dropped.
#[derive(Clone, Copy)]
enum Node<'a> {
    Item(&'a Item),
    Table(&'a Table),
    Value(&'a Value),
}

impl<'de> Deserializer<'de> for Node<'_> {
    type Error = SchemaError;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, SchemaError> {
        match self {
            Node::Item(Item::Table(table)) | Node::Table(table) => {
                visit_map(visitor, table.iter().map(|(k, v)| (k, Node::Item(v))))
            }
            Node::Item(Item::ArrayOfTables(tables)) => visit_seq(visitor, tables.iter().map(Node::Table)),
            // Tables do not list empty items.
            Node::Item(Item::None) => visitor.visit_unit(),
            Node::Item(Item::Value(value)) | Node::Value(value) => match value {
                Value::String(s) => visitor.visit_str(s.value()),
                Value::Integer(i) => visitor.visit_i64(*i.value()),
                Value::Float(f) => visitor.visit_f64(*f.value()),
                Value::Boolean(b) => visitor.visit_bool(*b.value()),
                // No field of a scene file is a date.
                Value::Datetime(_) => Err(de::Error::invalid_type(self.unexpected(), &visitor)),
                Value::Array(array) => visit_seq(visitor, array.iter().map(Node::Value)),
                Value::InlineTable(table) => visit_map(visitor, table.iter().map(|(k, v)| (k, Node::Value(v)))),
            },
        }
    }

    /// Absent fields never reach the deserializer: a value is always `Some`.
    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, SchemaError> {
        visitor.visit_some(self)
    }

    /// Enums are written as their variant's name.
    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, SchemaError> {
        match self {
            Node::Item(Item::Value(Value::String(s))) | Node::Value(Value::String(s)) => {
                visitor.visit_enum(s.value().as_str().into_deserializer())
            }
            _ => Err(de::Error::invalid_type(self.unexpected(), &one_of(variants).as_str())),
        }
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, SchemaError> {
        visitor.visit_newtype_struct(self)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf unit
        unit_struct seq tuple tuple_struct map struct identifier ignored_any
    }
}

impl<'a> Node<'a> {
    /// What the node holds, for an "invalid type" message.
    fn unexpected(self) -> Unexpected<'a> {
        match self {
            Node::Item(Item::Value(value)) | Node::Value(value) => match value {
                Value::String(s) => Unexpected::Str(s.value()),
                Value::Integer(i) => Unexpected::Signed(*i.value()),
                Value::Float(f) => Unexpected::Float(*f.value()),
                Value::Boolean(b) => Unexpected::Bool(*b.value()),
                Value::Datetime(_) => Unexpected::Other("datetime"),
                Value::Array(_) => Unexpected::Seq,
                Value::InlineTable(_) => Unexpected::Map,
            },
            Node::Item(Item::ArrayOfTables(_)) => Unexpected::Seq,
            Node::Item(Item::Table(_) | Item::None) | Node::Table(_) => Unexpected::Map,
        }
    }
}

impl<'de, 'a> IntoDeserializer<'de, SchemaError> for Node<'a> {
    type Deserializer = Node<'a>;
    fn into_deserializer(self) -> Node<'a> {
        self
    }
}

/// Visits `entries` as a map; every entry must be consumed.
fn visit_map<'de, 'a, V: Visitor<'de>>(
    visitor: V,
    entries: impl Iterator<Item = (&'a str, Node<'a>)>,
) -> Result<V::Value, SchemaError> {
    let mut map = MapDeserializer::new(entries);
    let value = visitor.visit_map(&mut map)?;
    map.end()?;
    Ok(value)
}

/// Visits `items` as a sequence; every item must be consumed.
fn visit_seq<'de, 'a, V: Visitor<'de>>(
    visitor: V,
    items: impl Iterator<Item = Node<'a>>,
) -> Result<V::Value, SchemaError> {
    let mut seq = SeqDeserializer::new(items);
    let value = visitor.visit_seq(&mut seq)?;
    seq.end()?;
    Ok(value)
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
    /// The file's number narrowed to the renderer's f32, which is what must be in range (a
    /// finite 1e39 is inf as an f32).
    fn float(&self, path: &str, v: f64, bounds: Bounds) -> Result<f32> {
        let v = v as f32;
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

    fn finite<const N: usize>(&self, path: &str, v: [f64; N]) -> Result<[f32; N]> {
        let mut out = [0.0; N];
        for (i, c) in v.into_iter().enumerate() {
            out[i] = self.float(&format!("{path}[{i}]"), c, Bounds::FINITE)?;
        }
        Ok(out)
    }

    fn vec3(&self, path: &str, v: [f64; 3]) -> Result<Vec3> {
        self.finite(path, v).map(Vec3::from_array)
    }

    fn vec2(&self, path: &str, v: [f64; 2]) -> Result<Vec2> {
        self.finite(path, v).map(Vec2::from_array)
    }
}

/// Formats a vector the way it is written in the file, for error messages.
fn list(v: &[f32]) -> String {
    let parts: Vec<String> = v.iter().map(|c| c.to_string()).collect();
    format!("[{}]", parts.join(", "))
}

/// The largest output side a scene (or a command's `--width`, `--height`) asks for.
pub const MAX_OUTPUT_SIDE: u32 = 16384;

/// The scene's name and output size, as a file's `name` and `[output]` or a scene built in code.
fn check_name_and_output(ctx: &Context, name: &str, output: [u32; 2]) -> Result<[u32; 2]> {
    if name.trim().is_empty() {
        return Err(ctx.error("name", "is empty: give the scene a name"));
    }
    Ok([
        ctx.int("output.width", output[0], 1, MAX_OUTPUT_SIDE)?,
        ctx.int("output.height", output[1], 1, MAX_OUTPUT_SIDE)?,
    ])
}

impl SceneFile {
    fn validate(self, ctx: &Context) -> Result<Scene> {
        let output = check_name_and_output(
            ctx,
            &self.name,
            self.output.as_ref().map_or(DEFAULT_OUTPUT, |o| [o.width, o.height]),
        )?;
        // Cheap checks first, so that a typo in the camera does not wait for mesh loading.
        let camera = self.camera.validate(ctx)?;
        let light = self.light.validate(ctx)?;
        let water = self.water.validate(ctx)?;
        let medium = self.medium.map_or(Ok(Medium::default()), |m| m.validate(ctx))?;
        let effects = self.effects.map_or(Ok(Effects::default()), |e| e.validate(ctx))?;
        marched_needs_a_directional_light(ctx, &effects, &light)?;
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

/// The ray march lights each step through the flat surface along one direction, which a
/// point light does not have.
fn marched_needs_a_directional_light(ctx: &Context, effects: &Effects, light: &Light) -> Result<()> {
    if effects.godray_method == GodrayMethod::Marched && light.kind == LightKind::Point {
        return Err(ctx.error(
            "effects.godray_method",
            "= \"marched\" needs a directional light, and light.kind is \"point\": use godray_method = \"beams\" with a point light",
        ));
    }
    Ok(())
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
                let direction = ctx.vec3("light.direction", direction)?;
                let unit = direction.normalize_or_zero();
                if unit.y >= 0.0 {
                    return Err(ctx.error(
                        "light.direction",
                        format_args!("= {} is out of range: must point downwards (y < 0)", list(&direction.to_array())),
                    ));
                }
                let distance = ctx.float(
                    "light.distance",
                    self.distance.unwrap_or(DEFAULT_LIGHT_DISTANCE.into()),
                    Bounds::gt(0.0),
                )?;
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
            ior: ctx.float("water.ior", self.ior.unwrap_or(DEFAULT_IOR.into()), Bounds::left_open(1.0, 3.0))?,
        })
    }
}

impl MediumFile {
    fn validate(&self, ctx: &Context) -> Result<Medium> {
        let defaults = Medium::default();
        let gamma = match self.gamma {
            None => defaults.gamma,
            Some(Gamma::Uniform(g)) => Vec3::splat(ctx.float("medium.gamma", g, Bounds::ge(0.0))?),
            Some(Gamma::Rgb(rgb)) => {
                let mut out = [0.0; 3];
                for (i, c) in rgb.into_iter().enumerate() {
                    out[i] = ctx.float(&format!("medium.gamma[{i}]"), c, Bounds::ge(0.0))?;
                }
                Vec3::from_array(out)
            }
        };
        Ok(Medium {
            gamma,
            scattering: ctx.float(
                "medium.scattering",
                self.scattering.unwrap_or(defaults.scattering.into()),
                Bounds::ge(0.0),
            )?,
            hg_g: ctx.float("medium.hg_g", self.hg_g.unwrap_or(defaults.hg_g.into()), Bounds::open(-1.0, 1.0))?,
        })
    }
}

impl EffectsFile {
    fn validate(&self, ctx: &Context) -> Result<Effects> {
        let d = Effects::default();
        let int = |name: &str, v: Option<u32>, default: u32, lo: u32, hi: u32| {
            ctx.int(&format!("effects.{name}"), v.unwrap_or(default), lo, hi)
        };
        let float = |name: &str, v: Option<f64>, default: f32, bounds: Bounds| {
            ctx.float(&format!("effects.{name}"), v.unwrap_or(default.into()), bounds)
        };
        let effects = Effects {
            caustics: self.caustics.unwrap_or(d.caustics),
            godrays: self.godrays.unwrap_or(d.godrays),
            filter: self.filter.unwrap_or(d.filter),
            photon_jitter: self.photon_jitter.unwrap_or(d.photon_jitter),
            caustic_refinement: self.caustic_refinement.unwrap_or(d.caustic_refinement),
            caustic_receiver_test: self.caustic_receiver_test.unwrap_or(d.caustic_receiver_test),
            caustic_grid: int("caustic_grid", self.caustic_grid, d.caustic_grid, 1, 4096)?,
            // The geometry shaders' output limits (see shader_math).
            caustic_subdivision: int(
                "caustic_subdivision",
                self.caustic_subdivision,
                d.caustic_subdivision,
                1,
                crate::shader_abi::limits::MAX_SUBDIVISION,
            )?,
            caustic_estimator: match self.caustic_estimator {
                None => d.caustic_estimator,
                Some(CausticEstimatorFile::Paper) => CausticEstimator::Paper,
                Some(CausticEstimatorFile::Footprint) => CausticEstimator::Footprint,
                Some(CausticEstimatorFile::Triangles) => CausticEstimator::Triangles,
            },
            caustic_photon_density: self.caustic_photon_density.map_or(d.caustic_photon_density, PhotonSpread::from),
            godray_photon_density: self.godray_photon_density.map_or(d.godray_photon_density, PhotonSpread::from),
            godray_method: match self.godray_method {
                None => d.godray_method,
                Some(GodrayMethodFile::Beams) => GodrayMethod::Beams,
                Some(GodrayMethodFile::Footprint) => GodrayMethod::Footprint,
                Some(GodrayMethodFile::Marched) => GodrayMethod::Marched,
            },
            godray_grid: int("godray_grid", self.godray_grid, d.godray_grid, 1, 4096)?,
            godray_subdivision: int(
                "godray_subdivision",
                self.godray_subdivision,
                d.godray_subdivision,
                1,
                crate::shader_abi::limits::GODRAY_MAX_SUBDIVISION,
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
        // The estimator's and the godray method's own geometry shaders may emit fewer photons
        // per invocation than the ranges above allow.
        let own_bounds = [
            (
                "caustic",
                "caustic_estimator",
                effects.caustic_subdivision,
                effects.caustic_estimator.name(),
                effects.caustic_estimator.max_subdivision(),
            ),
            (
                "godray",
                "godray_method",
                effects.godray_subdivision,
                effects.godray_method.name(),
                effects.godray_method.max_subdivision(),
            ),
        ];
        for (kind, setting, value, name, max) in own_bounds {
            if value > max {
                return Err(ctx.error(
                    &format!("effects.{kind}_subdivision"),
                    format_args!(
                        "= {value} is out of range for effects.{setting} = \"{name}\": must be <= {max} (the geometry shader's output limit: 1..={max} per axis)"
                    ),
                ));
            }
        }
        let least = effects.caustic_estimator.min_subdivision();
        if effects.caustic_subdivision < least {
            return Err(ctx.error(
                "effects.caustic_subdivision",
                format_args!(
                    "= {} is out of range for effects.caustic_estimator = \"{}\": must be >= {least} (each photon's footprint is measured to its neighbours in its coarse cell)",
                    effects.caustic_subdivision,
                    effects.caustic_estimator.name()
                ),
            ));
        }
        if effects.caustic_refinement && effects.caustic_estimator != CausticEstimator::Triangles {
            return Err(ctx.error(
                "effects.caustic_refinement",
                format_args!(
                    "= true refines the triangle estimator's mesh: it needs effects.caustic_estimator = \"triangles\" (here \"{}\")",
                    effects.caustic_estimator.name()
                ),
            ));
        }
        if effects.caustic_receiver_test && effects.caustic_estimator != CausticEstimator::Footprint {
            return Err(ctx.error(
                "effects.caustic_receiver_test",
                format_args!(
                    "= true holds the footprint points' hats to their receivers: it needs effects.caustic_estimator = \"footprint\" (here \"{}\")",
                    effects.caustic_estimator.name()
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

// ---------------------------------------------------------------------------------------------
// A scene built in code (`Scene { .. }`, the library's users and the tests) is held to the
// ranges a scene file is, by the same checks: its sections are written back into the file's
// shape and validated as a file's would be, so the ranges live in one place. Errors name the
// field as a file would, with the scene's name where a file's line would be.

impl Scene {
    /// Checks every field against the ranges `docs/limits.md` lists (what `load` checks in a
    /// scene file), and the meshes: finite positions and normals, one normal per position,
    /// whole triangles whose indices are in range, at least one triangle. `Frame::new` and the
    /// reference call it, so a NaN amplitude or a subdivision past the geometry shader's limit
    /// set in code is a named error, not a frame of NaN or an empty buffer.
    pub fn validate(&self) -> crate::error::Result<()> {
        self.check_ranges()
            .map_err(|e| crate::error::Error::InvalidParameter { name: "scene", message: format!("{e:#}") })
    }

    fn check_ranges(&self) -> Result<()> {
        let origin = PathBuf::from(format!("{:?} (built in code)", self.name));
        let doc = ImDocument::parse("").expect("an empty document parses");
        let ctx = Context { text: "", origin: &origin, doc };
        check_name_and_output(&ctx, &self.name, self.output)?;
        let v3 = |v: Vec3| v.to_array().map(f64::from);
        let v2 = |v: Vec2| v.to_array().map(f64::from);
        let c = &self.camera;
        CameraFile {
            position: v3(c.position),
            look_at: v3(c.look_at),
            fov_y_degrees: c.fov_y_degrees.into(),
            z_near: c.z_near.into(),
            z_far: c.z_far.into(),
        }
        .validate(&ctx)?;
        let l = &self.light;
        let directional = l.kind == LightKind::Directional;
        LightFile {
            kind: if directional { LightKindFile::Directional } else { LightKindFile::Point },
            direction: directional.then(|| v3(l.direction)),
            position: (!directional).then(|| v3(l.position)),
            intensity: l.intensity.into(),
            distance: directional.then_some(l.distance.into()),
        }
        .validate(&ctx)?;
        let w = &self.water;
        WaterFile {
            model: match w.model {
                WaterModel::CircularCosine => WaterModelFile::CircularCosine,
                WaterModel::AxisCosineNoise => WaterModelFile::AxisCosineNoise,
            },
            level: w.level.into(),
            amplitude: w.amplitude.into(),
            wavelength: w.wavelength.into(),
            speed: w.speed.into(),
            noise_amplitude: w.noise_amplitude.into(),
            noise_scale: w.noise_scale.into(),
            center: Some(v2(w.center)),
            extent_min: v2(w.extent_min),
            extent_max: v2(w.extent_max),
            ior: Some(w.ior.into()),
        }
        .validate(&ctx)?;
        let m = &self.medium;
        MediumFile {
            gamma: Some(Gamma::Rgb(v3(m.gamma))),
            scattering: Some(m.scattering.into()),
            hg_g: Some(m.hg_g.into()),
        }
        .validate(&ctx)?;
        let e = &self.effects;
        let spread = |s: PhotonSpread| match s {
            PhotonSpread::Even => PhotonSpreadFile::Even,
            PhotonSpread::View => PhotonSpreadFile::View,
        };
        EffectsFile {
            caustics: Some(e.caustics),
            godrays: Some(e.godrays),
            filter: Some(e.filter),
            caustic_estimator: Some(match e.caustic_estimator {
                CausticEstimator::Paper => CausticEstimatorFile::Paper,
                CausticEstimator::Footprint => CausticEstimatorFile::Footprint,
                CausticEstimator::Triangles => CausticEstimatorFile::Triangles,
            }),
            caustic_grid: Some(e.caustic_grid),
            caustic_subdivision: Some(e.caustic_subdivision),
            caustic_photon_density: Some(spread(e.caustic_photon_density)),
            caustic_refinement: Some(e.caustic_refinement),
            caustic_receiver_test: Some(e.caustic_receiver_test),
            photon_jitter: Some(e.photon_jitter),
            godray_method: Some(match e.godray_method {
                GodrayMethod::Beams => GodrayMethodFile::Beams,
                GodrayMethod::Footprint => GodrayMethodFile::Footprint,
                GodrayMethod::Marched => GodrayMethodFile::Marched,
            }),
            godray_photon_density: Some(spread(e.godray_photon_density)),
            godray_grid: Some(e.godray_grid),
            godray_subdivision: Some(e.godray_subdivision),
            caustic_target_scale: Some(e.caustic_target_scale.into()),
            godray_target_scale: Some(e.godray_target_scale.into()),
            point_size_min: Some(e.point_size_min.into()),
            point_size_max: Some(e.point_size_max.into()),
            line_width: Some(e.line_width.into()),
            iterations: Some(e.iterations),
            shadow_map_size: Some(e.shadow_map_size),
        }
        .validate(&ctx)?;
        marched_needs_a_directional_light(&ctx, e, l)?;
        for (i, mesh) in self.meshes.iter().enumerate() {
            let field = format!("meshes[{i}] ({:?})", mesh.name);
            let n = mesh.positions.len();
            if let Some(p) = mesh.positions.iter().find(|p| !p.is_finite()) {
                return Err(ctx.error(&field, format_args!("has a position that is not finite: {p}")));
            }
            if mesh.normals.len() != n || mesh.normals.iter().any(|v| !v.is_finite()) {
                return Err(ctx.error(&field, format_args!("needs {n} finite normals, one per position")));
            }
            if mesh.indices.len() % 3 != 0 {
                return Err(ctx.error(&field, format_args!("has {} indices: not whole triangles", mesh.indices.len())));
            }
            if let Some(k) = mesh.indices.iter().find(|k| **k as usize >= n) {
                return Err(ctx.error(&field, format_args!("index {k} is out of range: {n} positions")));
            }
        }
        if self.meshes.iter().all(|m| m.indices.is_empty()) {
            return Err(ctx.error("meshes", "contain no triangles"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_built_in_code_meets_the_files_ranges() {
        let tank = load("tank").unwrap();
        tank.validate().unwrap();
        let refused = |edit: &dyn Fn(&mut Scene), expected: &str| {
            let mut s = tank.clone();
            edit(&mut s);
            let e = s.validate().expect_err(expected).to_string();
            assert!(e.contains(expected), "{e}");
            assert!(e.contains("\"tank\" (built in code)"), "{e}");
        };
        refused(&|s| s.water.amplitude = f32::NAN, "water.amplitude = NaN is out of range: must be >= 0");
        refused(&|s| s.water.ior = 1.0, "water.ior = 1 is out of range");
        refused(&|s| s.light.direction = Vec3::Y, "light.direction = [0, 1, 0] is out of range: must point downwards");
        refused(&|s| s.camera.z_far = s.camera.z_near, "camera.z_far");
        refused(&|s| s.medium.hg_g = 1.0, "medium.hg_g = 1 is out of range");
        refused(&|s| s.output = [0, 10], "output.width = 0 is out of range");
        refused(
            &|s| {
                s.effects.caustic_estimator = CausticEstimator::Triangles;
                s.effects.caustic_subdivision = crate::shader_abi::limits::MAX_SUBDIVISION;
            },
            "is out of range for effects.caustic_estimator = \"triangles\"",
        );
        // The shipped footprint points need a neighbour in their coarse cell.
        refused(
            &|s| s.effects.caustic_subdivision = 1,
            "is out of range for effects.caustic_estimator = \"footprint\"",
        );
        refused(&|s| s.effects.point_size_max = f32::INFINITY, "effects.point_size_max = inf");
        refused(
            &|s| {
                s.light.kind = LightKind::Point;
                s.effects.godray_method = GodrayMethod::Marched;
            },
            "needs a directional light",
        );
        refused(&|s| s.meshes[0].indices[0] = 1 << 30, "index 1073741824 is out of range");
        refused(&|s| s.meshes[0].positions[0].x = f32::INFINITY, "has a position that is not finite");
        refused(&|s| s.meshes[0].normals.clear(), "finite normals, one per position");
        refused(&|s| s.meshes.iter_mut().for_each(|m| m.indices.clear()), "meshes contain no triangles");
    }

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
    fn fields_are_found_by_path_in_the_document() {
        let text = "water.level = 0\nname = 'x'\n[[objects]]\nobj = 'a'\n[[objects]]\nobj = 'b'\nscale = 2\n[medium]\ngamma = [1, 2, 3]\n";
        let ctx = Context { text, origin: Path::new("t.toml"), doc: ImDocument::parse(text).unwrap() };
        assert_eq!(ctx.at("objects[1].scale"), "t.toml:7");
        assert_eq!(ctx.at("medium.gamma[2]"), "t.toml:9");
        assert_eq!(ctx.at("water.level"), "t.toml:1", "dotted keys have a line too");
        assert_eq!(ctx.at("camera.position"), "t.toml", "absent fields have no line");
        assert_eq!(ctx.at("objects[2].scale"), "t.toml");
    }

    /// Loads `text` (no OBJ is read: each case fails before) and returns the error.
    fn schema_error(text: &str) -> String {
        format!("{:#}", load_str(text, Path::new("t.toml")).expect_err("accepted"))
    }

    #[test]
    fn arrays_must_have_exactly_their_length() {
        let base = "name = 'x'\nobjects = []\n[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0, 5]\n";
        let message = schema_error(base);
        assert!(message.contains("t.toml:5:11: camera.look_at: invalid length 4"), "{message}");
    }

    #[test]
    fn dates_are_named_and_quoted_keys_found() {
        let message = schema_error("name = 1979-05-27\n");
        assert!(message.contains("t.toml:1:8: name: invalid type: datetime, expected a string"), "{message}");
        let message = schema_error("name = 'x'\n[camera]\n'z.far' = 1\n");
        assert!(message.contains("t.toml:3:1: unknown field `camera.z.far`"), "{message}");
    }
}
