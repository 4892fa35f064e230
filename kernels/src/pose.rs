//! Rigid poses (rotation + translation) and conversion of other crates' vector types.

use crate::{Error, Point, Real};

/// A rigid pose: `x -> rotation * x + translation`, the rotation as a row-major 3x3 matrix.
/// Used to move batches in place ([`crate::Batch::transform`]) and meshes.
///
/// The matrix is applied as given (no orthonormality check): a scaled or sheared matrix moves
/// points accordingly. The transform is evaluated in the working precision (one rounding per
/// multiply-add): the transformed coordinates are within about `3 u` times the
/// transformed point's magnitude of the exact transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose<T> {
    /// Row-major rotation matrix.
    pub rotation: [[T; 3]; 3],
    /// Translation, applied after the rotation.
    pub translation: [T; 3],
}

impl<T: Real> Pose<T> {
    /// The identity.
    pub fn identity() -> Self {
        let (o, z) = (T::ONE, T::ZERO);
        Pose { rotation: [[o, z, z], [z, o, z], [z, z, o]], translation: [z; 3] }
    }

    /// A pure translation.
    pub fn translation(t: [T; 3]) -> Self {
        Pose { translation: t, ..Pose::identity() }
    }

    /// Rotation by `angle` radians about the unit `axis` (Rodrigues), then translation `t`.
    /// Computed in f64 and rounded.
    pub fn from_axis_angle(axis: [T; 3], angle: f64, t: [T; 3]) -> Self {
        let a = axis.map(|x| x.to_f64());
        let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let a = if n > 0.0 { a.map(|x| x / n) } else { [0.0, 0.0, 1.0] };
        let (s, c) = angle.sin_cos();
        let k = 1.0 - c;
        let m = [
            [c + a[0] * a[0] * k, a[0] * a[1] * k - a[2] * s, a[0] * a[2] * k + a[1] * s],
            [a[1] * a[0] * k + a[2] * s, c + a[1] * a[1] * k, a[1] * a[2] * k - a[0] * s],
            [a[2] * a[0] * k - a[1] * s, a[2] * a[1] * k + a[0] * s, c + a[2] * a[2] * k],
        ];
        Pose { rotation: m.map(|r| r.map(T::from_f64)), translation: t }
    }

    /// Applies the pose to a point.
    #[inline]
    pub fn apply(&self, p: Point<T>) -> Point<T> {
        let r = &self.rotation;
        [0, 1, 2].map(|i| r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2] + self.translation[i])
    }

    /// The pose `self` after `first` (apply `first`, then `self`), computed in f64.
    pub fn compose(&self, first: &Pose<T>) -> Pose<T> {
        let a = self.rotation.map(|r| r.map(|x| x.to_f64()));
        let b = first.rotation.map(|r| r.map(|x| x.to_f64()));
        let m = [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum::<f64>()));
        let t = [0, 1, 2].map(|i| {
            (0..3).map(|k| a[i][k] * first.translation[k].to_f64()).sum::<f64>()
                + self.translation[i].to_f64()
        });
        Pose { rotation: m.map(|r| r.map(T::from_f64)), translation: t.map(T::from_f64) }
    }

    /// `Err(Error::InvalidPose)` unless every entry is finite.
    pub fn check(&self) -> Result<(), Error> {
        let ok = self.rotation.iter().flatten().chain(self.translation.iter()).all(|x| x.is_finite());
        if ok {
            Ok(())
        } else {
            Err(Error::InvalidPose)
        }
    }
}

/// Anything that is a 3-D point in precision `T`: `[T; 3]`, and with the features of the same
/// names, `glam::Vec3`/`Vec3A` (f32), `glam::DVec3` (f64), `mint::Point3<T>` and
/// `mint::Vector3<T>`. Single queries and [`crate::Batch::from_points`] take any of them.
pub trait AsPoint<T>: Copy {
    /// The point as `[x, y, z]`.
    fn to_point(self) -> Point<T>;
}

impl<T: Real> AsPoint<T> for [T; 3] {
    #[inline]
    fn to_point(self) -> Point<T> {
        self
    }
}

#[cfg(feature = "glam")]
impl AsPoint<f32> for glam::Vec3 {
    #[inline]
    fn to_point(self) -> Point<f32> {
        self.to_array()
    }
}

#[cfg(feature = "glam")]
impl AsPoint<f32> for glam::Vec3A {
    #[inline]
    fn to_point(self) -> Point<f32> {
        self.to_array()
    }
}

#[cfg(feature = "glam")]
impl AsPoint<f64> for glam::DVec3 {
    #[inline]
    fn to_point(self) -> Point<f64> {
        self.to_array()
    }
}

#[cfg(feature = "mint")]
impl<T: Real> AsPoint<T> for mint::Point3<T> {
    #[inline]
    fn to_point(self) -> Point<T> {
        [self.x, self.y, self.z]
    }
}

#[cfg(feature = "mint")]
impl<T: Real> AsPoint<T> for mint::Vector3<T> {
    #[inline]
    fn to_point(self) -> Point<T> {
        [self.x, self.y, self.z]
    }
}

/// `[P; K]` to points.
#[inline]
pub(crate) fn points<T, P: AsPoint<T>, const K: usize>(p: &[P; K]) -> [Point<T>; K] {
    p.map(|x| x.to_point())
}
