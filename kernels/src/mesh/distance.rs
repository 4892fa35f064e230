//! [`Engine::mesh_distance`]'s searcher ([`Nearest`]): the smallest answer so far, less the
//! slack, prunes; and how answers are ranked.

use super::scratch::Pending;
use super::traverse::{check_finite, Axis, Search};
use super::MeshDistance;
use crate::algo::nodes::Limit;
use crate::ClosestPoints;
use crate::Engine;
use crate::Error;
use crate::Real;

impl Engine {
    /// How far above the smallest answer so far [`Engine::mesh_distance`] still looks for a
    /// nearer pair, in units of `u S` (`u` the unit roundoff of the mesh's precision, `S` the
    /// largest moved coordinate of both meshes), at most the engine's tolerance width
    /// (`scaled u S` or `absolute`, the larger). The distance answered is at most this many
    /// `u S` above the smallest of the kernels' answers over all pairs. Without it, meshes far
    /// from the origin, whose pairs' distances tie within rounding, were searched pair by pair
    /// (seconds instead of milliseconds; `docs/notes/mesh.md` in the repository).
    ///
    /// In f64 the bounds' own rounding exceeds this slack, so once a search has answered
    /// [`Engine::MESH_DISTANCE_WIDEN_AFTER`] pairs, or as many as both meshes have triangles if
    /// that is more, without finishing, its slack widens to the tolerance's width (64 `u S` by
    /// default): the distance is then at most that width above the smallest kernel answer.
    /// Part of [`Engine::mesh_distance`]'s guarantee; [`crate::Tolerance::EXACT`] has no slack.
    pub const MESH_DISTANCE_SLACK: f64 = 4.0;

    /// How many triangle pairs [`Engine::mesh_distance`] answers (at least; or as many as both
    /// meshes have triangles, if that is more) before its slack widens from
    /// [`Engine::MESH_DISTANCE_SLACK`] `u S` to the tolerance's width.
    pub const MESH_DISTANCE_WIDEN_AFTER: usize = 1 << 16;
}

/// [`Engine::mesh_distance`]: the smallest answer so far, less the slack, prunes.
pub(super) struct Nearest<T> {
    pub(super) best: Option<MeshDistance<T>>,
    pub(super) best_d: f64,
    pub(super) out: Vec<ClosestPoints<T>>,
    /// The tolerance in use (it caps the slack).
    pub(super) tol: crate::Tolerance,
    /// How much nearer than `best_d` a pair must be able to come to be visited.
    pub(super) slack: f64,
    /// The slack once `widen_after` pairs are answered: the tolerance's width.
    pub(super) wide: f64,
    /// [`Engine::MESH_DISTANCE_WIDEN_AFTER`], or the meshes' triangles if more.
    pub(super) widen_after: usize,
    /// The squared distance beyond which node pairs are pruned: `(sqrt(best_d) - slack)^2`,
    /// rounded up, at most `best_d`.
    pub(super) lim: f64,
    /// Triangle pairs answered (for the tests).
    pub(super) answered: usize,
    /// How many times `best` improved ([`Search::axis`]'s version), and the scene's magnitude.
    improved: usize,
    mag: f64,
}

impl<T: Real> Nearest<T> {
    pub(super) fn new(tol: crate::Tolerance) -> Self {
        Nearest {
            best: None,
            best_d: f64::INFINITY,
            out: Vec::new(),
            tol,
            slack: 0.0,
            wide: 0.0,
            widen_after: usize::MAX,
            lim: f64::INFINITY,
            answered: 0,
            improved: 0,
            mag: 0.0,
        }
    }

    /// The slack at magnitude `mag`: [`Engine::MESH_DISTANCE_SLACK`] `u S`, at most the tolerance's
    /// width there (`scaled u S` or `absolute`, the larger; a relative tolerance alone allows
    /// none), so that [`crate::Tolerance::EXACT`] keeps the exact minimum.
    pub(super) fn slack(tol: &crate::Tolerance, mag: f64) -> f64 {
        (Engine::MESH_DISTANCE_SLACK * T::UNIT_ROUNDOFF.to_f64() * mag).min(Self::width(tol, mag))
    }

    /// The tolerance's width at magnitude `mag` (`scaled u S` or `absolute`, the larger).
    pub(super) fn width(tol: &crate::Tolerance, mag: f64) -> f64 {
        (tol.scaled * T::UNIT_ROUNDOFF.to_f64() * mag).max(tol.absolute)
    }
}

/// How the nearest-pair searches ([`Engine::mesh_distance`], [`Engine::mesh_closest_point`])
/// rank an answer: its squared distance (as `f64`), or, where that overflows `T` (the
/// documented `+inf` of the kernels), its closest points' squared distance in `f64`: finite
/// for f32 meshes (so the search still finds the closest pair, and prunes by it), `+inf` only
/// for f64 points more than about 1.3e154 apart.
pub(super) fn rank<T: Real>(cp: &ClosestPoints<T>) -> f64 {
    let d = cp.sqdist.to_f64();
    if d != f64::INFINITY {
        return d;
    }
    (0..3).map(|k| cp.q[k].to_f64() - cp.p[k].to_f64()).map(|x| x * x).sum()
}

/// The squared distance beyond which a nearest-pair search that has an answer prunes: `lim`,
/// or, when even the best answer's rank ([`rank`]) overflows (f64 meshes more than about
/// 1.3e154 apart), the largest `f64`: a node pair whose squared gap overflows too can only
/// hold pairs that rank `+inf` as well (ties go to the smaller triangle numbers of the pairs
/// answered). Without it no node pair was ever pruned there, and the search answered every
/// pair (minutes for the Armadillo against fandisk; `tridist mesh ... --pose-b 1e155,0,0`).
pub(super) fn prune_beyond(lim: f64) -> f64 {
    if lim == f64::INFINITY {
        f64::MAX
    } else {
        lim
    }
}

/// `(sqrt(d) - slack)^2` rounded up (each step rounded to nearest, then one step up), and 0
/// where `slack` reaches `sqrt(d)`; `d` itself when that is smaller (or with no slack).
pub(super) fn less_slack(d: f64, slack: f64) -> f64 {
    if slack <= 0.0 || !d.is_finite() {
        return d;
    }
    let r = (d.sqrt().next_up() - slack).next_up();
    if r <= 0.0 {
        0.0
    } else {
        (r * r).next_up().min(d)
    }
}

impl<T: Real> Search<T> for Nearest<T> {
    fn limit(&self) -> Limit {
        Limit::Fixed(self.lim)
    }
    fn start(&mut self, mag: f64) {
        self.mag = mag;
        self.slack = Self::slack(&self.tol, mag);
        self.wide = Self::width(&self.tol, mag);
    }
    fn eager(&self, overlap: bool) -> bool {
        // A leaf pair whose boxes overlap likely holds a touching pair, whose answer 0 ends
        // the search: answered at once, not in a batch of 64, the distance at the report's
        // interpenetrating poses 4-7 took 0.008, 0.035-0.036, 0.012 and 0.028-0.029 ms instead
        // of 0.022, 0.067-0.071, 0.025-0.026 and 0.091-0.095 (in the overlap-depth order that
        // preceded the fraction's; `spin mesh distance P f32 1 0.5`, two copies of each build
        // alternated); separated poses never gather such a pair.
        self.best.is_none() || overlap
    }
    fn best_first(&self) -> bool {
        true
    }
    fn axis(&self) -> Option<Axis> {
        let b = self.best.filter(|_| self.best_d > 0.0)?;
        let dir = core::array::from_fn(|k| b.q[k].to_f64() - b.p[k].to_f64());
        Some(Axis { dir, version: self.improved, mag: self.mag })
    }
    fn flush(&mut self, e: &Engine, pend: &Pending<T>) -> Result<bool, Error> {
        self.out.clear();
        self.out.resize(pend.ids.len(), ClosestPoints::default());
        e.closest_points_triangle_triangle(&pend.a, &pend.b, &mut self.out)?;
        self.answered += pend.ids.len();
        for (cp, &(i, j)) in self.out.iter().zip(&pend.ids) {
            check_finite(cp.sqdist)?;
            let d = rank(cp);
            // ties among the pairs answered go to the smaller triangle numbers
            let better = match self.best {
                None => true,
                Some(m) => {
                    d < self.best_d || (d == self.best_d && (i as usize, j as usize) < (m.tri_a, m.tri_b))
                }
            };
            if better {
                self.improved += 1;
                self.best_d = d;
                self.best = Some(MeshDistance {
                    sqdist: cp.sqdist,
                    distance: Some(cp.sqdist.sqrt()),
                    p: cp.p,
                    q: cp.q,
                    tri_a: i as usize,
                    tri_b: j as usize,
                });
            }
        }
        if self.answered >= self.widen_after {
            self.slack = self.wide;
        }
        self.lim = prune_beyond(less_slack(self.best_d, self.slack));
        // nothing is nearer than touching: the search ends at the first batch that touches
        Ok(self.best_d == 0.0)
    }
}
