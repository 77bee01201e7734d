//! A small bounding-volume hierarchy over triangles for the reference ray tracer:
//! median split on the longest centroid axis, leaves of at most 4 triangles, flattened
//! depth-first so a node's left child follows it. Tested against brute force.

use glam::Vec3;

/// One triangle's vertices.
pub type Tri = [Vec3; 3];

#[derive(Clone, Copy, Debug)]
struct Node {
    min: Vec3,
    max: Vec3,
    /// Leaf: first triangle index; inner: index of the right child.
    start_or_right: u32,
    /// Leaf: triangle count (> 0); inner: 0.
    count: u32,
}

/// The hierarchy, owning its (reordered) triangles.
#[derive(Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    tris: Vec<Tri>,
    /// Each reordered triangle's index in the list given to [`Bvh::new`].
    ids: Vec<u32>,
}

const LEAF: usize = 4;

fn bounds<'a>(tris: impl Iterator<Item = &'a Tri>) -> (Vec3, Vec3) {
    tris.flatten().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(a, b), p| (a.min(*p), b.max(*p)),
    )
}

fn centroid(t: &Tri) -> Vec3 {
    (t[0] + t[1] + t[2]) / 3.0
}

impl Bvh {
    /// Builds over `tris` (degenerate triangles are kept; they are never hit).
    pub fn new(tris: Vec<Tri>) -> Self {
        let mut nodes = Vec::with_capacity(2 * tris.len() / LEAF + 1);
        let mut items: Vec<(Tri, u32)> = tris.into_iter().zip(0..).collect();
        if !items.is_empty() {
            let n = items.len();
            build(&mut nodes, &mut items, 0, n);
        }
        let (tris, ids) = items.into_iter().unzip();
        Bvh { nodes, tris, ids }
    }

    /// The index, in the list given to [`Bvh::new`], of triangle `i` as numbered by
    /// [`Bvh::closest`].
    pub fn original_index(&self, i: u32) -> u32 {
        self.ids[i as usize]
    }

    /// Triangle count.
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// True when there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// Geometric (unnormalized) normal of triangle `i` as numbered by [`Bvh::closest`].
    pub fn normal(&self, i: u32) -> Vec3 {
        let t = &self.tris[i as usize];
        (t[1] - t[0]).cross(t[2] - t[0])
    }

    /// Distance to the closest hit along `dir` (any length) within `(0, t_max)`, and the
    /// hit triangle's index, if any.
    pub fn closest(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<(f32, u32)> {
        if self.nodes.is_empty() {
            return None;
        }
        let inv = dir.recip();
        let mut best = t_max;
        let mut hit = None;
        // Depth is bounded by the median split: log2(n / LEAF) + 1 < 64 for any real mesh.
        let mut stack = [0u32; 64];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let idx = stack[sp] as usize;
            let node = self.nodes[idx];
            if !slab(node.min, node.max, origin, inv, best) {
                continue;
            }
            if node.count > 0 {
                let s = node.start_or_right as usize;
                for (k, t) in self.tris[s..s + node.count as usize].iter().enumerate() {
                    if let Some(d) = intersect(t, origin, dir) {
                        if d < best {
                            best = d;
                            hit = Some((s + k) as u32);
                        }
                    }
                }
            } else {
                stack[sp] = node.start_or_right;
                stack[sp + 1] = idx as u32 + 1;
                sp += 2;
            }
        }
        hit.map(|i| (best, i))
    }
}

/// Builds the subtree over `tris[first..first + count]`; returns its root's index. The
/// left child of an inner node is the next node; the right child's index is stored.
fn build(nodes: &mut Vec<Node>, tris: &mut [(Tri, u32)], first: usize, count: usize) -> u32 {
    let idx = nodes.len();
    let (min, max) = bounds(tris[first..first + count].iter().map(|t| &t.0));
    nodes.push(Node {
        min,
        max,
        start_or_right: first as u32,
        count: count as u32,
    });
    if count <= LEAF {
        return idx as u32;
    }
    let slice = &mut tris[first..first + count];
    let (cmin, cmax) = slice.iter().map(|t| centroid(&t.0)).fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(a, b), c| (a.min(c), b.max(c)),
    );
    let ext = cmax - cmin;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let mid = count / 2;
    slice.select_nth_unstable_by(mid, |a, b| {
        centroid(&a.0)[axis].total_cmp(&centroid(&b.0)[axis])
    });
    build(nodes, tris, first, mid);
    let right = build(nodes, tris, first + mid, count - mid);
    nodes[idx].start_or_right = right;
    nodes[idx].count = 0;
    idx as u32
}

/// Ray/box slab test within `(0, t_max)`.
fn slab(min: Vec3, max: Vec3, o: Vec3, inv: Vec3, t_max: f32) -> bool {
    let t0 = (min - o) * inv;
    let t1 = (max - o) * inv;
    let tmin = t0.min(t1).max_element().max(0.0);
    let tmax = t0.max(t1).min_element().min(t_max);
    tmin <= tmax
}

/// Möller–Trumbore; double-sided; `Some(t)` for t > 0.
pub fn intersect(t: &Tri, o: Vec3, d: Vec3) -> Option<f32> {
    let e1 = t[1] - t[0];
    let e2 = t[2] - t[0];
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - t[0];
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let dist = e2.dot(q) * inv;
    (dist > 0.0).then_some(dist)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_hit_matches_brute_force() {
        // A deterministic cloud of small triangles.
        let mut state = 7u64;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) as f32 / (1u64 << 31) as f32) * 2.0 - 1.0
        };
        let tris: Vec<Tri> = (0..500)
            .map(|_| {
                let c = Vec3::new(rnd(), rnd(), rnd()) * 5.0;
                [
                    c,
                    c + Vec3::new(rnd(), rnd(), rnd()),
                    c + Vec3::new(rnd(), rnd(), rnd()),
                ]
            })
            .collect();
        let bvh = Bvh::new(tris.clone());
        assert_eq!(bvh.len(), 500);
        for _ in 0..2000 {
            let o = Vec3::new(rnd(), rnd(), rnd()) * 6.0;
            let d = Vec3::new(rnd(), rnd(), rnd()).normalize_or(Vec3::X);
            let brute = tris
                .iter()
                .filter_map(|t| intersect(t, o, d))
                .filter(|&t| t < 4.0)
                .fold(None, |m: Option<f32>, t| Some(m.map_or(t, |m| m.min(t))));
            let got = bvh.closest(o, d, 4.0);
            assert_eq!(got.map(|h| h.0), brute);
            // The hit triangle is found again in the input list by its original index.
            if let Some((t, i)) = got {
                let original = &tris[bvh.original_index(i) as usize];
                assert_eq!(intersect(original, o, d), Some(t));
            }
        }
    }
}
