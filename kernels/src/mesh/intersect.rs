//! [`Engine::mesh_intersect`]'s and [`Engine::mesh_within_margin`]'s searcher ([`FirstHit`]):
//! stops at the first batch with an intersecting pair, or a pair within the margin.

use super::bounds::reach;
use super::contacts::margin_sq;
use super::scratch::Pending;
use super::traverse::{check_finite, Search};
use crate::algo::nodes::Limit;
use crate::engine::Outputs;
use crate::Engine;
use crate::Error;
use crate::Intersection;
use crate::Query;
use crate::Real;

/// [`Engine::mesh_intersect`] and [`Engine::mesh_within_margin`]: stops at the first batch
/// with a hit, an intersecting pair or (with a margin) a pair within the margin.
pub(super) struct FirstHit<T> {
    pub(super) tol: crate::Tolerance,
    /// Within-margin: the margin, decided as [`Contacts`] decides it; intersection: `None`.
    pub(super) margin: Option<f64>,
    pub(super) hit: Option<(usize, usize)>,
    pub(super) v: Vec<Intersection>,
    pub(super) d: Vec<T>,
    /// [`Search::overlap_first`] (always, but for the test that shows the walk without it).
    pub(super) overlap_first: bool,
    /// Triangle pairs answered (for the tests).
    pub(super) answered: usize,
}

impl<T: Real> FirstHit<T> {
    pub(super) fn new(tol: crate::Tolerance, margin: Option<f64>) -> Self {
        FirstHit { tol, margin, hit: None, v: Vec::new(), d: Vec::new(), overlap_first: true, answered: 0 }
    }

    pub(super) fn keep(&mut self, (i, j): (u32, u32)) {
        let p = (i as usize, j as usize);
        self.hit = Some(self.hit.map_or(p, |h| h.min(p)));
    }
}

impl<T: Real> Search<T> for FirstHit<T> {
    fn limit(&self) -> Limit {
        // "Intersecting" is said of pairs within the tolerance of touching, "within the
        // margin" of pairs the kernels answer within it: boxes that much farther apart are kept.
        reach::<T>(&self.tol, self.margin.unwrap_or(0.0))
    }
    fn eager(&self, overlap: bool) -> bool {
        // Within a margin, a search that finds nothing visits every node pair within it (as
        // the contact query does), so its leaf pairs are batched, except the first one and
        // those whose boxes overlap, which likely hold a hit.
        self.margin.is_none() || overlap || self.answered == 0
    }
    fn overlap_first(&self) -> bool {
        self.overlap_first
    }
    fn flush(&mut self, e: &Engine, pend: &Pending<T>) -> Result<bool, Error> {
        let n = pend.ids.len();
        self.answered += n;
        if let Some(margin) = self.margin {
            self.d.clear();
            self.d.resize(n, T::ZERO);
            e.run(Query::TriTri, &pend.a, &pend.b, Outputs::new().sqdist(&mut self.d))?;
            let m2 = margin_sq::<T>(margin);
            for k in 0..n {
                check_finite(self.d[k])?;
                if self.d[k] <= m2 {
                    self.keep(pend.ids[k]);
                }
            }
        } else {
            self.v.clear();
            self.v.resize(n, Intersection::Invalid);
            e.intersect_triangle_triangle(&pend.a, &pend.b, &mut self.v)?;
            for k in 0..n {
                match self.v[k] {
                    Intersection::Invalid => return Err(Error::NonFiniteCoordinate),
                    Intersection::Intersecting => self.keep(pend.ids[k]),
                    Intersection::Disjoint => {}
                }
            }
        }
        Ok(self.hit.is_some())
    }
}
