//! Structure-of-arrays batch containers, updated in place (a physics loop moves its batch
//! every frame instead of rebuilding it).

use crate::pose::{points, AsPoint};
use crate::{Error, Point, Pose, Real};

/// Lanes of the widest variant; SoA columns are padded to a multiple of this so that every
/// vector load of a batch, tail included, is in bounds and goes through the same code.
pub(crate) const PAD: usize = crate::lanes::MAX_LANES;

/// A batch of primitives with `K` points each (1 = points, 2 = segments, 3 = triangles), stored
/// as `3*K` padded coordinate columns (Shellshear & Ytterlid's "SIMD layout").
///
/// Invariant: the column stride `cap` is a multiple of the widest vector (16 lanes) and at
/// least the length rounded up to a multiple of it, and the lanes from the length to that
/// multiple repeat the last primitive, so every vector load of a query is in bounds and finite.
///
/// # Example
/// ```
/// use tridist::{Pose, TriangleBatch};
/// let t = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let mut batch = TriangleBatch::from_slice(&[t; 5]);
/// batch.push([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]);
/// batch.set(0, [[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [2.0, 1.0, 0.0]]).unwrap();
/// batch.transform(&Pose::translation([0.0, 0.0, 10.0])).unwrap();
/// assert_eq!(batch.len(), 6);
/// assert_eq!(batch.get(4), Some([[0.0, 0.0, 10.0], [1.0, 0.0, 10.0], [0.0, 1.0, 10.0]]));
/// ```
#[derive(Clone, Debug)]
pub struct Batch<T, const K: usize> {
    data: Vec<T>,
    cap: usize,
    len: usize,
}

/// Triangles in SoA columns.
pub type TriangleBatch<T> = Batch<T, 3>;
/// Segments in SoA columns.
pub type SegmentBatch<T> = Batch<T, 2>;
/// Points in SoA columns.
pub type PointBatch<T> = Batch<T, 1>;

/// Equal when they hold the same primitives (whatever their capacity).
impl<T: Real, const K: usize> PartialEq for Batch<T, K> {
    fn eq(&self, o: &Self) -> bool {
        self.len == o.len && self.iter().eq(o.iter())
    }
}

impl<T: Real, const K: usize> Default for Batch<T, K> {
    fn default() -> Self {
        Batch::with_capacity(0)
    }
}

impl<T: Real, const K: usize> Batch<T, K> {
    /// An empty batch with room for `n` primitives.
    pub fn with_capacity(n: usize) -> Self {
        let cap = n.div_ceil(PAD).max(1) * PAD;
        Batch { data: vec![T::ZERO; 3 * K * cap], cap, len: 0 }
    }

    /// Builds a batch from plain primitives.
    pub fn from_slice(prims: &[[Point<T>; K]]) -> Self {
        let mut b = Batch::with_capacity(prims.len());
        for (i, p) in prims.iter().enumerate() {
            b.write(i, p);
        }
        b.len = prims.len();
        b.pad();
        b
    }

    /// Builds a batch from primitives of any point type ([`AsPoint`]: arrays, glam, mint).
    pub fn from_points<P: AsPoint<T>>(prims: impl IntoIterator<Item = [P; K]>) -> Self {
        let mut b = Batch::with_capacity(0);
        b.extend(prims.into_iter().map(|p| points(&p)));
        b
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when the batch holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Primitive `i` as plain points, or `None` past the end.
    pub fn get(&self, i: usize) -> Option<[Point<T>; K]> {
        if i >= self.len {
            return None;
        }
        let mut out = [[T::ZERO; 3]; K];
        for (v, pt) in out.iter_mut().enumerate() {
            for (c, x) in pt.iter_mut().enumerate() {
                *x = self.data[(3 * v + c) * self.cap + i];
            }
        }
        Some(out)
    }

    /// Every primitive, in order.
    pub fn iter(&self) -> impl Iterator<Item = [Point<T>; K]> + '_ {
        (0..self.len).filter_map(|i| self.get(i))
    }

    /// Replaces primitive `i`.
    ///
    /// # Errors
    /// [`Error::LengthMismatch`] when `i` is not below the length.
    pub fn set(&mut self, i: usize, prim: [Point<T>; K]) -> Result<(), Error> {
        if i >= self.len {
            return Err(Error::LengthMismatch { what: "index", expected: self.len, found: i });
        }
        self.write(i, &prim);
        if i + 1 == self.len {
            self.pad();
        }
        Ok(())
    }

    /// Appends a primitive (amortised O(1): the columns double when full).
    pub fn push(&mut self, prim: [Point<T>; K]) {
        if self.len + 1 > self.cap {
            self.grow((self.cap * 2).max(self.len + 1));
        }
        self.write(self.len, &prim);
        self.len += 1;
        self.pad();
    }

    /// Appends primitives.
    pub fn extend(&mut self, prims: impl IntoIterator<Item = [Point<T>; K]>) {
        let it = prims.into_iter();
        let (lo, _) = it.size_hint();
        if self.len + lo > self.cap {
            self.grow(self.len + lo);
        }
        for p in it {
            if self.len + 1 > self.cap {
                self.grow((self.cap * 2).max(self.len + 1));
            }
            self.write(self.len, &p);
            self.len += 1;
        }
        self.pad();
    }

    /// Keeps the first `n` primitives (no reallocation).
    pub fn truncate(&mut self, n: usize) {
        if n < self.len {
            self.len = n;
            self.pad();
        }
    }

    /// Removes every primitive (keeps the capacity).
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// Moves every point by `pose`, in place.
    ///
    /// # Errors
    /// [`Error::InvalidPose`] for a non-finite pose (the batch is left unchanged).
    pub fn transform(&mut self, pose: &Pose<T>) -> Result<(), Error> {
        pose.check()?;
        let lanes = self.len.div_ceil(PAD) * PAD;
        for v in 0..K {
            for i in 0..lanes {
                let p = [0, 1, 2].map(|c| self.data[(3 * v + c) * self.cap + i]);
                let q = pose.apply(p);
                for (c, x) in q.into_iter().enumerate() {
                    self.data[(3 * v + c) * self.cap + i] = x;
                }
            }
        }
        Ok(())
    }

    /// Makes `self` the primitives of `src` moved by `pose`, reusing `self`'s storage (it only
    /// grows when `src` is longer than anything it held): the per-frame update of a body whose
    /// local-frame primitives stay in `src`.
    ///
    /// # Errors
    /// [`Error::InvalidPose`] for a non-finite pose (`self` is left unchanged).
    pub fn transform_from(&mut self, src: &Batch<T, K>, pose: &Pose<T>) -> Result<(), Error> {
        pose.check()?;
        if src.len > self.cap {
            *self = Batch::with_capacity(src.len);
        }
        self.len = src.len;
        let lanes = src.len.div_ceil(PAD) * PAD;
        for v in 0..K {
            for i in 0..lanes {
                let p = [0, 1, 2].map(|c| src.data[(3 * v + c) * src.cap + i]);
                let q = pose.apply(p);
                for (c, x) in q.into_iter().enumerate() {
                    self.data[(3 * v + c) * self.cap + i] = x;
                }
            }
        }
        Ok(())
    }

    fn write(&mut self, i: usize, prim: &[Point<T>; K]) {
        for (v, pt) in prim.iter().enumerate() {
            for (c, &x) in pt.iter().enumerate() {
                self.data[(3 * v + c) * self.cap + i] = x;
            }
        }
    }

    /// Restores the padding invariant after the last primitive changed.
    fn pad(&mut self) {
        if self.len == 0 {
            return;
        }
        let last = self.len - 1;
        let end = self.len.div_ceil(PAD) * PAD;
        for j in 0..3 * K {
            let x = self.data[j * self.cap + last];
            for i in self.len..end {
                self.data[j * self.cap + i] = x;
            }
        }
    }

    fn grow(&mut self, n: usize) {
        let cap = n.div_ceil(PAD) * PAD;
        let mut data = vec![T::ZERO; 3 * K * cap];
        for j in 0..3 * K {
            data[j * cap..j * cap + self.len]
                .copy_from_slice(&self.data[j * self.cap..j * self.cap + self.len]);
        }
        self.data = data;
        self.cap = cap;
    }

    /// The padded columns and their capacity: coordinate `j` (0..3K) of primitive `i` is
    /// `columns()[j * cap + i]`, for the batch driver.
    pub(crate) fn columns(&self) -> (&[T], usize) {
        (&self.data, self.cap)
    }
}

impl<T: Real> TriangleBatch<T> {
    /// Builds a triangle batch from an indexed mesh (vertex array + triangle indices), filling
    /// the columns directly (one allocation).
    ///
    /// # Errors
    /// [`Error::IndexOutOfRange`] when an index does not name a vertex.
    ///
    /// # Example
    /// ```
    /// use tridist::TriangleBatch;
    /// let v = [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
    /// let b = TriangleBatch::from_mesh(&v, &[[0, 1, 2], [1, 3, 2]]).unwrap();
    /// assert_eq!(b.get(1), Some([v[1], v[3], v[2]]));
    /// assert!(TriangleBatch::from_mesh(&v, &[[0, 1, 9]]).is_err());
    /// ```
    pub fn from_mesh(vertices: &[Point<T>], indices: &[[u32; 3]]) -> Result<Self, Error> {
        let mut b = Batch::with_capacity(indices.len());
        for (t, idx) in indices.iter().enumerate() {
            let mut tri = [[T::ZERO; 3]; 3];
            for (k, &i) in idx.iter().enumerate() {
                tri[k] = *vertices.get(i as usize).ok_or(Error::IndexOutOfRange {
                    triangle: t,
                    index: i as usize,
                    vertices: vertices.len(),
                })?;
            }
            b.write(t, &tri);
        }
        b.len = indices.len();
        b.pad();
        Ok(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(z: f64) -> [Point<f64>; 3] {
        [[0.0, 0.0, z], [1.0, 0.0, z], [0.0, 1.0, z]]
    }

    /// The padding invariant: lanes from the length to the next multiple of [`PAD`] repeat the last.
    fn padded(b: &Batch<f64, 3>) -> bool {
        let end = b.len.div_ceil(PAD) * PAD;
        b.len == 0
            || (0..9).all(|j| (b.len..end).all(|i| b.data[j * b.cap + i] == b.data[j * b.cap + b.len - 1]))
    }

    #[test]
    fn updates_keep_contents_and_padding() {
        let mut b = Batch::<f64, 3>::from_slice(&[tri(0.0), tri(1.0)]);
        assert!(padded(&b));
        for k in 0..20 {
            b.push(tri(2.0 + k as f64));
            assert!(padded(&b), "push {k}");
        }
        assert_eq!(b.len(), 22);
        assert_eq!(b.get(21), Some(tri(21.0)));
        assert_eq!(b.get(1), Some(tri(1.0)));
        b.set(21, tri(-1.0)).unwrap();
        assert!(padded(&b));
        assert_eq!(
            b.set(22, tri(0.0)),
            Err(Error::LengthMismatch { what: "index", expected: 22, found: 22 })
        );
        b.truncate(9);
        assert!(padded(&b));
        assert_eq!(b.iter().count(), 9);
        b.extend([tri(5.0), tri(6.0)]);
        assert_eq!(b.get(10), Some(tri(6.0)));
        assert!(padded(&b));
        b.clear();
        assert!(b.is_empty());
    }

    #[test]
    fn transforms_move_every_point_and_reject_bad_poses() {
        let src = Batch::<f64, 3>::from_slice(&[tri(0.0), tri(1.0), tri(2.0)]);
        let pose =
            Pose::from_axis_angle([0.0, 0.0, 1.0], core::f64::consts::FRAC_PI_2, [1.0, 2.0, 3.0]).unwrap();
        let mut dst = Batch::default();
        dst.transform_from(&src, &pose).unwrap();
        for i in 0..3 {
            let want = src.get(i).unwrap().map(|p| pose.apply(p));
            assert_eq!(dst.get(i), Some(want));
        }
        assert!(padded(&dst));
        let mut moved = src.clone();
        moved.transform(&pose).unwrap();
        assert_eq!(moved, {
            let mut x = Batch::with_capacity(3);
            x.transform_from(&src, &pose).unwrap();
            x
        });
        let bad = Pose { translation: [f64::NAN, 0.0, 0.0], ..Pose::identity() };
        assert_eq!(moved.transform(&bad), Err(Error::InvalidPose));
        assert_eq!(dst.transform_from(&src, &bad), Err(Error::InvalidPose));
    }
}
