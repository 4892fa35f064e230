//! Structure-of-arrays batch containers.

use crate::{Error, Point, Real};

/// Lanes of the widest variant; SoA columns are padded to a multiple of this so that every
/// vector load of a batch, tail included, is in bounds and goes through the same code.
pub(crate) const PAD: usize = 8;

/// A batch of primitives with `K` points each (1 = points, 2 = segments, 3 = triangles), stored
/// as `3*K` padded coordinate columns (the paper's "SIMD layout").
///
/// # Example
/// ```
/// use tridist::TriangleBatch;
/// let tris = [[[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 5];
/// let batch = TriangleBatch::from_slice(&tris);
/// assert_eq!(batch.len(), 5);
/// assert_eq!(batch.get(4), Some(tris[4]));
/// ```
#[derive(Clone, Debug, PartialEq)]
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

impl<T: Real, const K: usize> Batch<T, K> {
    /// Builds a batch from plain primitives. Padding lanes repeat the last primitive.
    pub fn from_slice(prims: &[[Point<T>; K]]) -> Self {
        let len = prims.len();
        let cap = len.div_ceil(PAD) * PAD;
        let mut data = vec![T::ZERO; 3 * K * cap];
        for i in 0..cap {
            let Some(src) = prims.get(i.min(len.saturating_sub(1))) else { break };
            for (v, pt) in src.iter().enumerate() {
                for (c, &x) in pt.iter().enumerate() {
                    data[(3 * v + c) * cap + i] = x;
                }
            }
        }
        Batch { data, cap, len }
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

    pub(crate) fn src(&self) -> crate::driver::Src<'_, T> {
        crate::driver::Src::Soa { data: &self.data, cap: self.cap, base: 0, k: K }
    }
}

impl<T: Real> TriangleBatch<T> {
    /// Builds a triangle batch from an indexed mesh (vertex array + triangle indices).
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
        let mut tris = Vec::with_capacity(indices.len());
        for (t, idx) in indices.iter().enumerate() {
            let mut tri = [[T::ZERO; 3]; 3];
            for (k, &i) in idx.iter().enumerate() {
                tri[k] = *vertices.get(i as usize).ok_or(Error::IndexOutOfRange {
                    triangle: t,
                    index: i as usize,
                    vertices: vertices.len(),
                })?;
            }
            tris.push(tri);
        }
        Ok(Self::from_slice(&tris))
    }
}
