//! The value types of the API: primitives, answers, certified intervals and path counters.

use crate::Real;

/// A point: `[x, y, z]`.
pub type Point<T> = [T; 3];
/// A segment: its two end points.
pub type Segment<T> = [Point<T>; 2];
/// A triangle: its three vertices.
pub type Triangle<T> = [Point<T>; 3];

/// A squared distance and the closest points realising it: `p` on the first primitive, `q` on
/// the second. For intersecting triangles `sqdist` is 0 and `p`, `q` are a point of contact
/// (equal up to rounding). Closest points are not unique for parallel features; any valid pair
/// may be returned.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ClosestPoints<T> {
    /// Squared distance.
    pub sqdist: T,
    /// Closest point on the first primitive.
    pub p: Point<T>,
    /// Closest point on the second primitive.
    pub q: Point<T>,
}

/// A certified interval of the (unsquared) distance: the exact distance between the two
/// primitives *as given* (every float is an exact rational) lies in `[lo, hi]`.
///
/// Every query computes one for every pair and uses it to decide whether the answer is good
/// enough ([`crate::Tolerance`]); ask for it with [`crate::Outputs::intervals`]. The returned
/// squared distance is the square of a distance in `[lo, hi]`, rounded once, so the error of the
/// answer's distance is at most `hi - lo` (plus that rounding). Non-finite input gives NaN
/// bounds; where the distance overflows the precision, `hi` (and possibly `lo`) is `+inf`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Interval<T> {
    /// Lower bound of the exact distance (0 when contact cannot be excluded).
    pub lo: T,
    /// Upper bound of the exact distance.
    pub hi: T,
}

impl<T: Real> Interval<T> {
    /// `hi - lo`: a bound on the error of the answer's distance.
    pub fn width(&self) -> T {
        self.hi - self.lo
    }

    /// Does the interval contain `d`?
    pub fn contains(&self, d: T) -> bool {
        self.lo <= d && d <= self.hi
    }
}

/// The answer of an intersection query.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Intersection {
    /// The triangles are apart: certain (a separating direction was proven beyond rounding),
    /// unless the pair is counted as uncertified in [`PathCounts`].
    Disjoint,
    /// The triangles touch or overlap, or are within the tolerance of touching
    /// ([`crate::Tolerance`]; with the `exact` feature and [`crate::Tolerance::EXACT`], exactly).
    Intersecting,
    /// A coordinate was NaN or infinite.
    #[default]
    Invalid,
}

impl Intersection {
    /// `Some(true)` for [`Intersection::Intersecting`], `Some(false)` for
    /// [`Intersection::Disjoint`], `None` for invalid input.
    pub fn as_bool(self) -> Option<bool> {
        match self {
            Intersection::Disjoint => Some(false),
            Intersection::Intersecting => Some(true),
            Intersection::Invalid => None,
        }
    }
}

/// The answer of a single within-margin query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Proximity<T> {
    /// The distance is at most the margin; its square.
    Within(T),
    /// The distance exceeds the margin.
    Beyond,
    /// A coordinate was NaN or infinite.
    Invalid,
}

/// Which path the pairs of a batch took (returned by every batch query): the speed
/// breakdown a user can read. Pairs are counted once in `pairs` and once more in each later
/// stage they reached.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct PathCounts {
    /// Pairs answered.
    pub pairs: u64,
    /// Pairs decided by a bounding-box test alone (within-margin: farther than the margin).
    pub prefiltered: u64,
    /// Pairs handed from a cheap test to the full distance pipeline (within-margin survivors
    /// of the box test, intersection pairs neither separated nor pierced).
    pub delegated: u64,
    /// Triangle-triangle distance: pairs the quick stage (one edge pair) left open, answered
    /// by the full fast stage (fifteen candidates and contact) in compacted vectors; without
    /// the quick stage ([`crate::Engine::quick_stage`]), every pair, loaded in place.
    pub refined: u64,
    /// Pairs whose fast-stage certificate was wider than the tolerance (for triangle-triangle
    /// distance: the full fast stage's), re-certified with the tight
    /// (error-free transformation) certificate, in compacted vectors.
    pub recertified: u64,
    /// Pairs the tight certificate could not accept either, recomputed by the accurate stage
    /// (PQP) in compacted vectors.
    pub compacted: u64,
    /// Pairs (f32 input) the working precision could not certify, recomputed in f64 from the
    /// exactly widened input.
    pub widened: u64,
    /// Pairs recomputed by the exact oracle (feature `exact`).
    pub exact: u64,
    /// Pairs whose final interval is still wider than the tolerance (answered, not certified
    /// to it; their interval says how far off they may be).
    pub uncertified: u64,
    /// Under [`crate::Tolerance::CORRECTLY_ROUNDED`]: pairs whose correctly rounded square
    /// neither the f64 interval nor the exact oracle (off or not compiled in) decided,
    /// answered with their f64 answer rounded once (also counted in `uncertified`).
    pub undecided: u64,
    /// Under [`crate::Tolerance::CORRECTLY_ROUNDED`]: pairs answered 0 by the mode's per-pair
    /// proof of contact where their interval could not decide: a point both primitives share,
    /// or an edge of one triangle crossing the other's interior (orientation tests with a
    /// certified error bound). Triangle pairs whose shared vertex, or the crossing its fast
    /// stage names, the mode's f64 pass proves itself get an exact interval and are not
    /// counted here (nearly every such pair: this counts what that pass leaves).
    pub crossed: u64,
}

impl PathCounts {
    /// Adds another batch's counts.
    pub fn add(&mut self, o: &PathCounts) {
        self.pairs += o.pairs;
        self.prefiltered += o.prefiltered;
        self.delegated += o.delegated;
        self.refined += o.refined;
        self.recertified += o.recertified;
        self.compacted += o.compacted;
        self.widened += o.widened;
        self.exact += o.exact;
        self.uncertified += o.uncertified;
        self.undecided += o.undecided;
        self.crossed += o.crossed;
    }
}
