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

/// Loads an OBJ file (and the MTL files it names, relative to it) as world-space-ready meshes.
pub fn load_obj(path: &Path) -> Result<Vec<Mesh>> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read OBJ file {}", path.display()))?;
    check_obj_text(&text).map_err(|(line, message)| anyhow!("{}:{line}: {message}", path.display()))?;

    // tobj's material callback cannot return our error, so it is parked here and checked
    // first: a broken MTL file would otherwise only show up as a missing material.
    let mtl_error: RefCell<Option<anyhow::Error>> = RefCell::new(None);
    let base = path.parent().unwrap_or(Path::new(""));
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    // Reading from a slice leaves it at the end of the line tobj failed on.
    let mut rest = text.as_bytes();
    let loaded = tobj::load_obj_buf(&mut rest, &options, |mtl| load_mtl(&base.join(mtl), &mtl_error));
    if let Some(e) = mtl_error.into_inner() {
        return Err(e.context(format!("{}: its mtllib", path.display())));
    }
    let (models, materials) = loaded.map_err(|e| anyhow!("{}:{}: {e}", path.display(), failing_line(&text, rest)))?;
    let materials = materials.map_err(|e| anyhow!("{}: materials: {e}", path.display()))?;

    let mut meshes = Vec::with_capacity(models.len());
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
        if let Some(mesh) = build_mesh(model.name, &model.mesh, albedo) {
            meshes.push(mesh);
        }
    }
    Ok(meshes)
}

/// Loads one MTL file for tobj. A failure is parked in `error` with the file (and the line
/// tobj stopped at), since tobj would only keep its position-less error kind.
fn load_mtl(path: &Path, error: &RefCell<Option<anyhow::Error>>) -> tobj::MTLLoadResult {
    let park = |e: anyhow::Error, kind: tobj::LoadError| {
        error.borrow_mut().get_or_insert(e);
        Err(kind)
    };
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) => {
            return park(anyhow!("cannot read MTL file {}: {e}", path.display()), tobj::LoadError::OpenFileFailed)
        }
    };
    let mut rest = text.as_bytes();
    match tobj::load_mtl_buf(&mut rest) {
        Ok(loaded) => Ok(loaded),
        Err(e) => park(anyhow!("{}:{}: {e}", path.display(), failing_line(&text, rest)), e),
    }
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
            Some(keyword @ ("v" | "vn")) => {
                // Parse failures are left to tobj; only values Rust parses but the renderer
                // cannot use (`nan`, `inf`) are caught here.
                let xyz: Vec<f32> = words.take(3).filter_map(|w| w.parse().ok()).collect();
                if xyz.iter().any(|c| !c.is_finite()) {
                    return Err((line_no, format!("non-finite coordinate in `{}`", line.trim())));
                }
                if keyword == "v" {
                    positions += 1;
                } else {
                    // Zero, or so small or large that its length under- or overflows.
                    if xyz.len() == 3 && Vec3::new(xyz[0], xyz[1], xyz[2]).try_normalize().is_none() {
                        return Err((line_no, format!("zero-length normal `{}` cannot be normalised", line.trim())));
                    }
                    normals += 1;
                }
            }
            Some("vt") => texcoords += 1,
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

/// A tobj mesh as a renderer mesh: zero-area triangles dropped, unused vertices removed,
/// normals made unit (or computed). `None` when no triangle is left.
fn build_mesh(name: String, mesh: &tobj::Mesh, albedo: Vec3) -> Option<Mesh> {
    let positions: Vec<Vec3> = mesh.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
    // With `single_index` tobj stores a normal per vertex only if every face corner had one;
    // a file that mixes faces with and without normals yields fewer normals than vertices,
    // and then they cannot be matched to vertices: compute them all instead.
    let given_normals = (mesh.normals.len() == mesh.positions.len())
        .then(|| mesh.normals.chunks_exact(3).map(|n| Vec3::new(n[0], n[1], n[2]).normalize()).collect::<Vec<_>>());

    let triangles: Vec<[u32; 3]> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .filter(|t| !is_degenerate(positions[t[0] as usize], positions[t[1] as usize], positions[t[2] as usize]))
        .collect();
    if triangles.is_empty() {
        return None;
    }
    let (positions, normals, indices) = match given_normals {
        Some(normals) => compact(&positions, &normals, &triangles),
        None => {
            let (positions, triangles) = compact_positions(&positions, &triangles);
            smooth_normals(positions, triangles)
        }
    };
    Some(Mesh { name, positions, normals, indices, albedo })
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
        assert_eq!(check_obj_text("v 0 0 0\nvn 0 0 0\n").unwrap_err().0, 2);
        assert_eq!(check_obj_text("v 0 0 0\nf\n").unwrap_err().0, 2);
        // A forward reference is an error even though the vertex comes later.
        assert_eq!(check_obj_text("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap_err().0, 1);
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
