//! A bounding-volume hierarchy over the scene's triangles, in f64: the reference renderer's
//! exact ray casts (photon paths, shadow rays, camera rays), and the frame's survey of what
//! the camera sees (`frame::photon_density`). A leaf: it knows triangles, not the method.
//!
//! Built top-down with a binned surface-area heuristic: at each node the triangles'
//! centroids are binned along the widest centroid axis and the split that minimises
//! `area(left)·count(left) + area(right)·count(right)` is taken, or the node becomes a
//! leaf when no split beats intersecting its triangles directly. Scenes here hold at most a
//! few hundred thousand triangles, so a plain build is fast enough and keeps the code short.

use glam::DVec3;

/// A ray's first hit.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Distance along the (unit) ray direction.
    pub t: f64,
    /// Unit geometric normal of the triangle hit (its winding's side; the caller takes |cos|).
    pub normal: DVec3,
}

#[derive(Clone, Copy, Debug)]
struct Triangle {
    v0: DVec3,
    e1: DVec3,
    e2: DVec3,
}

impl Triangle {
    /// Möller–Trumbore, two-sided: the distance in (t_min, t_max) or `None`.
    fn intersect(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
        let p = d.cross(self.e2);
        let det = self.e1.dot(p);
        // Relative test: a ray in the triangle's plane (or a degenerate triangle) misses.
        if det.abs() <= 1e-14 * self.e1.length() * self.e2.length() {
            return None;
        }
        let inv = 1.0 / det;
        let s = o - self.v0;
        let u = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(self.e1);
        let v = d.dot(q) * inv;
        if v < 0.0 || u + v > 1.0 {
            return None;
        }
        let t = self.e2.dot(q) * inv;
        (t > t_min && t < t_max).then_some(t)
    }

    fn normal(&self) -> DVec3 {
        self.e1.cross(self.e2).normalize()
    }
}

#[derive(Clone, Copy, Debug)]
struct Aabb {
    lo: DVec3,
    hi: DVec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb { lo: DVec3::splat(f64::INFINITY), hi: DVec3::splat(f64::NEG_INFINITY) };

    fn grow(&mut self, p: DVec3) {
        self.lo = self.lo.min(p);
        self.hi = self.hi.max(p);
    }

    fn union(self, o: Aabb) -> Aabb {
        Aabb { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }

    fn half_area(&self) -> f64 {
        let e = (self.hi - self.lo).max(DVec3::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    }

    /// Entry distance of the ray into the box within [t_min, t_max], if it meets it.
    /// `inv_d` is 1/d per axis (±∞ for a zero component; `f64::min`/`max` drop the NaN that
    /// 0·∞ gives when the origin lies on a slab's plane).
    fn entry(&self, o: DVec3, inv_d: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
        let a = (self.lo - o) * inv_d;
        let b = (self.hi - o) * inv_d;
        let mut t0 = t_min;
        let mut t1 = t_max;
        for k in 0..3 {
            t0 = t0.max(a[k].min(b[k]));
            t1 = t1.min(a[k].max(b[k]));
        }
        (t0 <= t1).then_some(t0)
    }
}

/// A node: a leaf holds `count > 0` triangles from `first`; an inner node's children are
/// nodes `first` and `first + 1`.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    first: u32,
    count: u32,
}

pub struct Bvh {
    nodes: Vec<Node>,
    triangles: Vec<Triangle>,
}

const BINS: usize = 16;
const LEAF_SIZE: usize = 4;
const MAX_DEPTH: usize = 60;
/// Cost of a node visit relative to one triangle test, for the SAH.
const TRAVERSAL_COST: f64 = 1.0;

struct Item {
    bounds: Aabb,
    centroid: DVec3,
    triangle: Triangle,
}

impl Bvh {
    /// Builds over triangle soup `[a, b, c]` (degenerate triangles are dropped).
    pub fn build(triangles: impl IntoIterator<Item = [DVec3; 3]>) -> Bvh {
        let mut items: Vec<Item> = triangles
            .into_iter()
            .filter_map(|[a, b, c]| {
                let triangle = Triangle { v0: a, e1: b - a, e2: c - a };
                if !(triangle.e1.cross(triangle.e2).length_squared() > 0.0) {
                    return None;
                }
                let mut bounds = Aabb::EMPTY;
                for p in [a, b, c] {
                    bounds.grow(p);
                }
                Some(Item { bounds, centroid: (a + b + c) / 3.0, triangle })
            })
            .collect();
        let mut nodes = vec![Node { bounds: Aabb::EMPTY, first: 0, count: 0 }];
        if !items.is_empty() {
            let n = items.len();
            build_node(&mut nodes, 0, &mut items, 0, n, 0);
        }
        Bvh { nodes, triangles: items.into_iter().map(|i| i.triangle).collect() }
    }

    /// Over every triangle of the scene's meshes.
    pub fn of_scene(scene: &crate::scene::Scene) -> Bvh {
        Bvh::build(scene.meshes.iter().flat_map(|m| {
            m.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]].map(|i| m.positions[i as usize].as_dvec3()))
        }))
    }

    /// The nearest hit in (t_min, t_max) along unit direction `d`.
    pub fn closest(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<Hit> {
        let mut best: Option<(f64, u32)> = None;
        let mut t_max = t_max;
        self.traverse(o, d, t_min, &mut t_max, |tri, t_min, t_max| {
            let t = self.triangles[tri as usize].intersect(o, d, t_min, *t_max)?;
            *t_max = t;
            best = Some((t, tri));
            Some(false)
        });
        best.map(|(t, tri)| Hit { t, normal: self.triangles[tri as usize].normal() })
    }

    /// Whether anything lies in (t_min, t_max) along `d`.
    pub fn occluded(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> bool {
        let mut t_max = t_max;
        let mut hit = false;
        self.traverse(o, d, t_min, &mut t_max, |tri, t_min, t_max| {
            self.triangles[tri as usize].intersect(o, d, t_min, *t_max)?;
            hit = true;
            Some(true)
        });
        hit
    }

    /// Visits the triangles of the leaves the ray meets, nearer child first. `test` returns
    /// `Some(true)` to stop, and may shrink `t_max`.
    fn traverse(
        &self,
        o: DVec3,
        d: DVec3,
        t_min: f64,
        t_max: &mut f64,
        mut test: impl FnMut(u32, f64, &mut f64) -> Option<bool>,
    ) {
        if self.triangles.is_empty() {
            return;
        }
        let inv_d = DVec3::ONE / d;
        let mut stack = [0u32; 64];
        let mut top = 0;
        if self.nodes[0].bounds.entry(o, inv_d, t_min, *t_max).is_none() {
            return;
        }
        stack[0] = 0;
        top += 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            // A hit found since this node was pushed may put it out of reach.
            if node.bounds.entry(o, inv_d, t_min, *t_max).is_none() {
                continue;
            }
            if node.count > 0 {
                for tri in node.first..node.first + node.count {
                    if test(tri, t_min, t_max) == Some(true) {
                        return;
                    }
                }
                continue;
            }
            let (l, r) = (node.first, node.first + 1);
            let tl = self.nodes[l as usize].bounds.entry(o, inv_d, t_min, *t_max);
            let tr = self.nodes[r as usize].bounds.entry(o, inv_d, t_min, *t_max);
            // Push the farther child first so the nearer one is visited first.
            let mut push = |n: u32| {
                stack[top] = n;
                top += 1;
            };
            match (tl, tr) {
                (Some(a), Some(b)) if a <= b => {
                    push(r);
                    push(l);
                }
                (Some(_), Some(_)) => {
                    push(l);
                    push(r);
                }
                (Some(_), None) => push(l),
                (None, Some(_)) => push(r),
                (None, None) => {}
            }
        }
    }
}

/// Fills `nodes[index]` with items[start..end], recursing into children.
fn build_node(nodes: &mut Vec<Node>, index: usize, items: &mut [Item], start: usize, end: usize, depth: usize) {
    let mut bounds = Aabb::EMPTY;
    let mut centroids = Aabb::EMPTY;
    for it in &items[start..end] {
        bounds = bounds.union(it.bounds);
        centroids.grow(it.centroid);
    }
    let count = end - start;
    let leaf = Node { bounds, first: start as u32, count: count as u32 };
    // The traversal stack holds at most depth + 1 entries: past MAX_DEPTH a node stays a
    // (large) leaf rather than overflow it.
    if count <= LEAF_SIZE || depth >= MAX_DEPTH {
        nodes[index] = leaf;
        return;
    }
    let extent = centroids.hi - centroids.lo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    if !(extent[axis] > 0.0) {
        nodes[index] = leaf;
        return;
    }
    let bin_of = |c: DVec3| (((c[axis] - centroids.lo[axis]) / extent[axis] * BINS as f64) as usize).min(BINS - 1);
    let mut bin_bounds = [Aabb::EMPTY; BINS];
    let mut bin_counts = [0usize; BINS];
    for it in &items[start..end] {
        let b = bin_of(it.centroid);
        bin_bounds[b] = bin_bounds[b].union(it.bounds);
        bin_counts[b] += 1;
    }
    // Sweep from the right to get each suffix's area and count, then from the left.
    let mut right_cost = [0.0f64; BINS];
    let (mut acc, mut n) = (Aabb::EMPTY, 0usize);
    for b in (1..BINS).rev() {
        acc = acc.union(bin_bounds[b]);
        n += bin_counts[b];
        right_cost[b] = if n > 0 { acc.half_area() * n as f64 } else { 0.0 };
    }
    let (mut best, mut best_split) = (f64::INFINITY, 0usize);
    let (mut acc, mut n) = (Aabb::EMPTY, 0usize);
    for b in 0..BINS - 1 {
        acc = acc.union(bin_bounds[b]);
        n += bin_counts[b];
        if n == 0 || n == count {
            continue;
        }
        let cost = acc.half_area() * n as f64 + right_cost[b + 1];
        if cost < best {
            best = cost;
            best_split = b + 1;
        }
    }
    let leaf_cost = bounds.half_area() * count as f64;
    let split_cost = TRAVERSAL_COST * bounds.half_area() + best;
    if best_split == 0 || (split_cost >= leaf_cost && count <= 4 * LEAF_SIZE) {
        nodes[index] = leaf;
        return;
    }
    // Partition in place by bin.
    let (mut i, mut j) = (start, end);
    while i < j {
        if bin_of(items[i].centroid) < best_split {
            i += 1;
        } else {
            j -= 1;
            items.swap(i, j);
        }
    }
    let mid = i;
    let first = nodes.len();
    nodes.push(leaf);
    nodes.push(leaf);
    nodes[index] = Node { bounds, first: first as u32, count: 0 };
    build_node(nodes, first, items, start, mid, depth + 1);
    build_node(nodes, first + 1, items, mid, end, depth + 1);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pseudo-random soup of small triangles.
    fn soup(n: usize) -> Vec<[DVec3; 3]> {
        let mut s = 0x1234_5678_9abc_def0u64;
        let mut r = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| {
                let c = DVec3::new(r(), r(), r()) * 10.0 - 5.0;
                let e = |r: &mut dyn FnMut() -> f64| DVec3::new(r(), r(), r()) - 0.5;
                [c, c + e(&mut r), c + e(&mut r)]
            })
            .collect()
    }

    #[test]
    fn closest_hit_matches_brute_force() {
        let tris = soup(2000);
        let bvh = Bvh::build(tris.clone());
        let brute: Vec<Triangle> = tris.iter().map(|[a, b, c]| Triangle { v0: *a, e1: *b - *a, e2: *c - *a }).collect();
        let mut hits = 0;
        for k in 0..500 {
            let f = k as f64;
            let o = DVec3::new((f * 0.37).sin() * 8.0, (f * 0.11).cos() * 8.0, 7.0);
            let d = (DVec3::new((f * 0.23).cos(), (f * 0.71).sin(), -3.0)).normalize();
            let want = brute.iter().filter_map(|t| t.intersect(o, d, 0.0, f64::INFINITY)).fold(f64::INFINITY, f64::min);
            let got = bvh.closest(o, d, 0.0, f64::INFINITY).map_or(f64::INFINITY, |h| h.t);
            assert_eq!(want, got, "ray {k}");
            assert_eq!(want.is_finite(), bvh.occluded(o, d, 0.0, f64::INFINITY), "ray {k}");
            hits += want.is_finite() as usize;
        }
        assert!(hits > 50, "the test must hit something: {hits}");
    }
}
