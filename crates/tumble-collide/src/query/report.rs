//! What the queries return: the collision [`Report`], the
//! [`DistanceResult`], and the work counters of both ([`QueryStats`], as PQP
//! returns with every query, so tests and benchmarks can see a tree that got
//! worse).

use super::error::QueryError;
use super::options::ReportMode;
use crate::bvh::{TraversalStats, Traverse};
use crate::contact::Contact;
use crate::math::DVec3;
use serde::Serialize;

/// Work done by one query.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct QueryStats {
    /// Bounding-volume tests (box-box, or box against the query volume).
    pub bv_tests: u64,
    /// Exact triangle tests (overlap, distance or contact generation).
    pub triangle_tests: u64,
    /// `true` when the walk ended early (first contact found, or distance 0).
    pub stopped_early: bool,
}

impl QueryStats {
    /// From a traversal's counters and the number of exact tests run.
    pub(crate) fn from_traversal(t: &TraversalStats, triangle_tests: u64) -> QueryStats {
        QueryStats {
            bv_tests: t.bv_tests,
            triangle_tests,
            stopped_early: t.stopped,
        }
    }
}

/// Result of a collision query.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Report {
    /// `true` when some triangle of A and some triangle of B share a point
    /// (closed triangles: touching counts). For primitive queries: when the
    /// solid primitive shares a point with a triangle of the mesh.
    pub intersect: bool,
    /// Intersecting triangle pairs `(triangle of A, triangle of B)`, sorted
    /// and without repeats; empty in [`super::ReportMode::Boolean`]. For
    /// primitive queries the first index is always 0 (the primitive).
    pub pairs: Vec<(u32, u32)>,
    /// Contacts (world frame, normal from B to A, see [`Contact`]); only in
    /// [`super::ReportMode::Contacts`].
    pub contacts: Vec<Contact>,
    /// Work counters.
    pub stats: QueryStats,
}

/// Result of a distance query.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DistanceResult {
    /// Distance between the shapes (m); 0 when they intersect. With a
    /// non-zero [`super::DistanceOptions`] error an upper bound within it.
    pub distance: f64,
    /// Closest point on A (world frame, m); a common point when intersecting.
    pub point_a: DVec3,
    /// Closest point on B (world frame, m).
    pub point_b: DVec3,
    /// Triangle of A holding `point_a` (0 for a primitive).
    pub tri_a: u32,
    /// Triangle of B holding `point_b`.
    pub tri_b: u32,
    /// Work counters.
    pub stats: QueryStats,
}

impl Report {
    /// Records a hit of the pair `(a, b)` as [`super::collide`](fn@super::collide) and
    /// [`super::collide_primitive`] both report it in `mode`: `intersect`, the
    /// pair unless in [`ReportMode::Boolean`]; then whether the walk stops.
    #[inline]
    pub(crate) fn record_hit(&mut self, pair: (u32, u32), mode: ReportMode, stop_first: bool) -> Traverse {
        self.intersect = true;
        if mode != ReportMode::Boolean {
            self.pairs.push(pair);
        }
        if stop_first {
            Traverse::Stop
        } else {
            Traverse::Continue
        }
    }

    /// The end of a collision query once its walk (`traversal`, `tests`
    /// exact tests) and its contacts are done: pairs sorted (each came once),
    /// counters set; [`QueryError::NotFinite`] naming `query` when a contact
    /// is not finite (coordinates or dimensions near the f64 limit, e.g. a
    /// sphere of radius 1e308, overflow in the contact arithmetic; found by
    /// fuzzing), never a NaN contact.
    pub(crate) fn finish(
        mut self,
        traversal: &TraversalStats,
        tests: u64,
        query: &'static str,
    ) -> Result<Report, QueryError> {
        self.pairs.sort_unstable();
        let finite = |c: &Contact| c.point.is_finite() && c.normal.is_finite() && c.distance.is_finite();
        if !self.contacts.iter().all(finite) {
            return Err(QueryError::NotFinite(query));
        }
        self.stats = QueryStats::from_traversal(traversal, tests);
        Ok(self)
    }

    /// The same report with A and B exchanged: pairs reversed (and sorted
    /// again), contacts flipped (normals from the new B to the new A).
    pub fn swapped(mut self) -> Report {
        for p in &mut self.pairs {
            *p = (p.1, p.0);
        }
        self.pairs.sort_unstable();
        for c in &mut self.contacts {
            *c = c.flipped();
        }
        self
    }
}

impl DistanceResult {
    /// The result if its distance and points are finite; coordinates near
    /// the f64 limit (1e300) can overflow in the closest-point arithmetic
    /// (found by fuzzing): then [`QueryError::NotFinite`] naming `query`,
    /// never NaN points.
    pub(crate) fn finite(self, query: &'static str) -> Result<DistanceResult, QueryError> {
        if self.distance.is_finite() && self.point_a.is_finite() && self.point_b.is_finite() {
            Ok(self)
        } else {
            Err(QueryError::NotFinite(query))
        }
    }

    /// The same result with A and B exchanged (points and triangles).
    pub fn swapped(self) -> DistanceResult {
        DistanceResult {
            point_a: self.point_b,
            point_b: self.point_a,
            tri_a: self.tri_b,
            tri_b: self.tri_a,
            ..self
        }
    }
}
