//! Contact reduction: which points of a contact patch to keep when there
//! are many. A patch is the set of contacts of one shape pair whose normals
//! agree; the solver needs only the points that span its support region
//! (the normal forces of any points inside their convex hull can be carried
//! by its corners) and its deepest point, which drives the push-out. Four
//! points chosen by area as in Bullet's and Jolt's manifold reduction, then,
//! for curved or long patches, the points that grow their hull the most,
//! so that the solver's work follows the contact area and not the number
//! of triangles that touch (issue 15: two lumpy meshes make thousands).

use crate::math::{first_max, DVec3};

/// Most points one patch keeps ([`reduce_patch`]).
pub const PATCH_MAX_POINTS: usize = 8;

/// Chooses at most 4 of `n` points (position, distance) that keep the
/// manifold's support area: the deepest point (see the tie rule inside), the point farthest from it,
/// the point making the largest triangle with those two, and the point
/// farthest outside that triangle (the usual heuristic of Bullet's and Jolt's
/// contact reduction). Returns indices in increasing order and how many.
pub fn reduce_to_four(n: usize, normal: DVec3, get: impl Fn(usize) -> (DVec3, f64)) -> ([usize; 4], usize) {
    let mut keep = [0usize; 4];
    if n <= 4 {
        for (i, k) in keep.iter_mut().enumerate().take(n) {
            *k = i;
        }
        return (keep, n);
    }
    let argmax = |score: &dyn Fn(usize) -> f64| first_max(n, score);
    // Deepest point; depths equal within TIE x (manifold size) (a flat resting
    // face) are told apart by position along a fixed tangent, so that the
    // choice does not flip under round-off (feature ids must stay put for
    // warm starting). The kept depth is then within that tolerance of the
    // deepest.
    const TIE: f64 = 1e-5;
    let (deepest, _) = argmax(&|i| -get(i).1);
    let pd = get(deepest).0;
    let size = (0..n).map(|i| (get(i).0 - pd).length()).fold(0.0, f64::max);
    let dmin = get(deepest).1;
    let tangent = normal.any_orthonormal_vector();
    let (i0, _) = argmax(&|i| {
        if get(i).1 <= dmin + TIE * size {
            get(i).0.dot(tangent)
        } else {
            f64::NEG_INFINITY
        }
    });
    let p0 = get(i0).0;
    let (i1, _) = argmax(&|i| (get(i).0 - p0).length_squared());
    let p1 = get(i1).0;
    let area = |a: DVec3, b: DVec3, c: DVec3| (b - a).cross(c - a).dot(normal);
    let (i2, _) = argmax(&|i| area(p0, p1, get(i).0).abs());
    let p2 = get(i2).0;
    let sign = area(p0, p1, p2).signum();
    let (i3, s3) = argmax(&|i| {
        let q = get(i).0;
        let o = -sign * area(p0, p1, q);
        o.max(-sign * area(p1, p2, q)).max(-sign * area(p2, p0, q))
    });
    keep = [i0, i1, i2, i3];
    let mut count = if s3 > 0.0 { 4 } else { 3 };
    keep[..count].sort_unstable();
    // Drop duplicates (degenerate input: all points coincide or are collinear).
    let mut m = 1;
    for k in 1..count {
        if keep[k] != keep[m - 1] {
            keep[m] = keep[k];
            m += 1;
        }
    }
    count = m;
    (keep, count)
}

/// The convex hull of `points` (x, y) in counter-clockwise order, into
/// `hull` (Andrew's monotone chain; collinear points dropped).
fn convex_hull_2d(points: impl Iterator<Item = (f64, f64)>, hull: &mut Vec<(f64, f64)>) {
    let mut p: Vec<(f64, f64)> = points.collect();
    p.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    hull.clear();
    if p.len() < 3 {
        hull.extend(p);
        return;
    }
    for pass in 0..2 {
        let start = hull.len();
        for k in 0..p.len() {
            let q = if pass == 0 { p[k] } else { p[p.len() - 1 - k] };
            while hull.len() >= start + 2 && cross_2d(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0 {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
}

/// Twice the signed area of the triangle (o, a, b): positive when b lies
/// left of o -> a.
fn cross_2d(o: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
}

/// How far `q` lies outside the counter-clockwise convex polygon (its
/// largest distance beyond an edge line; <= 0 inside). A polygon of one
/// or two points is a point or a segment: the distance from it.
fn outside(polygon: &[(f64, f64)], q: (f64, f64)) -> f64 {
    match polygon.len() {
        0 => f64::INFINITY,
        1 => ((q.0 - polygon[0].0).powi(2) + (q.1 - polygon[0].1).powi(2)).sqrt(),
        _ => (0..polygon.len())
            .map(|k| {
                let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
                let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
                if polygon.len() == 2 {
                    cross_2d(a, b, q).abs() / len
                } else {
                    -cross_2d(a, b, q) / len
                }
            })
            .fold(f64::NEG_INFINITY, f64::max),
    }
}

/// Points of a patch within this of its deepest (m) are the ones it rests
/// on ([`reduce_patch`]); the rest are speculative contacts further away.
pub const PATCH_DEPTH_BAND: f64 = 0.002;

/// A choice that starts from the points kept last step stands while its
/// kept polygon spans at least this fraction of the area a fresh choice
/// spans ([`reduce_patch`]).
pub const KEEP_AREA_FRACTION: f64 = 0.9;

/// Points kept last step stand for the patch's deepest while they are
/// within this of it (m); else the deepest joins them ([`reduce_patch`]).
pub const KEEP_DEPTH_SLACK: f64 = 0.0002;

/// Chooses at most `max` (>= 4) of a patch's `n` points (position, and
/// distance or gap, m) and writes their indices, in increasing order, to
/// `keep`: all of them when `n <= max`. Else the points within
/// [`PATCH_DEPTH_BAND`] of the deepest, and every point of negative gap,
/// are the patch's support: the four of
/// [`reduce_to_four`] among them (the deepest and three that span the
/// largest area across `normal`), then one at a time the support point
/// farthest outside the kept points' convex hull (ties to the lower index)
/// while one lies outside, which brings the kept hull close to the whole
/// support polygon; when the support has fewer than `max`,
/// the deepest of the other points fill up. Choosing by spread alone would
/// keep shallow speculative points at the rim and leave the body resting
/// on its one deepest point.
///
/// `prior(i)` says that point `i` was kept last step (same features, about
/// the same place). Where a support has many nearly equal candidates (the
/// ring of vertices a torus rests on, a flat face on a fine mesh), a fresh
/// choice flips between neighbours from step to step as the body rocks by
/// microns: the support polygon turns, the points lose their warm-started
/// impulses, and the body rocks on. So the support points kept last step
/// stay (with the deepest point when they are more than
/// [`KEEP_DEPTH_SLACK`] shallower than it, and grown by the hull rule while
/// there is room) as long as their polygon spans at least
/// [`KEEP_AREA_FRACTION`] of the fresh choice's; Bullet's persistent
/// manifolds keep their points for the same reason. Every choice is
/// geometric and the input order decides ties: the result is a function
/// of the points and the prior flags. A support along a line (no area)
/// is always chosen afresh.
pub fn reduce_patch(
    n: usize,
    normal: DVec3,
    max: usize,
    get: impl Fn(usize) -> (DVec3, f64),
    prior: impl Fn(usize) -> bool,
    keep: &mut Vec<usize>,
) {
    keep.clear();
    let max = max.max(4);
    if n <= max {
        keep.extend(0..n);
        return;
    }
    let points: Vec<(DVec3, f64)> = (0..n).map(get).collect();
    let deepest = points.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let level = (deepest + PATCH_DEPTH_BAND).max(0.0);
    let support: Vec<usize> = (0..n).filter(|&i| points[i].1 <= level).collect();
    if support.len() <= max {
        // The others, NaN gaps included (ordered by `total_cmp`, which
        // puts a positive NaN last): a patch keeps points whatever its
        // gaps (an empty patch has no normal).
        let mut rest: Vec<usize> = (0..n)
            .filter(|&i| points[i].1.is_nan() || points[i].1 > level)
            .collect();
        rest.sort_by(|&x, &y| points[x].1.total_cmp(&points[y].1).then(x.cmp(&y)));
        keep.extend_from_slice(&support);
        keep.extend(rest.into_iter().take(max - support.len()));
        keep.sort_unstable();
        return;
    }
    // The support in the plane across the normal, in support order.
    let (t1, t2) = normal.any_orthonormal_pair();
    let flat: Vec<(f64, f64)> = support
        .iter()
        .map(|&i| (points[i].0.dot(t1), points[i].0.dot(t2)))
        .collect();
    let mut polygon = Vec::with_capacity(max);
    // A fresh choice, as positions in `support`.
    let (four, count) = reduce_to_four(support.len(), normal, |k| points[support[k]]);
    let mut fresh: Vec<usize> = four[..count].to_vec();
    grow_by_hull(&mut fresh, &flat, max, &mut polygon);
    // The points kept last step, if they still do the job.
    let mut kept: Vec<usize> = (0..support.len()).filter(|&k| prior(support[k])).collect();
    let chosen = 'chosen: {
        if kept.is_empty() {
            break 'chosen fresh;
        }
        if kept
            .iter()
            .all(|&k| points[support[k]].1 > deepest + KEEP_DEPTH_SLACK)
        {
            let (first_deepest, _) = first_max(support.len(), |k| -points[support[k]].1);
            kept.push(first_deepest);
        }
        if kept.len() > max {
            break 'chosen fresh;
        }
        grow_by_hull(&mut kept, &flat, max, &mut polygon);
        let area_kept = hull_area(kept.iter().map(|&k| flat[k]), &mut polygon);
        let area_fresh = hull_area(fresh.iter().map(|&k| flat[k]), &mut polygon);
        // A support along a line (a cylinder on its side) has no area to
        // compare, and the hull rule does not grow along the line: fresh.
        let (lo, hi) = flat.iter().fold(
            (
                (f64::INFINITY, f64::INFINITY),
                (f64::NEG_INFINITY, f64::NEG_INFINITY),
            ),
            |(lo, hi), p| ((lo.0.min(p.0), lo.1.min(p.1)), (hi.0.max(p.0), hi.1.max(p.1))),
        );
        let extent2 = (hi.0 - lo.0).powi(2) + (hi.1 - lo.1).powi(2);
        if area_fresh > 1e-6 * extent2 && area_kept >= KEEP_AREA_FRACTION * area_fresh {
            kept
        } else {
            fresh
        }
    };
    keep.extend(chosen.into_iter().map(|k| support[k]));
    keep.sort_unstable();
}

/// Adds to `keep` (positions in `flat`), one at a time while it has fewer
/// than `max`, the point farthest outside the kept points' convex hull,
/// while one lies outside (ties to the lower position): the hull's corners
/// carry the wrench.
fn grow_by_hull(keep: &mut Vec<usize>, flat: &[(f64, f64)], max: usize, polygon: &mut Vec<(f64, f64)>) {
    let mut edges: Vec<(f64, f64, f64)> = Vec::with_capacity(max);
    while keep.len() < max {
        convex_hull_2d(keep.iter().map(|&k| flat[k]), polygon);
        let mut best = None;
        let mut best_out = 0.0;
        if polygon.len() >= 3 {
            // Outward unit normals and offsets of the edges, once per round:
            // a point's distance outside is its largest edge distance.
            edges.clear();
            for k in 0..polygon.len() {
                let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
                let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
                let (nx, ny) = ((b.1 - a.1) / len, (a.0 - b.0) / len);
                edges.push((nx, ny, nx * a.0 + ny * a.1));
            }
            for (k, q) in flat.iter().enumerate() {
                if keep.contains(&k) {
                    continue; // on the hull already, whatever round-off says
                }
                let out = edges
                    .iter()
                    .map(|e| e.0 * q.0 + e.1 * q.1 - e.2)
                    .fold(f64::NEG_INFINITY, f64::max);
                if out > best_out {
                    best_out = out;
                    best = Some(k);
                }
            }
        } else {
            for (k, &q) in flat.iter().enumerate() {
                if keep.contains(&k) {
                    continue;
                }
                let out = outside(polygon, q);
                if out > best_out {
                    best_out = out;
                    best = Some(k);
                }
            }
        }
        let Some(k) = best else { break };
        keep.push(k);
    }
}

/// Area of the convex hull of `points` (m^2); `polygon` is scratch.
fn hull_area(points: impl Iterator<Item = (f64, f64)>, polygon: &mut Vec<(f64, f64)>) -> f64 {
    convex_hull_2d(points, polygon);
    let twice: f64 = (0..polygon.len())
        .map(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
            a.0 * b.1 - a.1 * b.0
        })
        .sum();
    0.5 * twice
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_testkit::{RandomSource, SplitMix64};

    fn reduce(points: &[(DVec3, f64)]) -> Vec<usize> {
        reduce_after(points, &[])
    }

    /// Twice the area of the convex hull of `p` (x, y): the support
    /// polygon a set of points spans.
    fn hull_area(p: Vec<(f64, f64)>) -> f64 {
        let mut hull = Vec::new();
        convex_hull_2d(p.into_iter(), &mut hull);
        (0..hull.len())
            .map(|i| {
                let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
                a.0 * b.1 - a.1 * b.0
            })
            .sum()
    }

    #[test]
    fn the_hull_of_a_square_with_inner_points_is_its_corners_counter_clockwise() {
        let mut points = vec![
            (0.5, 0.5),
            (1.0, 1.0),
            (0.0, 0.0),
            (0.2, 0.7),
            (1.0, 0.0),
            (0.5, 0.0),
            (0.0, 1.0),
        ];
        points.push((0.99, 0.01));
        let mut hull = Vec::new();
        convex_hull_2d(points.into_iter(), &mut hull);
        assert_eq!(hull, vec![(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
        assert_eq!(hull_area(hull.clone()), 2.0);
        assert!(outside(&hull, (0.5, 0.5)) < 0.0);
        assert!((outside(&hull, (1.5, 0.5)) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn a_flat_grid_keeps_its_four_corners_so_the_support_polygon_is_whole() {
        // 20 x 20 points of one flat face resting at equal depth: any normal
        // wrench the full set carries (centre of pressure anywhere in the
        // square) the corners carry too.
        let mut points = Vec::new();
        for i in 0..20 {
            for j in 0..20 {
                points.push((DVec3::new(i as f64 * 0.01, j as f64 * 0.01, 0.0), -0.001));
            }
        }
        let keep = reduce(&points);
        assert!(keep.len() <= PATCH_MAX_POINTS && keep.len() >= 4);
        for corner in [0, 19, 380, 399] {
            assert!(keep.contains(&corner), "corner {corner} dropped: {keep:?}");
        }
    }

    #[test]
    fn random_patches_keep_the_deepest_point_and_most_of_the_support_area() {
        let mut rng = SplitMix64(7);
        for case in 0..200 {
            let n = 9 + (rng.next_u64() % 300) as usize;
            let points: Vec<(DVec3, f64)> = (0..n)
                .map(|_| {
                    let p = DVec3::new(
                        rng.range(-0.1, 0.1),
                        rng.range(-0.05, 0.05),
                        rng.range(-1e-3, 1e-3),
                    );
                    (p, rng.range(-0.003, 0.0))
                })
                .collect();
            let keep = reduce(&points);
            assert!(keep.len() <= PATCH_MAX_POINTS, "case {case}: kept {}", keep.len());
            assert!(
                keep.windows(2).all(|w| w[0] < w[1]),
                "case {case}: not increasing and unique"
            );
            // The deepest point, up to reduce_to_four's tie tolerance.
            let deepest = points.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
            let kept_deepest = keep.iter().map(|&i| points[i].1).fold(f64::INFINITY, f64::min);
            assert!(
                kept_deepest <= deepest + 1e-5 * 0.3,
                "case {case}: deepest dropped"
            );
            // Every point here has a negative gap, so all are support; the
            // kept ones span most of their hull (four chosen by area, then
            // spread).
            let flat =
                |ids: &mut dyn Iterator<Item = usize>| ids.map(|i| (points[i].0.x, points[i].0.y)).collect();
            let full = hull_area(flat(&mut (0..n)));
            let kept = hull_area(flat(&mut keep.iter().copied()));
            assert!(kept >= 0.85 * full, "case {case}: kept hull {kept} of {full}");
        }
    }

    #[test]
    fn speculative_points_do_not_displace_the_support() {
        // A ring of 40 points resting at -1 mm (a torus on the floor) and 200
        // speculative points 5 to 20 mm up around it: the kept points are all
        // on the ring, spread round it.
        let mut points = Vec::new();
        for k in 0..40 {
            let a = std::f64::consts::TAU * k as f64 / 40.0;
            points.push((DVec3::new(0.1 * a.cos(), 0.1 * a.sin(), 0.0), -0.001));
        }
        let mut rng = SplitMix64(3);
        for _ in 0..200 {
            let p = DVec3::new(rng.range(-0.14, 0.14), rng.range(-0.14, 0.14), 0.0);
            points.push((p, rng.range(0.005, 0.02)));
        }
        let keep = reduce(&points);
        assert_eq!(keep.len(), PATCH_MAX_POINTS);
        assert!(keep.iter().all(|&i| i < 40), "{keep:?}");
        let ring = hull_area((0..40).map(|i| (points[i].0.x, points[i].0.y)).collect());
        let kept = hull_area(keep.iter().map(|&i| (points[i].0.x, points[i].0.y)).collect());
        assert!(kept >= 0.85 * ring, "kept {kept} of {ring}");
    }

    #[test]
    fn a_small_support_is_kept_whole_and_the_deepest_others_fill_up() {
        // Three points at rest and 20 above them: the three, then the five
        // lowest of the others.
        let mut points = vec![
            (DVec3::ZERO, -0.001),
            (DVec3::X * 0.1, -0.001),
            (DVec3::Y * 0.1, -0.0012),
        ];
        for k in 0..20 {
            points.push((DVec3::new(0.01 * k as f64, 0.05, 0.0), 0.02 - 0.0005 * k as f64));
        }
        let keep = reduce(&points);
        assert_eq!(keep, vec![0, 1, 2, 18, 19, 20, 21, 22]);
        // Up to the limit, nothing is dropped.
        let few = &points[..PATCH_MAX_POINTS];
        let mut all = Vec::new();
        reduce_patch(
            few.len(),
            DVec3::Z,
            PATCH_MAX_POINTS,
            |i| few[i],
            |_| false,
            &mut all,
        );
        assert_eq!(all, (0..PATCH_MAX_POINTS).collect::<Vec<_>>());
    }

    /// A ring of 120 points (a torus resting on the floor, 0.5 mm in),
    /// rocked by `tilt` (rad about y, rad about x): its depths.
    fn rocked_ring(tilt: (f64, f64)) -> Vec<(DVec3, f64)> {
        (0..120)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 120.0;
                let p = DVec3::new(0.4 * a.cos(), 0.4 * a.sin(), 0.0);
                (p, -0.0005 + tilt.0 * p.x + tilt.1 * p.y)
            })
            .collect()
    }

    fn reduce_after(points: &[(DVec3, f64)], before: &[usize]) -> Vec<usize> {
        let mut keep = Vec::new();
        reduce_patch(
            points.len(),
            DVec3::Z,
            PATCH_MAX_POINTS,
            |i| points[i],
            |i| before.contains(&i),
            &mut keep,
        );
        keep
    }

    #[test]
    fn a_patch_keeps_points_whatever_its_gaps() {
        // Gaps that are NaN (a contact of an overflowing shape) or partly
        // NaN: the patch still keeps as many points as it may, the finite
        // ones first, never none.
        let n = PATCH_MAX_POINTS + 3;
        let all_nan: Vec<(DVec3, f64)> = (0..n).map(|i| (DVec3::X * i as f64, f64::NAN)).collect();
        assert_eq!(reduce(&all_nan), (0..PATCH_MAX_POINTS).collect::<Vec<_>>());
        let mut some_nan = all_nan.clone();
        some_nan[n - 1].1 = 0.001;
        some_nan[n - 2].1 = -0.001;
        let kept = reduce(&some_nan);
        assert_eq!(kept.len(), PATCH_MAX_POINTS);
        assert!(kept.contains(&(n - 1)) && kept.contains(&(n - 2)), "{kept:?}");
    }

    #[test]
    fn a_rocking_ring_keeps_the_points_it_kept() {
        // Rocked by 0.1 mrad this way and that (40 um across the ring), a
        // fresh choice moves round the ring; the kept points stay, and they
        // are the ones a fresh choice made at the start.
        let first = reduce(&rocked_ring((1e-4, 0.0)));
        let mut fresh_moved = false;
        for step in 1..20 {
            let a = step as f64;
            let points = rocked_ring((1e-4 * a.cos(), 1e-4 * a.sin()));
            assert_eq!(reduce_after(&points, &first), first, "step {step}");
            fresh_moved |= reduce(&points) != first;
        }
        assert!(fresh_moved, "a fresh choice never moved: the test shows nothing");
    }

    #[test]
    fn kept_points_that_no_longer_span_the_patch_give_way_to_a_fresh_choice() {
        // Four neighbours on the ring span almost nothing of it.
        let points = rocked_ring((0.0, 0.0));
        assert_eq!(reduce_after(&points, &[10, 11, 12, 13]), reduce(&points));
    }

    #[test]
    fn the_deepest_point_joins_kept_points_that_are_too_shallow() {
        // Tipped by 3 mrad about y, the ring's deepest point (x = -0.4) is
        // 2.4 mm deeper than its shallowest; kept points near the top of
        // the tilt stay (they still span the ring) and the deepest joins.
        let points = rocked_ring((3e-3, 0.0));
        let deepest = (0..points.len())
            .min_by(|&i, &j| points[i].1.total_cmp(&points[j].1))
            .unwrap();
        assert_eq!(deepest, 60);
        let before = [20, 30, 40, 80, 90, 100];
        let keep = reduce_after(&points, &before);
        assert!(keep.contains(&deepest), "{keep:?}");
        for i in before {
            if points[i].1 <= points[deepest].1 + PATCH_DEPTH_BAND {
                assert!(keep.contains(&i), "{i} dropped: {keep:?}");
            }
        }
    }

    #[test]
    fn a_line_of_support_is_chosen_afresh_whatever_was_kept() {
        // A cylinder on its side: 60 points along a line, all resting. The
        // kept points (the middle of the line) span no area to compare, so
        // the fresh choice, which reaches both ends, stands.
        let points: Vec<(DVec3, f64)> = (0..60)
            .map(|k| (DVec3::new(0.01 * k as f64, 0.0, 0.0), -0.0005))
            .collect();
        let fresh = reduce(&points);
        assert!(fresh.contains(&0) && fresh.contains(&59), "{fresh:?}");
        assert_eq!(reduce_after(&points, &[28, 29, 30, 31]), fresh);
    }
}
