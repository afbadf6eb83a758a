//! Top-down OBBTree construction (Gottschalk, Lin & Manocha 1996, section 4;
//! thesis 4.6 and 5.1) and the tree's statistics.
//!
//! Each node's box is fitted to its triangles ([`super::fit`]), then the
//! triangles are split by the plane through the mean of their centroids,
//! orthogonal to the box's longest axis. A lopsided split (one side below
//! [`LOPSIDED_FRACTION`] of the triangles, or empty: e.g. many triangles with
//! one centroid) tries the other axes; when all three are lopsided a median
//! split is used, so every internal node has two non-empty children, the
//! depth stays logarithmic and the build always terminates.
//! Nodes with at most `leaf_size` triangles become leaves (thesis 5.4.2: a
//! leaf per triangle wastes memory and box tests on tiny boxes).

use super::fit::{fit_axes, AxesSource};
use super::node::{Node, MAX_LEAF_SIZE, MAX_TRIANGLES};
use super::obb::Obb;
use crate::math::DVec3;
use crate::mesh::TriMesh;

/// Construction settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BuildOptions {
    /// Most triangles in one leaf, 1..=7. Default 2: on the thesis' torus
    /// pair (200 poses, `benches/bvh_tori.rs`) BV tests + triangle pairs sum
    /// to 695k / 618k / 631k / 668k for leaf sizes 1 / 2 / 3 / 4, and 2 needs
    /// 59 bytes per triangle against 92 for 1 (4 needs 32).
    pub leaf_size: usize,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions { leaf_size: 2 }
    }
}

/// Why a tree could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BvhError {
    /// `leaf_size` outside 1..=7.
    #[error("OBBTree leaf_size must be in 1..={max}, got {value}")]
    BadLeafSize {
        /// The value given.
        value: usize,
        /// Largest accepted value.
        max: usize,
    },
    /// A vertex lies farther from the mesh's origin than [`MAX_COORDINATE`]
    /// along some axis: the tree's f32 boxes (and the squares taken when
    /// fitting them) would overflow, and a query could miss a contact.
    #[error("OBBTree supports vertex coordinates up to {max:e} m, vertex {vertex} has {value:e}")]
    CoordinateTooLarge {
        /// Index of the vertex.
        vertex: usize,
        /// Its largest coordinate (absolute value, m).
        value: f64,
        /// [`MAX_COORDINATE`].
        max: f64,
    },
    /// The mesh has more triangles than a node link can address.
    #[error("OBBTree supports at most {max} triangles, mesh has {count}")]
    TooManyTriangles {
        /// Triangles in the mesh.
        count: usize,
        /// The limit (2^28).
        max: usize,
    },
}

/// Size and shape of a built tree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreeStats {
    /// Nodes in total (internal + leaves).
    pub nodes: usize,
    /// Leaf nodes.
    pub leaves: usize,
    /// Levels on the longest root-to-leaf path (a lone root leaf has depth 1).
    pub depth: usize,
    /// Triangles indexed.
    pub triangles: usize,
    /// Nodes whose axes came from the node's triangles because the hull was flat.
    pub flat_fallbacks: usize,
    /// Nodes with the identity frame because everything was degenerate.
    pub identity_fallbacks: usize,
    /// Heap + inline bytes of the tree (nodes and triangle index array).
    pub memory_bytes: usize,
    /// `memory_bytes / triangles`.
    pub bytes_per_triangle: f64,
}

/// An OBBTree over one mesh. It stores triangle indices, not the mesh: queries
/// hand triangle indices to callbacks, which look the triangles up themselves.
#[derive(Debug, Clone)]
pub struct ObbTree {
    nodes: Vec<Node>,
    tris: Vec<u32>,
    depth: usize,
    leaves: usize,
    flat_fallbacks: usize,
    identity_fallbacks: usize,
    /// Every leaf box lies within this of the root box's centre (m): the
    /// largest distance of a leaf's centre from it plus the leaf's half
    /// diagonal.
    leaf_reach: f64,
}

/// Largest vertex coordinate (absolute, m, in the mesh's own frame) an
/// OBBTree accepts. Boxes are stored in f32 (largest finite value 3.4e38) and
/// the separating-axis tests add a few extents together; below 1e36 none of
/// that overflows. Beyond f32's range a box became infinite and the walk
/// skipped real contacts (found by fuzzing with 1.8e308 m vertices).
pub const MAX_COORDINATE: f64 = 1e36;

impl ObbTree {
    /// Builds with [`BuildOptions::default`].
    pub fn build(mesh: &TriMesh) -> Result<ObbTree, BvhError> {
        Self::build_with(mesh, &BuildOptions::default())
    }

    /// Builds with explicit options.
    pub fn build_with(mesh: &TriMesh, options: &BuildOptions) -> Result<ObbTree, BvhError> {
        let leaf_size = options.leaf_size;
        if !(1..=MAX_LEAF_SIZE).contains(&leaf_size) {
            return Err(BvhError::BadLeafSize {
                value: leaf_size,
                max: MAX_LEAF_SIZE,
            });
        }
        if let Some((vertex, value)) = mesh
            .vertices()
            .iter()
            .map(|v| v.abs().max_element())
            .enumerate()
            .find(|&(_, c)| c > MAX_COORDINATE)
        {
            return Err(BvhError::CoordinateTooLarge {
                vertex,
                value,
                max: MAX_COORDINATE,
            });
        }
        let n = mesh.triangles().len();
        if n >= MAX_TRIANGLES {
            return Err(BvhError::TooManyTriangles {
                count: n,
                max: MAX_TRIANGLES - 1,
            });
        }
        let centroids: Vec<DVec3> = (0..n)
            .map(|t| {
                let [a, b, c] = mesh.triangle(t);
                (a + b + c) / 3.0
            })
            .collect();
        let mut tree = ObbTree {
            nodes: Vec::with_capacity(2 * n.div_ceil(leaf_size)),
            tris: (0..n as u32).collect(),
            depth: 0,
            leaves: 0,
            flat_fallbacks: 0,
            identity_fallbacks: 0,
            leaf_reach: 0.0,
        };
        let mut mark = vec![u32::MAX; mesh.vertices().len()];
        let mut points: Vec<DVec3> = Vec::new();
        let mut keyed: Vec<(f64, u32)> = Vec::new();
        // (node, start, end, depth)
        let mut work: Vec<(usize, usize, usize, usize)> = vec![(0, 0, n, 1)];
        tree.nodes.push(Node::default());
        while let Some((id, start, end, depth)) = work.pop() {
            tree.depth = tree.depth.max(depth);
            // Distinct vertices of this node's triangles.
            points.clear();
            for &t in &tree.tris[start..end] {
                for v in mesh.triangles()[t as usize] {
                    if mark[v as usize] != id as u32 {
                        mark[v as usize] = id as u32;
                        points.push(mesh.vertices()[v as usize]);
                    }
                }
            }
            let (axes, source) = fit_axes(
                &points,
                tree.tris[start..end].iter().map(|&t| mesh.triangle(t as usize)),
            );
            match source {
                AxesSource::Hull => {}
                AxesSource::Triangles => tree.flat_fallbacks += 1,
                AxesSource::Identity => tree.identity_fallbacks += 1,
            }
            let obb = Obb::fit_points(axes, points.iter().copied())
                .expect("a node always has at least one triangle");
            let mut node = Node::conservative(&obb, points.iter().copied());
            let count = end - start;
            if count <= leaf_size {
                node.link = Node::leaf_link(start, count);
                tree.nodes[id] = node;
                tree.leaves += 1;
                continue;
            }
            let mid = split(&mut tree.tris[start..end], &centroids, &obb, &mut keyed) + start;
            let left = tree.nodes.len();
            node.link = left as u32;
            tree.nodes[id] = node;
            tree.nodes.push(Node::default());
            tree.nodes.push(Node::default());
            // Right pushed first so the left subtree is built (and laid out) first.
            work.push((left + 1, mid, end, depth + 1));
            work.push((left, start, mid, depth + 1));
        }
        let root = tree.nodes[0].center_f64();
        tree.leaf_reach = tree
            .nodes
            .iter()
            .filter(|n| n.is_leaf())
            .map(|n| (n.center_f64() - root).length() + DVec3::from(n.half_f64()).length())
            .fold(0.0, f64::max);
        Ok(tree)
    }

    /// A radius about the root box's centre (m) that holds every leaf box
    /// whole: a point of any leaf box is at most this far from it, so a
    /// rigid motion's reach over this ball bounds every leaf's.
    pub fn leaf_reach(&self) -> f64 {
        self.leaf_reach
    }

    /// All nodes; the root is `nodes()[0]`.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The triangle index array that leaves point into.
    pub fn triangle_indices(&self) -> &[u32] {
        &self.tris
    }

    /// Mesh triangle indices held by a leaf (empty for an internal node).
    #[inline]
    pub fn leaf_triangles(&self, node: &Node) -> &[u32] {
        if !node.is_leaf() {
            return &[];
        }
        let (s, c) = node.leaf_range();
        &self.tris[s as usize..(s + c) as usize]
    }

    /// Bytes used by the tree (nodes + triangle indices + the struct itself).
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.nodes.len() * std::mem::size_of::<Node>()
            + self.tris.len() * std::mem::size_of::<u32>()
    }

    /// Size and shape statistics.
    pub fn stats(&self) -> TreeStats {
        let memory_bytes = self.memory_bytes();
        TreeStats {
            nodes: self.nodes.len(),
            leaves: self.leaves,
            depth: self.depth,
            triangles: self.tris.len(),
            flat_fallbacks: self.flat_fallbacks,
            identity_fallbacks: self.identity_fallbacks,
            memory_bytes,
            bytes_per_triangle: memory_bytes as f64 / self.tris.len().max(1) as f64,
        }
    }
}

/// A split leaving less than this fraction of the triangles on one side is
/// lopsided: the other axes are tried for a more even one.
pub const LOPSIDED_FRACTION: f64 = 0.1;

/// Reorders `tris` into two non-empty halves and returns the split index.
///
/// The mean split along the longest axis is taken unless it is lopsided
/// (a side below [`LOPSIDED_FRACTION`], or empty); then the other axes, by
/// extent, are tried. When every axis is lopsided the median split along the
/// longest axis is used, which bounds the depth by `log(n) / log(1 / 0.9)`
/// even for triangles spaced exponentially along a line.
fn split(tris: &mut [u32], centroids: &[DVec3], obb: &Obb, keyed: &mut Vec<(f64, u32)>) -> usize {
    let h = obb.half_extents;
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| h[j].total_cmp(&h[i]));
    let n = tris.len();
    let smaller = |i: usize| i.min(n - i);
    for &k in &order {
        let axis = obb.axes.col(k);
        let mean = tris.iter().map(|&t| axis.dot(centroids[t as usize])).sum::<f64>() / n as f64;
        let i = partition_below(tris, centroids, axis, mean);
        if i > 0 && smaller(i) as f64 >= LOPSIDED_FRACTION * n as f64 {
            return i;
        }
    }
    // Median split along the longest axis; ties broken by triangle index so
    // the result does not depend on the sort's internals.
    let axis = obb.axes.col(order[0]);
    keyed.clear();
    keyed.extend(tris.iter().map(|&t| (axis.dot(centroids[t as usize]), t)));
    keyed.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for (dst, &(_, t)) in tris.iter_mut().zip(keyed.iter()) {
        *dst = t;
    }
    tris.len() / 2
}

/// Moves the triangles whose centroid lies below `mean` along `axis` to the
/// front and returns how many there are.
fn partition_below(tris: &mut [u32], centroids: &[DVec3], axis: DVec3, mean: f64) -> usize {
    let mut i = 0;
    for j in 0..tris.len() {
        if axis.dot(centroids[tris[j] as usize]) < mean {
            tris.swap(i, j);
            i += 1;
        }
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{icosphere_mesh, torus_mesh};

    /// Walks the tree checking that every vertex of every triangle lies inside
    /// every ancestor's stored f32 box (no tolerance beyond the built-in pad),
    /// that each triangle is in exactly one leaf, and the leaf sizes.
    fn check_tree(mesh: &TriMesh, tree: &ObbTree, leaf_size: usize) {
        let nodes = tree.nodes();
        let mut seen = vec![0u32; mesh.triangles().len()];
        let mut stack = vec![(0usize, Vec::<usize>::new())];
        let mut leaves = 0;
        let mut depth = 0;
        while let Some((id, mut ancestors)) = stack.pop() {
            ancestors.push(id);
            depth = depth.max(ancestors.len());
            let node = &nodes[id];
            if node.is_leaf() {
                leaves += 1;
                let tris = tree.leaf_triangles(node);
                assert!(!tris.is_empty() && tris.len() <= leaf_size);
                for &t in tris {
                    seen[t as usize] += 1;
                    for v in mesh.triangle(t as usize) {
                        for &a in &ancestors {
                            assert!(
                                nodes[a].contains(v),
                                "vertex {v} of triangle {t} outside node {a}"
                            );
                        }
                    }
                }
            } else {
                let c = node.first_child() as usize;
                assert!(c > id && c + 1 < nodes.len());
                stack.push((c, ancestors.clone()));
                stack.push((c + 1, ancestors));
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
        let st = tree.stats();
        assert_eq!(st.leaves, leaves);
        assert_eq!(st.nodes, 2 * leaves - 1);
        assert_eq!(st.depth, depth);
        assert_eq!(st.triangles, mesh.triangles().len());
    }

    #[test]
    fn torus_tree_contains_its_triangles() {
        let mesh = torus_mesh(1.0, 0.3, 30, 20).unwrap();
        for leaf_size in [1, 2, 4, 7] {
            let tree = ObbTree::build_with(&mesh, &BuildOptions { leaf_size }).unwrap();
            check_tree(&mesh, &tree, leaf_size);
            let st = tree.stats();
            // A balanced-ish tree: depth within a small factor of log2(leaves).
            assert!(
                st.depth <= 4 * (st.leaves as f64).log2().ceil() as usize + 2,
                "{st:?}"
            );
        }
    }

    #[test]
    fn far_from_origin_mesh_is_contained() {
        let mesh = icosphere_mesh(0.01, 3)
            .unwrap()
            .map_vertices(|v| v + DVec3::new(5000.0, -3000.0, 700.0))
            .unwrap();
        let tree = ObbTree::build(&mesh).unwrap();
        check_tree(&mesh, &tree, 2);
    }

    #[test]
    fn flat_and_duplicate_triangles_build() {
        // A flat grid (every hull degenerate) plus triangles repeated 5 times
        // (identical centroids force the median split).
        let mut v = Vec::new();
        let mut t = Vec::new();
        for i in 0..6 {
            for j in 0..6 {
                v.push(DVec3::new(i as f64, j as f64, 0.0));
            }
        }
        for i in 0..5u32 {
            for j in 0..5u32 {
                let a = i * 6 + j;
                t.push([a, a + 6, a + 7]);
                t.push([a, a + 7, a + 1]);
            }
        }
        for _ in 0..5 {
            t.push([0, 6, 7]);
        }
        let mesh = TriMesh::new(v, t).unwrap();
        let tree = ObbTree::build_with(&mesh, &BuildOptions { leaf_size: 1 }).unwrap();
        check_tree(&mesh, &tree, 1);
        assert!(tree.stats().flat_fallbacks > 0);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(32))]
        /// Random triangle soups, with vertices snapped to a coarse grid so
        /// that duplicate points, coplanar sets and zero-area triangles are
        /// common: the tree must still contain every triangle.
        #[test]
        fn random_soups_are_contained(seed in 0u64..u64::MAX, n in 1usize..120, leaf_size in 1usize..=7, snap in proptest::bool::ANY) {
            let mut r = crate::bvh::traverse::tests::rng(seed);
            let mut v = Vec::new();
            for _ in 0..3 * n {
                let mut p = DVec3::new(r(), r(), r()) * 4.0 - DVec3::splat(2.0);
                if snap {
                    p = (p * 2.0).round() * 0.5;
                }
                v.push(p);
            }
            let t: Vec<[u32; 3]> = (0..n as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
            let mesh = TriMesh::new(v, t).unwrap();
            let tree = ObbTree::build_with(&mesh, &BuildOptions { leaf_size }).unwrap();
            check_tree(&mesh, &tree, leaf_size);
        }
    }

    /// Triangles spaced exponentially along x: every mean split along x
    /// cuts off the farthest one (a chain of depth n without the lopsided
    /// rule); the tree must stay logarithmic and contain every triangle.
    #[test]
    fn exponentially_spaced_triangles_give_a_shallow_tree() {
        // 4^59 = 3e35 stays inside the f32 range of the stored boxes.
        let n = 60;
        let mut v = Vec::new();
        let mut t = Vec::new();
        for k in 0..n as u32 {
            let x = 4f64.powi(k as i32);
            v.extend([
                DVec3::new(x, 0.0, 0.0),
                DVec3::new(x, 0.1, 0.0),
                DVec3::new(x, 0.0, 0.1),
            ]);
            t.push([3 * k, 3 * k + 1, 3 * k + 2]);
        }
        let mesh = TriMesh::new(v, t).unwrap();
        let tree = ObbTree::build_with(&mesh, &BuildOptions { leaf_size: 1 }).unwrap();
        check_tree(&mesh, &tree, 1);
        // Balanced: log2(60) = 5.9 levels; peeling ~3 per level: about 20.
        let bound = 3 * (n as f64).log2().ceil() as usize;
        assert!(tree.stats().depth <= bound, "{:?} (bound {bound})", tree.stats());
    }

    #[test]
    fn bad_options_are_errors() {
        let mesh = icosphere_mesh(1.0, 0).unwrap();
        for leaf_size in [0, 8] {
            assert_eq!(
                ObbTree::build_with(&mesh, &BuildOptions { leaf_size }).unwrap_err(),
                BvhError::BadLeafSize {
                    value: leaf_size,
                    max: 7
                }
            );
        }
    }

    #[test]
    fn build_is_deterministic() {
        let mesh = torus_mesh(1.0, 0.4, 17, 9).unwrap();
        let a = ObbTree::build(&mesh).unwrap();
        let b = ObbTree::build(&mesh).unwrap();
        assert_eq!(a.nodes(), b.nodes());
        assert_eq!(a.triangle_indices(), b.triangle_indices());
    }
}
