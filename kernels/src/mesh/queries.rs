//! The mesh queries of [`Engine`]: each checks its input, moves the roots and runs the one
//! traversal ([`search`]) with its searcher.

use super::bounds::point_gap2;
use super::contacts::{contacts_threaded, sorted, Contacts};
use super::distance::{prune_beyond, rank, Nearest};
use super::intersect::FirstHit;
use super::traverse::{check_finite, search};
use super::{Contact, Mesh, MeshDistance, MeshPoint, FLUSH};
use crate::algo::nodes::Moved;
use crate::ClosestPoints;
use crate::Engine;
use crate::Error;
use crate::Point;
use crate::Pose;
use crate::Real;
use crate::Triangle;

impl Engine {
    /// The closest pair of triangles of two meshes in their poses: squared distance, closest
    /// points and the triangles that hold them (`None` when a mesh is empty). Touching or
    /// intersecting meshes give 0 (at some touching pair).
    ///
    /// The answer is the kernels' answer for the pair it names, and its distance is at most
    /// `min(4 u S, w)` above the smallest of the kernels' answers over all pairs (`S` the
    /// largest moved coordinate of both meshes, `w` the tolerance's `scaled u S` or
    /// `absolute`, the larger): the search does not refine within the coordinates' own
    /// rounding, where far from the origin every pair may tie. A search that has answered
    /// [`Engine::MESH_DISTANCE_WIDEN_AFTER`] pairs (or as many as both meshes have triangles, if more)
    /// without finishing allows `w` instead (f64 meshes far apart compared with their size:
    /// see [`Engine::MESH_DISTANCE_SLACK`]). [`crate::Tolerance::EXACT`] leaves no slack.
    ///
    /// Meshes so far apart that the squared distance overflows `T` (f32 meshes more than
    /// about 1.8e19 apart, f64 ones 1.3e154) get `sqdist = +inf`, as the triangle queries
    /// document, with the closest points of the pair named. For f32 meshes that pair is still
    /// the closest one as above: the search ranks such answers by their points' squared
    /// distance in f64. For f64 meshes, where that overflows too, it is the first pair (in
    /// triangle numbers) of those answered whose square overflows, not necessarily the
    /// closest, and node pairs whose squared gap overflows are not searched; move both poses
    /// nearer the origin together, or scale the meshes, for the closest pair.
    ///
    /// # Errors
    /// The engine's setting errors ([`Engine::check`]), [`Error::InvalidPose`] for a non-finite
    /// pose, [`Error::NonFiniteCoordinate`] when a moved coordinate overflows; under
    /// [`crate::Tolerance::CORRECTLY_ROUNDED`], [`Error::Undecided`] when a pair that may hold
    /// the minimum could not be decided without the exact oracle, or when the squared distance
    /// is near or beyond `T`'s range (see "Correctly rounded" below).
    ///
    /// # Correctly rounded
    /// Under [`crate::Tolerance::CORRECTLY_ROUNDED`] `sqdist` is the smallest exact squared
    /// distance over all triangle pairs of the moved meshes ([`Mesh::triangle_at`]), rounded to
    /// nearest in `T`, and the pair named is the first in triangle order whose correctly rounded
    /// square is that value: every pair whose exact distance can be the minimum is answered by
    /// the correctly rounded triangle query. `distance` is the smallest exact distance
    /// correctly rounded, `RN(sqrt(D*))`, decided on its own from the candidates that may hold
    /// the minimum (it can belong to another pair whose square rounds alike), or `None` when
    /// one of them is undecided without the oracle: f64 meshes need the `exact` feature for
    /// it, as the triangle queries' distances do. It costs a contact query around the minimum
    /// after the distance search. The decisions of the other mesh queries run under it as under
    /// [`crate::Tolerance::EXACT`].
    pub fn mesh_distance<T: Real>(
        &self,
        a: &Mesh<T>,
        pose_a: &Pose<T>,
        b: &Mesh<T>,
        pose_b: &Pose<T>,
    ) -> Result<Option<MeshDistance<T>>, Error> {
        if self.current_tolerance().correctly_rounded {
            return self.mesh_distance_rounded(a, pose_a, b, pose_b);
        }
        let mut s = Nearest::new(self.current_tolerance());
        s.widen_after = Engine::MESH_DISTANCE_WIDEN_AFTER.max(a.len() + b.len());
        search(self, a, pose_a, b, pose_b, &mut s)?;
        Ok(s.best)
    }

    /// [`Engine::mesh_distance`] under [`crate::Tolerance::CORRECTLY_ROUNDED`]: the smallest
    /// exact squared distance over all triangle pairs, rounded to nearest. The search at the
    /// default tolerance bounds it from above; every pair whose answer falls within that bound
    /// plus twice the default tolerance's width (`2 x 64 u S`, so every pair whose exact distance
    /// can be the minimum) is answered by the correctly rounded triangle query, and the minimum
    /// of their rounded squares is the rounded minimum (rounding is monotonic). The pair
    /// reported is the first in triangle order whose rounded square is that minimum. The
    /// distance likewise: the candidates whose intervals reach the minimum's pair's are asked
    /// for their correctly rounded distances, and the smallest is the minimum's.
    fn mesh_distance_rounded<T: Real>(
        &self,
        a: &Mesh<T>,
        pose_a: &Pose<T>,
        b: &Mesh<T>,
        pose_b: &Pose<T>,
    ) -> Result<Option<MeshDistance<T>>, Error> {
        let plain = self.tolerance(crate::Tolerance::DEFAULT);
        let Some(first) = plain.mesh_distance(a, pose_a, b, pose_b)? else { return Ok(None) };
        // S: the largest moved coordinate of both meshes (their root boxes)
        let s = [a.moved_box(0, &Moved::of(pose_a)), b.moved_box(0, &Moved::of(pose_b))]
            .iter()
            .flat_map(|(lo, hi)| lo.iter().chain(hi.iter()))
            .fold(0.0f64, |m, x| m.max(x.abs()));
        let w = 2.0 * crate::Tolerance::DEFAULT.scaled * T::UNIT_ROUNDOFF.to_f64() * s;
        let reach = first.sqdist.to_f64().sqrt() * (1.0 + 4.0 * T::UNIT_ROUNDOFF.to_f64()) + w;
        let reach = T::from_f64(reach);
        if !reach.is_finite() {
            // squares beyond T's range: no margin reaches them (mesh_contacts takes finite ones)
            return Err(Error::Undecided);
        }
        // the candidates: the pairs within reach, and the default search's own pair
        let mut near: Vec<(usize, usize)> = plain
            .mesh_contacts(a, pose_a, b, pose_b, reach, None)?
            .iter()
            .map(|c| (c.tri_a, c.tri_b))
            .collect();
        if !near.contains(&(first.tri_a, first.tri_b)) {
            near.push((first.tri_a, first.tri_b));
        }
        let tri = |m: &Mesh<T>, i: usize, p: &Pose<T>| m.triangle_at(i, p).ok_or(Error::NonFiniteCoordinate);
        let ta = near.iter().map(|c| tri(a, c.0, pose_a)).collect::<Result<Vec<_>, _>>()?;
        let tb = near.iter().map(|c| tri(b, c.1, pose_b)).collect::<Result<Vec<_>, _>>()?;
        let mut cp = vec![ClosestPoints::default(); near.len()];
        let mut ok = vec![false; near.len()];
        let mut iv = vec![crate::Interval::default(); near.len()];
        self.run(
            crate::Query::TriTri,
            &ta[..],
            &tb[..],
            crate::Outputs::new().closest_points(&mut cp).certified(&mut ok).intervals(&mut iv),
        )?;
        for c in &cp {
            check_finite(c.sqdist)?;
        }
        // (`near` holds the default search's pair, so it is never empty)
        let k = rounded_minimum(&cp, &ok, &iv, &near)?;
        // the distance, decided on its own over the candidates that may reach the minimum
        let at = reaching(&iv, k);
        let (da, db): (Vec<_>, Vec<_>) = at.iter().map(|&j| (ta[j], tb[j])).unzip();
        let mut dist = vec![T::ZERO; at.len()];
        let mut dok = vec![false; at.len()];
        let mut div = vec![crate::Interval::default(); at.len()];
        self.run(
            crate::Query::TriTri,
            &da[..],
            &db[..],
            crate::Outputs::new().distances(&mut dist).certified(&mut dok).intervals(&mut div),
        )?;
        Ok(Some(MeshDistance {
            sqdist: cp[k].sqdist,
            distance: rounded_min_distance(&dist, &dok, &div),
            p: cp[k].p,
            q: cp[k].q,
            tri_a: near[k].0,
            tri_b: near[k].1,
        }))
    }

    /// Every triangle pair of two meshes in their poses whose distance is at most `margin`
    /// (contact generation), each with its squared distance and closest points, ordered by
    /// squared distance then triangle numbers; with `cap`, the first `cap` of that order,
    /// found in memory for about `2 cap` contacts and one batch of candidates (the cap's
    /// size, kept within 64 and 1024) however many pairs are within the margin
    /// (the search narrows to the `cap`-th contact's distance once it has that many).
    ///
    /// Within the margin is decided as [`Engine::within_margin_triangle_triangle`] decides it
    /// (the full triangle-triangle answer, thresholded), pair by pair. So the search visits
    /// every pair whose answer could fall within the margin: exactly up to the margin plus the
    /// tolerance's width (`scaled u S`, 64 `u S` by default) beyond it. Far from the origin
    /// that width can hold far more pairs than the margin, and the search takes time in
    /// proportion (`docs/notes/mesh.md` in the repository measures it); a smaller
    /// [`crate::Tolerance::scaled`] narrows the reach (and sends more pairs to the kernels'
    /// accurate stage). With [`Engine::threads`] above 1 the traversal is split into pieces
    /// walked in parallel; the answer is the same. A margin whose square overflows `f64`
    /// (above about 1.3e154) reaches every pair whose squared distance overflows too: they
    /// tie at `+inf`, ordered by triangle numbers, so a cap cannot narrow that search.
    ///
    /// # Errors
    /// [`Error::InvalidMargin`] for `margin`, the engine's other setting errors
    /// ([`Engine::check`]), [`Error::InvalidPose`], [`Error::NonFiniteCoordinate`].
    pub fn mesh_contacts<T: Real>(
        &self,
        a: &Mesh<T>,
        pose_a: &Pose<T>,
        b: &Mesh<T>,
        pose_b: &Pose<T>,
        margin: T,
        cap: Option<usize>,
    ) -> Result<Vec<Contact<T>>, Error> {
        let e = self.margin(margin.to_f64());
        // (the threaded search does not start from `search`, which checks the settings)
        e.params::<T>()?;
        let state = || Contacts::new(margin.to_f64(), e.current_tolerance(), cap);
        let mut found = if self.thread_count() > 1 {
            contacts_threaded(&e, a, pose_a, b, pose_b, &state)?
        } else {
            let mut s = state();
            search(&e, a, pose_a, b, pose_b, &mut s)?;
            s.found
        };
        // deterministic either way: no two contacts share their triangle pair (the threaded
        // search returns them sorted)
        if self.thread_count() <= 1 {
            found = sorted(found.iter());
        }
        if let Some(c) = cap {
            found.truncate(c);
        }
        Ok(found)
    }

    /// Do two meshes in their poses intersect (touch or overlap)? `Some((tri_a, tri_b))`: a
    /// pair the kernels call intersecting ([`Engine::intersect_triangle_triangle`]; the
    /// search stops at the first batch that holds one, and reports its smallest pair), `None`
    /// when every pair is disjoint.
    ///
    /// The kernels may call a pair within the tolerance's width of touching intersecting, so
    /// `None` is answered only after every such pair was answered disjoint. Far from the
    /// origin, where that width (72 `u S` by default) approaches the meshes' size, that is
    /// many pairs, and a `None` takes time in proportion. A `Some` is found among overlapping
    /// boxes first, so it stays fast there (module docs, "The traversal").
    ///
    /// # Errors
    /// The engine's setting errors ([`Engine::check`]), [`Error::InvalidPose`],
    /// [`Error::NonFiniteCoordinate`].
    pub fn mesh_intersect<T: Real>(
        &self,
        a: &Mesh<T>,
        pose_a: &Pose<T>,
        b: &Mesh<T>,
        pose_b: &Pose<T>,
    ) -> Result<Option<(usize, usize)>, Error> {
        let mut s = FirstHit::new(self.current_tolerance(), None);
        search::<T, _>(self, a, pose_a, b, pose_b, &mut s)?;
        Ok(s.hit)
    }

    /// Are two meshes in their poses within `margin` of each other (PQP's tolerance query, a
    /// clearance check)? `Some((tri_a, tri_b))`: a pair the kernels answer within the margin,
    /// one of [`Engine::mesh_contacts`]' contacts at that margin (the search stops at the
    /// first batch that holds one, and reports its smallest pair); `None` exactly when
    /// [`Engine::mesh_contacts`] finds none. The same decision, so the same guarantees: every
    /// pair within the margin is seen, and a pair within `c u S` of the margin may go either
    /// way. Where the meshes come within the margin this stops early, so it is cheaper than a
    /// distance query compared with the margin (reports/MESH.md times both); where they do
    /// not, it visits every node pair the contact query visits, and answers their triangle
    /// pairs' squared distances only. One thread whatever [`Engine::threads`] says.
    ///
    /// # Errors
    /// [`Error::InvalidMargin`] for `margin`, the engine's other setting errors
    /// ([`Engine::check`]), [`Error::InvalidPose`], [`Error::NonFiniteCoordinate`].
    pub fn mesh_within_margin<T: Real>(
        &self,
        a: &Mesh<T>,
        pose_a: &Pose<T>,
        b: &Mesh<T>,
        pose_b: &Pose<T>,
        margin: T,
    ) -> Result<Option<(usize, usize)>, Error> {
        let e = self.margin(margin.to_f64());
        let mut s = FirstHit::new(e.current_tolerance(), Some(margin.to_f64()));
        search::<T, _>(&e, a, pose_a, b, pose_b, &mut s)?;
        Ok(s.hit)
    }

    /// The closest point of a mesh in its pose to `x`: squared distance, the point and its
    /// triangle (`None` for an empty mesh). Where the squared distance overflows `T` it is
    /// `+inf`, ranked and named as [`Engine::mesh_distance`] says (for f32 the closest point
    /// still; for f64, farther than about 1.3e154, a point of the first triangle answered).
    ///
    /// Under [`crate::Tolerance::CORRECTLY_ROUNDED`] `sqdist` is the smallest exact squared
    /// distance from `x` to the triangles of the moved mesh ([`Mesh::triangle_at`]), rounded to
    /// nearest in `T`, and the triangle named is the first in triangle order whose correctly
    /// rounded square is that value; the point is that triangle's closest point as the
    /// correctly rounded point-triangle query returns it. Every triangle whose exact distance
    /// can be the minimum (within the default search's answer plus twice the default
    /// tolerance's width) is answered by that query. `distance` is the minimum's exact
    /// distance correctly rounded, or `None`, as [`Engine::mesh_distance`] decides it.
    ///
    /// # Errors
    /// The engine's setting errors ([`Engine::check`]), [`Error::InvalidPose`],
    /// [`Error::NonFiniteCoordinate`] (also for a non-finite `x`); under
    /// [`crate::Tolerance::CORRECTLY_ROUNDED`], [`Error::Undecided`] when a triangle that may
    /// hold the minimum could not be decided without the exact oracle (feature `exact`), or
    /// when the squared distance is near or beyond `T`'s range.
    pub fn mesh_closest_point<T: Real>(
        &self,
        m: &Mesh<T>,
        pose: &Pose<T>,
        x: Point<T>,
    ) -> Result<Option<MeshPoint<T>>, Error> {
        if self.current_tolerance().correctly_rounded {
            return self.mesh_closest_point_rounded(m, pose, x);
        }
        self.params::<T>()?;
        pose.check()?;
        if x.iter().any(|c| !c.is_finite()) {
            return Err(Error::NonFiniteCoordinate);
        }
        if m.is_empty() {
            return Ok(None);
        }
        let mv = Moved::of(pose);
        mv.fits(m)?;
        let xf = x.map(Real::to_f64);
        let mut best: Option<MeshPoint<T>> = None;
        let mut best_d = f64::INFINITY;
        let (mut ids, mut tris) = (Vec::new(), Vec::new());
        let mut out = Vec::new();
        let mut flush = |ids: &mut Vec<u32>,
                         tris: &mut Vec<Triangle<T>>,
                         best: &mut Option<MeshPoint<T>>,
                         best_d: &mut f64| {
            out.clear();
            out.resize(ids.len(), ClosestPoints::default());
            self.closest_point_point_triangle(&[x], &tris[..], &mut out)?;
            for (cp, &i) in out.iter().zip(ids.iter()) {
                check_finite(cp.sqdist)?;
                let d = rank(cp);
                if best.is_none_or(|b| d < *best_d || (d == *best_d && (i as usize) < b.tri)) {
                    *best_d = d;
                    *best = Some(MeshPoint {
                        sqdist: cp.sqdist,
                        distance: Some(cp.sqdist.sqrt()),
                        point: cp.q,
                        tri: i as usize,
                    });
                }
            }
            ids.clear();
            tris.clear();
            Ok::<(), Error>(())
        };
        let mut stack = vec![(point_gap2(&xf, &m.moved_box(0, &mv)), 0u32)];
        while let Some((gap, n)) = stack.pop() {
            if best.is_some() && gap > prune_beyond(best_d) {
                continue;
            }
            let node = &m.nodes[n as usize];
            if node.count > 0 {
                for at in node.first as usize..(node.first + node.count) as usize {
                    ids.push(m.order[at]);
                    tris.push(m.leaf_triangle_at(at, pose));
                }
                if ids.len() >= FLUSH {
                    flush(&mut ids, &mut tris, &mut best, &mut best_d)?;
                }
            } else {
                // farthest first: the nearest on top
                let at = stack.len();
                stack.extend(
                    (node.first..node.first + node.kids)
                        .map(|k| (point_gap2(&xf, &m.moved_box(k as usize, &mv)), k)),
                );
                stack[at..].sort_by(|p, q| q.0.total_cmp(&p.0));
            }
        }
        if !ids.is_empty() {
            flush(&mut ids, &mut tris, &mut best, &mut best_d)?;
        }
        Ok(best)
    }

    /// [`Engine::mesh_closest_point`] under [`crate::Tolerance::CORRECTLY_ROUNDED`], as
    /// [`Engine::mesh_distance`] does it for two meshes: the search at the default tolerance
    /// bounds the minimum from above, every triangle whose box comes within that bound plus
    /// twice the default tolerance's width (`2 x 64 u S`) is answered by the correctly rounded
    /// point-triangle query, and the smallest rounded square is the rounded minimum.
    fn mesh_closest_point_rounded<T: Real>(
        &self,
        m: &Mesh<T>,
        pose: &Pose<T>,
        x: Point<T>,
    ) -> Result<Option<MeshPoint<T>>, Error> {
        let plain = self.tolerance(crate::Tolerance::DEFAULT);
        let Some(first) = plain.mesh_closest_point(m, pose, x)? else { return Ok(None) };
        let mv = Moved::of(pose);
        let xf = x.map(Real::to_f64);
        // S: the largest coordinate of the moved mesh (its root box) and of x
        let (lo, hi) = m.moved_box(0, &mv);
        let s = lo.iter().chain(hi.iter()).chain(xf.iter()).fold(0.0f64, |a, v| a.max(v.abs()));
        let u = T::UNIT_ROUNDOFF.to_f64();
        let w = 2.0 * crate::Tolerance::DEFAULT.scaled * u * s;
        let reach = first.sqdist.to_f64().sqrt() * (1.0 + 4.0 * u) + w;
        let reach2 = reach * reach * (1.0 + 4.0 * f64::EPSILON);
        if !T::from_f64(reach).is_finite() || !reach2.is_finite() {
            // squares near or beyond T's range: no reach bounds them
            return Err(Error::Undecided);
        }
        // the candidates: every triangle whose box (rounded outward, its gap rounded down)
        // comes within reach, and the default search's own triangle
        let (mut ids, mut tris) = (Vec::new(), Vec::new());
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            if point_gap2(&xf, &m.moved_box(n as usize, &mv)) > reach2 {
                continue;
            }
            let node = &m.nodes[n as usize];
            if node.count > 0 {
                for at in node.first as usize..(node.first + node.count) as usize {
                    ids.push(m.order[at] as usize);
                    tris.push(m.leaf_triangle_at(at, pose));
                }
            } else {
                stack.extend(node.first..node.first + node.kids);
            }
        }
        if !ids.contains(&first.tri) {
            ids.push(first.tri);
            tris.push(m.triangle_at(first.tri, pose).ok_or(Error::NonFiniteCoordinate)?);
        }
        let n = ids.len();
        let mut cp = vec![ClosestPoints::default(); n];
        let mut ok = vec![false; n];
        let mut iv = vec![crate::Interval::default(); n];
        self.run(
            crate::Query::PointTri,
            &[x],
            &tris[..],
            crate::Outputs::new().closest_points(&mut cp).certified(&mut ok).intervals(&mut iv),
        )?;
        for c in &cp {
            check_finite(c.sqdist)?;
        }
        // (`ids` holds the default search's triangle, so it is never empty)
        let k = rounded_minimum(&cp, &ok, &iv, &ids)?;
        // the distance, decided on its own over the candidates that may reach the minimum
        let at = reaching(&iv, k);
        let dt: Vec<Triangle<T>> = at.iter().map(|&j| tris[j]).collect();
        let mut dist = vec![T::ZERO; at.len()];
        let mut dok = vec![false; at.len()];
        let mut div = vec![crate::Interval::default(); at.len()];
        self.run(
            crate::Query::PointTri,
            &[x],
            &dt[..],
            crate::Outputs::new().distances(&mut dist).certified(&mut dok).intervals(&mut div),
        )?;
        Ok(Some(MeshPoint {
            sqdist: cp[k].sqdist,
            distance: rounded_min_distance(&dist, &dok, &div),
            point: cp[k].q,
            tri: ids[k],
        }))
    }
}

/// The candidate with the smallest correctly rounded square, the first by `key` (triangle
/// order) among equals, for the correctly rounded mesh queries; [`Error::Undecided`] when there
/// is none, or when an undecided candidate's square may round to that minimum or below.
fn rounded_minimum<T: Real, K: Ord>(
    cp: &[ClosestPoints<T>],
    ok: &[bool],
    iv: &[crate::Interval<T>],
    key: &[K],
) -> Result<usize, Error> {
    let k = (0..cp.len())
        .min_by(|&x, &y| {
            cp[x]
                .sqdist
                .partial_cmp(&cp[y].sqdist)
                .unwrap_or(core::cmp::Ordering::Equal)
                .then(key[x].cmp(&key[y]))
        })
        .ok_or(Error::Undecided)?;
    let at_most = cp[k].sqdist.to_f64() * (1.0 + 4.0 * T::UNIT_ROUNDOFF.to_f64());
    if (0..cp.len()).any(|j| !ok[j] && iv[j].lo.to_f64() * iv[j].lo.to_f64() <= at_most) {
        return Err(Error::Undecided);
    }
    Ok(k)
}

/// The candidates whose exact distance may be the minimum's: every one whose interval starts
/// at or below the end of the interval of `k` (a decided candidate, so its exact distance is
/// at most that end, and the minimum's too).
pub(super) fn reaching<T: Real>(iv: &[crate::Interval<T>], k: usize) -> Vec<usize> {
    let hi = iv[k].hi.to_f64();
    (0..iv.len()).filter(|&j| iv[j].lo.to_f64() <= hi).collect()
}

/// `RN(sqrt(min D*))` over candidates holding the minimum, from their correctly rounded
/// distances (`dist`, decided where `ok`, `iv` their intervals): rounding and the square root
/// are monotonic, so it is the smallest decided distance, unless an undecided candidate may
/// round to it or below (then `None`).
pub(super) fn rounded_min_distance<T: Real>(dist: &[T], ok: &[bool], iv: &[crate::Interval<T>]) -> Option<T> {
    let m = (0..dist.len()).filter(|&j| ok[j]).map(|j| dist[j]).reduce(|m, d| if d < m { d } else { m })?;
    let at_most = m.to_f64() * (1.0 + 4.0 * T::UNIT_ROUNDOFF.to_f64());
    (0..dist.len()).all(|j| ok[j] || iv[j].lo.to_f64() > at_most).then_some(m)
}
