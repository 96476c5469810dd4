//! OBJ/MTL loading (with `tobj`) into validated triangle meshes.
//!
//! What the renderer gets from here: one [`Mesh`] per OBJ model (tobj starts a new model at
//! every `o`/`g` and at every material change), triangles only, finite positions, unit
//! normals for every vertex (computed when the file has none), no zero-area triangles, and an
//! albedo from the material's `Kd` (0.8 grey when there is none: no `usemtl`, a name no
//! `mtllib` defines, or a material without `Kd`). `usemtl` is a state, as in the OBJ format:
//! it carries over into later `o`/`g` groups.
//!
//! tobj reports errors without a position, so the text is read here first: indices are
//! checked line by line (tobj checks them only when a model ends, far from the culprit), and
//! tobj's own parse errors get the line it stopped at.

use super::Mesh;
use anyhow::{anyhow, bail, Context as _, Result};
use glam::Vec3;
use std::cell::RefCell;
use std::path::Path;

/// Albedo of geometry without a material (or whose material has no `Kd`).
pub const DEFAULT_ALBEDO: Vec3 = Vec3::splat(0.8);

/// What an OBJ file gave: its meshes, and what was repaired or ignored on the way (each a
/// line for the user: the file, the line numbers and what was done).
#[derive(Debug, Default)]
pub struct ObjModel {
    pub meshes: Vec<Mesh>,
    pub warnings: Vec<String>,
}

/// Loads an OBJ file (and the MTL files it names, relative to it) as world-space-ready meshes.
///
/// Files as exporters write them load, with a warning for what was repaired: names in
/// Latin-1 or UTF-16 (names are labels; the numbers are ASCII either way), zero-length
/// normals (replaced by their face's normal), empty material names, a missing MTL file (the
/// default material), polylines and points (`l`, `p`: ignored), and non-convex polygons
/// (triangulated by ear clipping, not as a fan, which would fill their holes).
pub fn load_obj(path: &Path) -> Result<ObjModel> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read OBJ file {}", path.display()))?;
    let mut warnings = Vec::new();
    let text = decode_text(&bytes, path, &mut warnings);
    check_obj_text(&text).map_err(|(line, message)| anyhow!("{}:{line}: {message}", path.display()))?;
    let text = prepare_for_tobj(&text, path, &mut warnings);

    // tobj's material callback cannot return our error, so it is parked here and checked
    // first: a broken MTL file would otherwise only show up as a missing material.
    let mtl_error: RefCell<Option<anyhow::Error>> = RefCell::new(None);
    let mtl_warnings: RefCell<Vec<String>> = RefCell::new(Vec::new());
    let base = path.parent().unwrap_or(Path::new(""));
    // Polygons are triangulated here (ear clipping), not by tobj (a fan).
    let options = tobj::LoadOptions { triangulate: false, single_index: true, ..Default::default() };
    // Reading from a slice leaves it at the end of the line tobj failed on.
    let mut rest = text.as_bytes();
    let loaded = tobj::load_obj_buf(&mut rest, &options, |mtl| load_mtl(&base.join(mtl), &mtl_error, &mtl_warnings));
    if let Some(e) = mtl_error.into_inner() {
        return Err(e.context(format!("{}: its mtllib", path.display())));
    }
    warnings.extend(mtl_warnings.into_inner());
    let (models, materials) = loaded.map_err(|e| anyhow!("{}:{}: {e}", path.display(), failing_line(&text, rest)))?;
    let materials = materials.map_err(|e| anyhow!("{}: materials: {e}", path.display()))?;

    let mut meshes = Vec::with_capacity(models.len());
    let mut repaired_normals = 0usize;
    for model in models {
        let material = model.mesh.material_id.and_then(|id| materials.get(id));
        let albedo = match material.and_then(|m| m.diffuse) {
            Some(kd) => {
                let kd = Vec3::from_array(kd);
                if !kd.is_finite() || kd.min_element() < 0.0 || kd.max_element() > 1.0 {
                    bail!(
                        "{}: material `{}`: Kd = [{}, {}, {}] is out of range: each component must be in [0, 1]",
                        path.display(),
                        material.map_or("", |m| m.name.as_str()),
                        kd.x,
                        kd.y,
                        kd.z
                    );
                }
                kd
            }
            None => DEFAULT_ALBEDO,
        };
        if let Some((mesh, repaired)) = build_mesh(model.name, &model.mesh, albedo) {
            repaired_normals += repaired;
            meshes.push(mesh);
        }
    }
    if repaired_normals > 0 {
        warnings.push(format!(
            "{}: {repaired_normals} face corner(s) had a zero-length normal: each takes its face's normal",
            path.display()
        ));
    }
    Ok(ObjModel { meshes, warnings })
}

/// The text of an OBJ or MTL file. UTF-8 (with or without a byte-order mark) as it is;
/// UTF-16 (by its byte-order mark, or by the zero bytes of ASCII text) decoded; anything else
/// read as Latin-1, every byte one character: exporters write material and object names in
/// the system's 8-bit code page, and those names are only labels.
fn decode_text(bytes: &[u8], path: &Path, warnings: &mut Vec<String>) -> String {
    let utf16 = |bytes: &[u8], little: bool| -> String {
        let units = bytes.chunks_exact(2).map(|c| {
            if little {
                u16::from_le_bytes([c[0], c[1]])
            } else {
                u16::from_be_bytes([c[0], c[1]])
            }
        });
        char::decode_utf16(units).map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER)).collect()
    };
    // A UTF-8 byte-order mark is dropped whatever follows, so it never reaches the first
    // keyword (even when the rest is then read as Latin-1).
    let bytes = bytes.strip_prefix(&[0xEF, 0xBB, 0xBF]).unwrap_or(bytes);
    let (little, rest) = match bytes {
        [0xFF, 0xFE, rest @ ..] => (Some(true), rest),
        [0xFE, 0xFF, rest @ ..] => (Some(false), rest),
        _ => (None, bytes),
    };
    // Without a mark: ASCII text in UTF-16 has a zero in every other byte.
    let zeros_at = |parity: usize| bytes.iter().skip(parity).step_by(2).filter(|&&b| b == 0).count();
    let half = bytes.len() / 2;
    let little = little.or_else(|| {
        (half >= 4 && zeros_at(1) * 10 >= half * 9)
            .then_some(true)
            .or((half >= 4 && zeros_at(0) * 10 >= half * 9).then_some(false))
    });
    if let Some(little) = little {
        warnings.push(format!(
            "{}: decoded as UTF-16 ({}-endian); UTF-8 is what OBJ readers expect",
            path.display(),
            if little { "little" } else { "big" }
        ));
        return utf16(rest, little);
    }
    match std::str::from_utf8(bytes) {
        Ok(text) => text.to_owned(),
        Err(e) => {
            let line = bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
            warnings.push(format!(
                "{}:{line}: not UTF-8 (byte 0x{:02X}): the file is read as Latin-1, so names show as their 8-bit characters",
                path.display(),
                bytes[e.valid_up_to()]
            ));
            bytes.iter().map(|&b| b as char).collect()
        }
    }
}

/// Rewrites what tobj refuses but the renderer can use, keeping every line where it is (so
/// tobj's line numbers stay true): `l` and `p` records become empty lines (with a warning:
/// underlight renders faces), and an empty `usemtl` / `newmtl` name becomes `(unnamed)`.
fn prepare_for_tobj(text: &str, path: &Path, warnings: &mut Vec<String>) -> String {
    let mut out = String::with_capacity(text.len());
    let mut skipped: Vec<usize> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("l" | "p") => skipped.push(i + 1),
            Some(keyword @ ("usemtl" | "newmtl")) if words.next().is_none() => {
                out.push_str(keyword);
                out.push(' ');
                out.push_str(UNNAMED_MATERIAL);
            }
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    if !skipped.is_empty() {
        let shown: Vec<String> = skipped.iter().take(5).map(|l| l.to_string()).collect();
        warnings.push(format!(
            "{}: ignored {} polyline/point record(s) (`l`, `p`; lines {}{}): underlight renders faces only",
            path.display(),
            skipped.len(),
            shown.join(", "),
            if skipped.len() > 5 { ", …" } else { "" }
        ));
    }
    out
}

/// The name an empty `newmtl` / `usemtl` gets.
pub const UNNAMED_MATERIAL: &str = "(unnamed)";

/// Loads one MTL file for tobj. A failure is parked in `error` with the file (and the line
/// tobj stopped at), since tobj would only keep its position-less error kind. A missing file
/// is a warning: the model renders with the default material.
fn load_mtl(
    path: &Path,
    error: &RefCell<Option<anyhow::Error>>,
    warnings: &RefCell<Vec<String>>,
) -> tobj::MTLLoadResult {
    let park = |e: anyhow::Error, kind: tobj::LoadError| {
        error.borrow_mut().get_or_insert(e);
        Err(kind)
    };
    let bytes = match std::fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            warnings.borrow_mut().push(format!(
                "MTL file {} does not exist: its materials get the default albedo {}",
                path.display(),
                DEFAULT_ALBEDO.x
            ));
            return Ok((Vec::new(), Default::default()));
        }
        Err(e) => {
            return park(anyhow!("cannot read MTL file {}: {e}", path.display()), tobj::LoadError::OpenFileFailed)
        }
    };
    let mut notes = Vec::new();
    let text = decode_text(&bytes, path, &mut notes);
    warnings.borrow_mut().extend(notes);
    if let Err((line, message)) = check_mtl_text(&text) {
        return park(anyhow!("{}:{line}: {message}", path.display()), tobj::LoadError::MaterialParseError);
    }
    let text = prepare_for_tobj(&text, path, &mut Vec::new());
    let mut rest = text.as_bytes();
    match tobj::load_mtl_buf(&mut rest) {
        Ok(loaded) => Ok(loaded),
        Err(e) => park(anyhow!("{}:{}: {e}", path.display(), failing_line(&text, rest)), e),
    }
}

/// Numbers in an MTL file, quoted with their line when one does not parse (tobj says only
/// which kind of value failed).
fn check_mtl_text(text: &str) -> std::result::Result<(), (usize, String)> {
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(keyword @ ("Ka" | "Kd" | "Ks" | "Ke" | "Tf" | "Ns" | "Ni" | "d" | "Tr" | "illum")) = words.next() {
            for w in words {
                if w.parse::<f32>().is_err() {
                    return Err((i + 1, format!("`{keyword}` value `{w}` is not a number")));
                }
            }
        }
    }
    Ok(())
}

/// The 1-based line a `BufRead` over `text` stopped at, given what it left unread: the last
/// line it consumed, newline included.
fn failing_line(text: &str, unread: &[u8]) -> usize {
    let consumed = &text[..text.len() - unread.len()];
    consumed.trim_end_matches('\n').matches('\n').count() + 1
}

/// Checks what tobj does not check (or checks too late to say where): face indices against
/// the vertices defined so far, non-finite coordinates, zero-length normals and empty faces.
/// Returns the 1-based line and a message.
fn check_obj_text(text: &str) -> std::result::Result<(), (usize, String)> {
    let (mut positions, mut texcoords, mut normals) = (0usize, 0usize, 0usize);
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some(keyword @ ("v" | "vn" | "vt")) => {
                let mut xyz = Vec::with_capacity(3);
                for w in words.by_ref() {
                    let value: f32 =
                        w.parse().map_err(|_| (line_no, format!("`{keyword}` coordinate `{w}` is not a number")))?;
                    xyz.push(value);
                }
                let needed = if keyword == "vt" { 1 } else { 3 };
                if xyz.len() < needed {
                    return Err((
                        line_no,
                        format!("`{keyword}` needs {needed} coordinate(s), got {} in `{}`", xyz.len(), line.trim()),
                    ));
                }
                if xyz.iter().any(|c| !c.is_finite()) {
                    return Err((line_no, format!("non-finite coordinate in `{}`", line.trim())));
                }
                // A zero-length normal is repaired later (its face's normal), with a warning.
                match keyword {
                    "v" => positions += 1,
                    "vn" => normals += 1,
                    _ => texcoords += 1,
                }
            }
            Some(keyword @ ("f" | "l")) => {
                let mut corners = 0;
                for corner in words {
                    corners += 1;
                    check_corner(corner, [positions, texcoords, normals])
                        .map_err(|message| (line_no, format!("{keyword} `{corner}`: {message}")))?;
                }
                if corners == 0 {
                    return Err((line_no, format!("`{keyword}` without vertices")));
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// One face corner (`v`, `v/vt`, `v//vn` or `v/vt/vn`; negative = relative to the end),
/// against the element counts defined so far.
fn check_corner(corner: &str, counts: [usize; 3]) -> std::result::Result<(), String> {
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    let parts: Vec<&str> = corner.split('/').collect();
    if parts.len() > 3 || parts[0].is_empty() {
        return Err("malformed face corner: expected v, v/vt, v//vn or v/vt/vn".to_owned());
    }
    for (k, part) in parts.iter().enumerate().filter(|(_, p)| !p.is_empty()) {
        let index: i64 = part.parse().map_err(|_| format!("{} index {part:?} is not an integer", WHAT[k]))?;
        let count = counts[k] as i64;
        let in_range = if index > 0 { index <= count } else { index < 0 && -index <= count };
        if !in_range {
            return Err(format!(
                "{} index {index} is out of range: {count} defined so far (valid: 1..={count} or -{count}..=-1)",
                WHAT[k]
            ));
        }
    }
    Ok(())
}

/// A tobj mesh as a renderer mesh: polygons triangulated (ear clipping), zero-area triangles
/// dropped, unused vertices removed, normals made unit (or computed). A face corner whose
/// normal has zero length takes its face's normal. `None` when no triangle is left; else the
/// mesh and the number of corners whose normal was repaired.
fn build_mesh(name: String, mesh: &tobj::Mesh, albedo: Vec3) -> Option<(Mesh, usize)> {
    let mut positions: Vec<Vec3> = mesh.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
    let triangles: Vec<[u32; 3]> = triangulate(&positions, &mesh.indices, &mesh.face_arities)
        .into_iter()
        .filter(|t| !is_degenerate(positions[t[0] as usize], positions[t[1] as usize], positions[t[2] as usize]))
        .collect();
    if triangles.is_empty() {
        return None;
    }
    // With `single_index` tobj stores a normal per vertex only if every face corner had one;
    // a file that mixes faces with and without normals yields fewer normals than vertices,
    // and then they cannot be matched to vertices: compute them all instead.
    if mesh.normals.len() != mesh.positions.len() {
        let (positions, triangles) = compact_positions(&positions, &triangles);
        let (p, n, i) = smooth_normals(positions, triangles);
        return Some((Mesh { name, positions: p, normals: n, indices: i, albedo }, 0));
    }
    let mut normals: Vec<Vec3> = mesh
        .normals
        .chunks_exact(3)
        .map(|n| Vec3::new(n[0], n[1], n[2]).try_normalize().unwrap_or(Vec3::ZERO))
        .collect();
    // A zero normal cannot be lit: its corner gets a copy of the vertex with the face's normal.
    let mut repaired = 0;
    let mut fixed: Vec<[u32; 3]> = Vec::with_capacity(triangles.len());
    for t in &triangles {
        let mut t = *t;
        let flat = face_normal(&positions, &t).normalize();
        for v in &mut t {
            if normals[*v as usize] == Vec3::ZERO {
                repaired += 1;
                positions.push(positions[*v as usize]);
                normals.push(flat);
                *v = (positions.len() - 1) as u32;
            }
        }
        fixed.push(t);
    }
    let (positions, normals, indices) = compact(&positions, &normals, &fixed);
    Some((Mesh { name, positions, normals, indices, albedo }, repaired))
}

/// Triangles of tobj's faces: `arities` gives each face's corner count (empty: all are
/// triangles). Polygons are ear-clipped in their own plane (Newell's normal), so a
/// non-convex outline, or a ring bridged to its hole, keeps its shape; a fan from the first
/// corner would cover the concave parts and the hole.
fn triangulate(positions: &[Vec3], indices: &[u32], arities: &[u32]) -> Vec<[u32; 3]> {
    if arities.is_empty() {
        return indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    }
    let mut out = Vec::with_capacity(indices.len());
    let mut start = 0usize;
    for &n in arities {
        let face = &indices[start..start + n as usize];
        start += n as usize;
        ear_clip(positions, face, &mut out);
    }
    out
}

/// Ear clipping of one polygon (corners in order, either winding): repeatedly cuts off a
/// convex corner whose triangle holds no other corner. Output triangles keep the polygon's
/// winding. A polygon with no ear left (self-intersecting) is finished as a fan.
fn ear_clip(positions: &[Vec3], face: &[u32], out: &mut Vec<[u32; 3]>) {
    if face.len() < 3 {
        return;
    }
    // Newell's normal: robust for non-convex and slightly non-planar polygons.
    let mut normal = Vec3::ZERO;
    for i in 0..face.len() {
        let (a, b) = (positions[face[i] as usize], positions[face[(i + 1) % face.len()] as usize]);
        normal += Vec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    let Some(normal) = normal.try_normalize() else {
        return; // zero area
    };
    // 2-D coordinates in the polygon's plane, counter-clockwise about `normal`.
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let p2 = |i: u32| {
        let p = positions[i as usize];
        glam::Vec2::new(p.dot(u), p.dot(v))
    };
    let cross = |a: glam::Vec2, b: glam::Vec2, c: glam::Vec2| (b - a).perp_dot(c - a);
    let mut ring: Vec<u32> = face.to_vec();
    let mut guard = 0;
    while ring.len() > 3 && guard < 2 * face.len() * face.len() {
        guard += 1;
        let n = ring.len();
        let mut cut = None;
        for i in 0..n {
            let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            let (pa, pb, pc) = (p2(a), p2(b), p2(c));
            if cross(pa, pb, pc) <= 0.0 {
                continue; // reflex or straight: not an ear
            }
            // No other corner inside (or on) the ear; corners that coincide with the ear's
            // own (a bridge to a hole visits them twice) do not count.
            let blocked = ring.iter().any(|&k| {
                let pk = p2(k);
                if pk == pa || pk == pb || pk == pc {
                    return false;
                }
                cross(pa, pb, pk) >= 0.0 && cross(pb, pc, pk) >= 0.0 && cross(pc, pa, pk) >= 0.0
            });
            if !blocked {
                cut = Some(i);
                break;
            }
        }
        let Some(i) = cut else { break };
        let n = ring.len();
        out.push([ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]]);
        ring.remove(i);
    }
    // Three corners left (or no ear: a self-intersecting outline), finished as a fan.
    for k in 1..ring.len() - 1 {
        out.push([ring[0], ring[k], ring[k + 1]]);
    }
}

/// Zero area, up to rounding: the edges' cross product is tiny relative to their lengths
/// (collinear or coincident corners). Such triangles rasterise to nothing and have no normal.
fn is_degenerate(a: Vec3, b: Vec3, c: Vec3) -> bool {
    let (e1, e2) = (b - a, c - a);
    e1.cross(e2).length() <= 1e-6 * e1.length() * e2.length()
}

/// Keeps only the vertices the triangles use, renumbered in first-use order.
fn compact(positions: &[Vec3], normals: &[Vec3], triangles: &[[u32; 3]]) -> (Vec<Vec3>, Vec<Vec3>, Vec<u32>) {
    let mut remap = vec![u32::MAX; positions.len()];
    let (mut out_p, mut out_n, mut indices) = (Vec::new(), Vec::new(), Vec::with_capacity(triangles.len() * 3));
    for &v in triangles.iter().flatten() {
        let slot = &mut remap[v as usize];
        if *slot == u32::MAX {
            *slot = out_p.len() as u32;
            out_p.push(positions[v as usize]);
            out_n.push(normals[v as usize]);
        }
        indices.push(*slot);
    }
    (out_p, out_n, indices)
}

fn compact_positions(positions: &[Vec3], triangles: &[[u32; 3]]) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let (p, _, indices) = compact(positions, &vec![Vec3::ZERO; positions.len()], triangles);
    (p, indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect())
}

/// Area-weighted smooth vertex normals (the unnormalised face cross product is twice the
/// area). Where the faces around a vertex cancel out (a vertex shared by the two sides of a
/// thin sheet, say) there is no meaningful average, so that vertex is split into one copy
/// per face, each with the face's own normal.
fn smooth_normals(mut positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> (Vec<Vec3>, Vec<Vec3>, Vec<u32>) {
    let mut sum = vec![Vec3::ZERO; positions.len()];
    let mut magnitude = vec![0.0f32; positions.len()];
    for t in &triangles {
        let n = face_normal(&positions, t);
        for &v in t {
            sum[v as usize] += n;
            magnitude[v as usize] += n.length();
        }
    }
    let cancelled = |v: usize| sum[v].length() <= 1e-4 * magnitude[v] || sum[v].try_normalize().is_none();
    let mut normals: Vec<Vec3> = sum.iter().map(|n| n.try_normalize().unwrap_or(Vec3::Y)).collect();
    let mut indices = Vec::with_capacity(triangles.len() * 3);
    let mut split_any = false;
    for t in &triangles {
        let flat = face_normal(&positions, t).normalize();
        for &v in t {
            if cancelled(v as usize) {
                split_any = true;
                indices.push(positions.len() as u32);
                positions.push(positions[v as usize]);
                normals.push(flat);
            } else {
                indices.push(v);
            }
        }
    }
    if split_any {
        // The split vertices' originals are now unused (and have no valid normal).
        let triangles: Vec<[u32; 3]> = indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        return compact(&positions, &normals, &triangles);
    }
    (positions, normals, indices)
}

/// The unnormalised normal of a triangle (its length is twice the area).
fn face_normal(positions: &[Vec3], t: &[u32; 3]) -> Vec3 {
    let [a, b, c] = t.map(|i| positions[i as usize]);
    (b - a).cross(c - a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_are_checked_against_what_is_defined_so_far() {
        assert!(check_corner("3", [3, 0, 0]).is_ok());
        assert!(check_corner("-3", [3, 0, 0]).is_ok());
        assert!(check_corner("3/1/2", [3, 1, 2]).is_ok());
        assert!(check_corner("3//2", [3, 0, 2]).is_ok());
        assert!(check_corner("4", [3, 0, 0]).unwrap_err().contains("vertex index 4 is out of range"));
        assert!(check_corner("0", [3, 0, 0]).is_err());
        assert!(check_corner("-4", [3, 0, 0]).is_err());
        assert!(check_corner("1//3", [3, 0, 2]).unwrap_err().contains("normal index 3"));
        assert!(check_corner("1/2", [3, 1, 0]).unwrap_err().contains("texture coordinate index 2"));
        assert!(check_corner("x", [3, 0, 0]).is_err());
        assert!(check_corner("1/1/1/1", [3, 1, 1]).is_err());
    }

    #[test]
    fn text_errors_name_the_line() {
        let (line, message) = check_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n").unwrap_err();
        assert_eq!(line, 4);
        assert!(message.contains("vertex index 4"), "{message}");
        assert_eq!(check_obj_text("v 0 0 0\nv nan 0 0\n").unwrap_err().0, 2);
        // A zero normal is repaired later, not refused; a bad number is quoted.
        assert!(check_obj_text("v 0 0 0\nvn 0 0 0\n").is_ok());
        let (line, message) = check_obj_text("v 0 0 0\nv 1 0x 0\n").unwrap_err();
        assert_eq!(line, 2);
        assert!(message.contains("`0x`"), "{message}");
        assert_eq!(check_obj_text("v 0 0 0\nf\n").unwrap_err().0, 2);
        // A forward reference is an error even though the vertex comes later.
        assert_eq!(check_obj_text("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap_err().0, 1);
    }

    #[test]
    fn a_utf8_byte_order_mark_never_reaches_the_first_keyword() {
        let mut warnings = Vec::new();
        let path = Path::new("bom.obj");
        assert_eq!(decode_text(b"\xEF\xBB\xBFv 0 0 0\n", path, &mut warnings), "v 0 0 0\n");
        // Followed by a Latin-1 byte: read as Latin-1, still without the mark.
        assert_eq!(decode_text(b"\xEF\xBB\xBFv 0 0 0\n# caf\xE9\n", path, &mut warnings), "v 0 0 0\n# caf\u{e9}\n");
        assert_eq!(warnings.len(), 1, "{warnings:?}");
    }

    #[test]
    fn ear_clipping_keeps_concave_corners_and_holes_empty() {
        // An L shape (concave at corner 3), counter-clockwise seen from +z: area 3.
        let l = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)];
        let positions: Vec<Vec3> = l.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
        let mut tris = Vec::new();
        ear_clip(&positions, &[0, 1, 2, 3, 4, 5], &mut tris);
        let area: f32 = tris.iter().map(|t| face_normal(&positions, t).z / 2.0).sum();
        assert_eq!(tris.len(), 4);
        assert!((area - 3.0).abs() < 1e-5, "{area}: every triangle inside, same winding");
        // A 4×4 square with a 2×2 hole, bridged from (0,0) to (1,1): area 12, and no triangle
        // covers the hole's centre.
        let ring = [
            (0.0, 0.0),
            (4.0, 0.0),
            (4.0, 4.0),
            (0.0, 4.0),
            (0.0, 0.0),
            (1.0, 1.0),
            (1.0, 3.0),
            (3.0, 3.0),
            (3.0, 1.0),
            (1.0, 1.0),
        ];
        let positions: Vec<Vec3> = ring.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
        let mut tris = Vec::new();
        ear_clip(&positions, &(0..positions.len() as u32).collect::<Vec<_>>(), &mut tris);
        let area: f32 = tris.iter().map(|t| face_normal(&positions, t).z / 2.0).sum();
        assert!((area - 12.0).abs() < 1e-4, "area {area}");
        let centre = glam::Vec2::new(2.5, 1.5); // inside the hole, off the diagonals
        for t in &tris {
            let [a, b, c] = t.map(|i| positions[i as usize].truncate());
            let inside = (b - a).perp_dot(centre - a) > 0.0
                && (c - b).perp_dot(centre - b) > 0.0
                && (a - c).perp_dot(centre - c) > 0.0;
            assert!(!inside, "triangle {t:?} covers the hole");
        }
    }

    #[test]
    fn degenerate_triangles_are_recognised() {
        let (a, b) = (Vec3::ZERO, Vec3::X);
        assert!(is_degenerate(a, b, Vec3::new(2.0, 0.0, 0.0)), "collinear");
        assert!(is_degenerate(a, a, b), "coincident corners");
        assert!(!is_degenerate(a, b, Vec3::Y));
        assert!(!is_degenerate(a, Vec3::splat(1e-3), Vec3::new(1e-3, 0.0, 0.0)), "small is not degenerate");
    }

    #[test]
    fn smooth_normals_average_and_split_where_faces_cancel() {
        // Two triangles of a square in the xz plane, seen from above: one shared normal +y.
        let square = vec![Vec3::ZERO, Vec3::Z, Vec3::new(1.0, 0.0, 1.0), Vec3::X];
        let (p, n, i) = smooth_normals(square, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!((p.len(), i.len()), (4, 6));
        assert!(n.iter().all(|n| (*n - Vec3::Y).length() < 1e-6), "{n:?}");
        // The same triangle both ways round: every vertex cancels and is split.
        let tri = vec![Vec3::ZERO, Vec3::X, Vec3::Z];
        let (p, n, i) = smooth_normals(tri, vec![[0, 1, 2], [0, 2, 1]]);
        assert_eq!((p.len(), i.len()), (6, 6));
        assert!(n.iter().all(|n| (n.length() - 1.0).abs() < 1e-6 && n.y.abs() > 0.999), "{n:?}");
    }
}
