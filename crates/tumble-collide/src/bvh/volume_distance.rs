//! Branch-and-bound distance from one OBBTree to a convex query volume (a
//! primitive shape): the single-tree form of [`super::traverse::distance_with`]
//! (PQP's `DistanceRecurse` with one side fixed). The caller supplies the
//! lower bound of a node box's distance to the volume, in the mesh frame, and
//! the exact distance of a triangle; children are visited nearest-first and
//! pruned with the same PQP-style [`DistanceTolerance`].

use super::build::ObbTree;
use super::node::Node;
use super::stack::SmallStack;
use super::traverse::{check_nonneg, DistanceResult, DistanceTolerance, TraversalError, TraversalStats};

/// Smallest value of `on_tri(t, best)` over the triangles of `tree`, pruning
/// every node whose `node_lower_bound` (m, a lower bound on the distance from
/// anything inside the node's stored box to the volume) cannot beat the best
/// so far by more than `tolerance`. `on_tri` must return the distance of
/// triangle `t` (or any value not below it when it can tell that `t` cannot
/// win against `best`). Starts from `upper_bound` (m); stops at 0.
pub fn volume_distance(
    tree: &ObbTree,
    upper_bound: f64,
    tolerance: &DistanceTolerance,
    node_lower_bound: impl Fn(&Node) -> f64,
    mut on_tri: impl FnMut(u32, f64) -> f64,
) -> Result<DistanceResult, TraversalError> {
    check_nonneg("distance upper bound", upper_bound)?;
    tolerance.check()?;
    let tol = *tolerance;
    let nodes = tree.nodes();
    let mut best = upper_bound;
    let mut stats = TraversalStats {
        bv_tests: 1,
        ..TraversalStats::default()
    };
    if nodes.is_empty() {
        return Ok(DistanceResult {
            distance: best,
            stats,
        });
    }
    let mut stack = SmallStack::<(u32, f64)>::new();
    let lb = node_lower_bound(&nodes[0]);
    if !tol.prunes(lb, best) {
        stack.push((0, lb));
    }
    while let Some((i, lb)) = stack.pop() {
        if tol.prunes(lb, best) {
            continue;
        }
        let n = &nodes[i as usize];
        if n.is_leaf() {
            // The one-tree form of `traverse::distance_with`'s leaf step (one
            // triangle per call instead of a pair): each hot loop folds into
            // its own `best` inline rather than through a shared callback.
            stats.leaf_pairs += 1;
            for &t in tree.leaf_triangles(n) {
                stats.triangle_pairs += 1;
                let d = on_tri(t, best);
                if d < best {
                    best = d;
                }
            }
            if best <= 0.0 {
                stats.stopped = true;
                break;
            }
            continue;
        }
        let c = n.first_child();
        let lbs = [
            node_lower_bound(&nodes[c as usize]),
            node_lower_bound(&nodes[c as usize + 1]),
        ];
        stats.bv_tests += 2;
        let order = if lbs[0] <= lbs[1] { [1, 0] } else { [0, 1] };
        for k in order {
            if !tol.prunes(lbs[k], best) {
                stack.push((c + k as u32, lbs[k]));
            }
        }
    }
    Ok(DistanceResult {
        distance: best,
        stats,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::traverse::tests::rng;
    use crate::math::DVec3;
    use crate::mesh::torus_mesh;

    // Opens like the tests of bvh/query.rs (a torus, its tree, a seeded rng):
    // three setup lines per test, not worth a fixture that would tie the
    // modules' meshes and seeds together.
    #[test]
    fn point_distance_matches_brute_force_over_vertices() {
        // Volume = a point; triangle "distance" = nearest vertex, never below
        // the true triangle distance, so box pruning keeps the exact minimum.
        let m = torus_mesh(1.0, 0.3, 20, 10).unwrap();
        let t = ObbTree::build(&m).unwrap();
        let mut r = rng(5);
        for _ in 0..40 {
            let p = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 6.0;
            let brute = m
                .vertices()
                .iter()
                .map(|v| (*v - p).length())
                .fold(f64::INFINITY, f64::min);
            let lb = |n: &Node| {
                let u = n.axes_f64().transpose() * (p - n.center_f64());
                (u.abs() - DVec3::from_array(n.half_f64()))
                    .max(DVec3::ZERO)
                    .length()
            };
            let near = |i: u32, _| {
                m.triangle(i as usize)
                    .iter()
                    .map(|v| (*v - p).length())
                    .fold(f64::INFINITY, f64::min)
            };
            let exact = volume_distance(&t, f64::INFINITY, &DistanceTolerance::EXACT, lb, near).unwrap();
            assert_eq!(exact.distance, brute);
            let tol = DistanceTolerance {
                rel_err: 0.5,
                abs_err: 0.0,
            };
            let approx = volume_distance(&t, f64::INFINITY, &tol, lb, near).unwrap();
            assert!(approx.distance >= brute && approx.distance <= 1.5 * brute + 1e-12);
            assert!(approx.stats.triangle_pairs <= exact.stats.triangle_pairs);
        }
        let bad = DistanceTolerance {
            rel_err: -1.0,
            abs_err: 0.0,
        };
        assert!(volume_distance(&t, f64::INFINITY, &bad, |_| 0.0, |_, _| 0.0).is_err());
        assert!(volume_distance(&t, f64::NAN, &DistanceTolerance::EXACT, |_| 0.0, |_, _| 0.0).is_err());
    }
}
