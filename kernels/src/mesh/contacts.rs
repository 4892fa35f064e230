//! [`Engine::mesh_contacts`]'s searcher ([`Contacts`]): every triangle pair within the margin,
//! decided by the kernels, optionally capped to the nearest; and its sorting and threads.

use super::bounds::reach;
use super::scratch::{Pending, Side};
use super::traverse::{check_finite, moved, root_visit, roots_apart, split, walk, Search};
use super::{Contact, Mesh, CONTACT_FLUSH, FLUSH};
use crate::algo::nodes::Limit;
use crate::engine::Outputs;
use crate::Engine;
use crate::Error;
use crate::Point;
use crate::Pose;
use crate::Query;
use crate::Real;

/// [`Engine::mesh_contacts`]: every pair within reach of the margin, answered by the full
/// triangle-triangle query ([`Query::TriTri`], distance and closest points in one run) and
/// kept when within the margin. That is [`Query::Within`]'s answer pair by pair: within-margin
/// is the full query thresholded (its box test skips only pairs the full query would put
/// beyond the margin; `algo/within.rs`, checked by the `within` fuzz target), and the pairs
/// reaching here passed a box test of their own, so its test would skip almost none of them
/// and hand the rest to the full query through the driver's escalation step (a copy of every
/// pair: 16 % of the contact query's time at the report's deepest pose, `perf`).
pub(super) struct Contacts<T> {
    pub(super) margin: f64,
    pub(super) tol: crate::Tolerance,
    /// [`Engine::mesh_contacts`]'s cap: once `found` holds twice that many, it is cut to the
    /// first `cap` of the contacts' order, whose last ([`Contacts::worst`]) then bounds the
    /// search, so `found` stays below `2 cap` plus a batch however many pairs are in reach.
    pub(super) cap: Option<usize>,
    /// The margin the search's limit reaches for: the margin, or less once the cap is full
    /// (derived from `worst` in [`Contacts::cut`] and kept: the limit runs per node pair).
    pub(super) bound: f64,
    /// The squared distance of the `cap`-th contact so far, once there are that many: no
    /// pair farther can be among the first `cap`.
    pub(super) worst: Option<T>,
    pub(super) found: Vec<Contact<T>>,
    pub(super) d: Vec<T>,
    pub(super) p: Vec<Point<T>>,
    pub(super) q: Vec<Point<T>>,
}

impl<T: Real> Contacts<T> {
    pub(super) fn new(margin: f64, tol: crate::Tolerance, cap: Option<usize>) -> Self {
        Contacts {
            margin,
            tol,
            cap,
            bound: margin,
            worst: None,
            found: Vec::new(),
            d: Vec::new(),
            p: Vec::new(),
            q: Vec::new(),
        }
    }

    /// Keeps the first `cap` contacts found so far once there are twice that many.
    pub(super) fn cut(&mut self) {
        let Some(cap) = self.cap else { return };
        if self.found.len() < 2 * cap.max(1) {
            return;
        }
        self.found = sorted(self.found.iter());
        self.found.truncate(cap);
        if let Some(last) = self.found.last() {
            self.worst = Some(last.sqdist);
            // node pairs beyond reach of the cap-th contact's distance cannot hold a contact
            // ordered before it (rounded up: the limit must not cut a tie)
            self.bound = self.bound.min(last.sqdist.to_f64().sqrt().next_up());
        }
    }
}

impl<T: Real> Search<T> for Contacts<T> {
    fn limit(&self) -> Limit {
        reach::<T>(&self.tol, self.bound)
    }
    fn batch(&self) -> usize {
        self.cap.map_or(CONTACT_FLUSH, |c| c.clamp(FLUSH, CONTACT_FLUSH))
    }
    fn flush(&mut self, e: &Engine, pend: &Pending<T>) -> Result<bool, Error> {
        let n = pend.ids.len();
        self.d.clear();
        self.d.resize(n, T::ZERO);
        self.p.clear();
        self.p.resize(n, [T::ZERO; 3]);
        self.q.clear();
        self.q.resize(n, [T::ZERO; 3]);
        e.run(
            Query::TriTri,
            &pend.a,
            &pend.b,
            Outputs::new().sqdist(&mut self.d).points(&mut self.p, &mut self.q),
        )?;
        let m2 = margin_sq::<T>(self.margin);
        let worst = self.worst.unwrap_or(m2);
        for k in 0..n {
            check_finite(self.d[k])?;
            if self.d[k] <= m2 && self.d[k] <= worst {
                let (i, j) = pend.ids[k];
                self.found.push(Contact {
                    tri_a: i as usize,
                    tri_b: j as usize,
                    sqdist: self.d[k],
                    p: self.p[k],
                    q: self.q[k],
                });
            }
        }
        self.cut();
        Ok(false)
    }
}

/// The squared margin a triangle pair's squared distance is compared with, in the working
/// precision: the one threshold of the contact query and the clearance check, so that they
/// decide every pair alike.
pub(super) fn margin_sq<T: Real>(margin: f64) -> T {
    let m = T::from_f64(margin);
    m * m
}

/// The order of [`Engine::mesh_contacts`] as an integer key: squared distance (as
/// `f64::total_cmp` orders it), then triangle numbers (each below 2^32: the tree numbers
/// triangles in `u32`). Distinct for distinct pairs.
pub(super) fn contact_key<T: Real>(c: &Contact<T>) -> (u64, u64) {
    let u = c.sqdist.to_f64().to_bits();
    let d = if u >> 63 == 1 { !u } else { u | 1 << 63 };
    (d, (c.tri_a as u64) << 32 | c.tri_b as u64)
}

/// `contacts` in [`contact_key`] order: the keys (with a reference each) sorted, then the
/// contacts copied in their order, so the sort moves 24 bytes per contact instead of the
/// contact (72 bytes in f64; `perf` of `spin mesh contacts 5 f64 2 3` had the sort of the
/// contacts themselves at 11 % of the two threads' time).
pub(super) fn sorted<'c, T: Real>(contacts: impl Iterator<Item = &'c Contact<T>>) -> Vec<Contact<T>> {
    sorted_keyed(contacts.map(|c| (contact_key(c), c)).collect(), 0)
}

/// [`sorted`] on contacts whose keys are already computed, into a vector with room for at
/// least `room` contacts.
pub(super) fn sorted_keyed<T: Real>(
    mut keys: Vec<((u64, u64), &Contact<T>)>,
    room: usize,
) -> Vec<Contact<T>> {
    keys.sort_unstable_by_key(|k| k.0);
    let mut out = Vec::with_capacity(room.max(keys.len()));
    out.extend(keys.iter().map(|k| *k.1));
    out
}

/// [`Engine::mesh_contacts`] on the engine's threads: the node pairs are split breadth first
/// into pieces (at least 32 per thread where the trees allow), each walked on its own by a
/// thread with its own moved bounds and leaves; the pieces' contacts are then sorted on the
/// threads too ([`sort_threaded`]), so the answer is the single-threaded one, in its order.
pub(super) fn contacts_threaded<T: Real>(
    e: &Engine,
    a: &Mesh<T>,
    pa: &Pose<T>,
    b: &Mesh<T>,
    pb: &Pose<T>,
    state: &(impl Fn() -> Contacts<T> + Sync),
) -> Result<Vec<Contact<T>>, Error> {
    let e = &e.for_small_batches();
    pa.check()?;
    pb.check()?;
    if a.is_empty() || b.is_empty() {
        return Ok(Vec::new());
    }
    let (ma, mb) = (moved(a, pa)?, moved(b, pb)?);
    let mut probe = state();
    if roots_apart((a, &ma), (b, &mb), &mut probe) {
        return Ok(Vec::new());
    }
    let (mut sa, mut sb) = (Side::new(a, pa, ma, e.isa()), Side::new(b, pb, mb, e.isa()));
    let root = root_visit(e.isa(), &mut sa, &mut sb, &probe);
    let pieces = split(e.isa(), &mut sa, &mut sb, root, &probe, 32 * e.thread_count());
    if pieces.is_empty() {
        // pruned at the root: no thread to wake
        return Ok(Vec::new());
    }
    let single = e.threads(1);
    let found = crate::engine::par_map_init(
        e.thread_count(),
        &pieces,
        || (Side::new(a, pa, ma, e.isa()), Side::new(b, pb, mb, e.isa())),
        |(sa, sb), &v| {
            let mut s = state();
            walk(&single, sa, sb, vec![v], &mut s)?;
            Ok(s.found)
        },
    );
    let parts = found.into_iter().collect::<Result<Vec<_>, Error>>()?;
    Ok(sort_threaded(e.thread_count(), parts))
}

/// The contacts of all `parts` in [`contact_key`] order, sorted on `threads` threads:
/// splitters drawn from a regular sample of the keys cut the order into one range per
/// thread; each part's keys are computed once and dealt to their ranges, and each range is
/// gathered from every part and sorted on its own (a sample sort). The keys are distinct (no
/// two contacts share their triangle pair), so the result does not depend on how the contacts
/// were split. (Merging the sorted pieces on the calling thread was 13 % of its time at the
/// report's deepest pose, and capped two threads at 1.55x one, `perf`; every range's thread
/// computing and filtering the keys of all contacts left the sort at 1.42x.)
pub(super) fn sort_threaded<T: Real>(threads: usize, parts: Vec<Vec<Contact<T>>>) -> Vec<Contact<T>> {
    let total: usize = parts.iter().map(Vec::len).sum();
    if threads <= 1 || total < 4096 {
        return sorted(parts.iter().flatten());
    }
    // a regular sample, sorted; its quantiles are the splitters
    let step = (total / (SAMPLE_PER_RANGE * threads)).max(1);
    let mut sample: Vec<(u64, u64)> = parts.iter().flatten().step_by(step).map(contact_key).collect();
    sample.sort_unstable();
    let cuts: Vec<(u64, u64)> = (1..threads).map(|i| sample[i * sample.len() / threads]).collect();
    // range r holds the contacts c with cuts[r - 1] <= key(c) < cuts[r]
    // (by index: the dealt keys borrow from `parts`, not from the item)
    let which: Vec<usize> = (0..parts.len()).collect();
    let dealt = crate::engine::par_map_init(
        threads,
        &which,
        || (),
        |_, &i| {
            let part = &parts[i];
            let mut to: Vec<Vec<_>> =
                (0..threads).map(|_| Vec::with_capacity(part.len() / threads + 16)).collect();
            for c in part {
                let k = contact_key(c);
                to[cuts.partition_point(|x| *x <= k)].push((k, c));
            }
            to
        },
    );
    let ranges: Vec<usize> = (0..threads).collect();
    let sorted = crate::engine::par_map_init(
        threads,
        &ranges,
        || (),
        |_, &r| {
            let mut keys = Vec::with_capacity(dealt.iter().map(|d| d[r].len()).sum());
            for d in &dealt {
                keys.extend_from_slice(&d[r]);
            }
            // the first range's vector becomes the answer: room for all
            sorted_keyed(keys, if r == 0 { total } else { 0 })
        },
    );
    let mut ranges = sorted.into_iter();
    let mut all = ranges.next().unwrap_or_default();
    for s in ranges {
        all.extend(s);
    }
    all
}

/// Sampled keys per range of [`sort_threaded`]: a splitter's place in the order varies by
/// about `1 / (2 sqrt(SAMPLE_PER_RANGE * threads))` of the total (the standard deviation of a
/// sample's median), and the threads wait for the largest range. (At 64 per range, the two
/// ranges of the report's deepest pose held 24,995 and 30,471 contacts.)
pub(super) const SAMPLE_PER_RANGE: usize = 512;
