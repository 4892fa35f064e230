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

    /// Rotation by `angle` radians about `axis` (Rodrigues), then translation `t`. The axis
    /// need not be a unit vector: any finite non-zero length is normalised, tiny and huge ones
    /// included (where its squares would underflow or overflow, it is first divided by its
    /// largest component). Computed in f64 and rounded to `T`.
    ///
    /// # Errors
    /// [`Error::InvalidRotation`] for a zero or non-finite axis or a non-finite angle (a zero
    /// axis names no rotation: write [`Pose::translation`] for none), [`Error::InvalidPose`]
    /// for a non-finite translation.
    pub fn from_axis_angle(axis: [T; 3], angle: f64, t: [T; 3]) -> Result<Self, Error> {
        let a = axis.map(|x| x.to_f64());
        let big = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if !angle.is_finite() || a.iter().any(|x| !x.is_finite()) || big == 0.0 {
            return Err(Error::InvalidRotation);
        }
        if t.iter().any(|x| !x.is_finite()) {
            return Err(Error::InvalidPose);
        }
        // scaled only where its squares could underflow or overflow (elsewhere the same bits
        // as the plain normalisation)
        let a = if (1e-150..=1e150).contains(&big) { a } else { a.map(|x| x / big) };
        let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let a = a.map(|x| x / n);
        let (s, c) = angle.sin_cos();
        let k = 1.0 - c;
        let m = [
            [c + a[0] * a[0] * k, a[0] * a[1] * k - a[2] * s, a[0] * a[2] * k + a[1] * s],
            [a[1] * a[0] * k + a[2] * s, c + a[1] * a[1] * k, a[1] * a[2] * k - a[0] * s],
            [a[2] * a[0] * k - a[1] * s, a[2] * a[1] * k + a[0] * s, c + a[2] * a[2] * k],
        ];
        Ok(Pose { rotation: m.map(|r| r.map(T::from_f64)), translation: t })
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A quarter turn about x moves y to z and z to -y, whatever the axis' length: tiny and
    /// huge axes (whose squares underflow or overflow) and a subnormal one included.
    #[test]
    fn axes_of_any_finite_length_give_the_same_rotation() {
        for scale in [1.0, 3.0, 1e-200, 1e-310, 1e200, f64::MAX] {
            let p = Pose::from_axis_angle([scale, 0.0, 0.0], core::f64::consts::FRAC_PI_2, [0.0; 3]).unwrap();
            for (x, want) in [([0.0, 1.0, 0.0], [0.0, 0.0, 1.0]), ([0.0, 0.0, 1.0], [0.0, -1.0, 0.0])] {
                let got = p.apply(x);
                let err = (0..3).map(|i| (got[i] - want[i]).abs()).fold(0.0, f64::max);
                assert!(err <= 4.0 * f64::EPSILON, "axis length {scale}: {x:?} -> {got:?}");
            }
        }
        // a general axis: the matrix is orthonormal and keeps the axis fixed
        let axis = [1e-170, -2e-170, 3e-170];
        let p = Pose::from_axis_angle(axis, 1.3, [0.0; 3]).unwrap();
        let r = p.rotation;
        for i in 0..3 {
            for j in 0..3 {
                let dot: f64 = (0..3).map(|k| r[i][k] * r[j][k]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((dot - want).abs() <= 8.0 * f64::EPSILON, "rows {i} {j}: {dot}");
            }
        }
        let fixed = p.apply([1.0, -2.0, 3.0]);
        assert!((0..3).all(|i| (fixed[i] - [1.0, -2.0, 3.0][i]).abs() <= 16.0 * f64::EPSILON), "{fixed:?}");
        // and in f32, whose axis is widened first
        let p = Pose::<f32>::from_axis_angle([0.0, 0.0, 1e-30], core::f64::consts::PI, [0.0; 3]).unwrap();
        let got = p.apply([1.0, 0.0, 0.0]);
        assert!((got[0] + 1.0).abs() <= 2.0 * f32::EPSILON && got[1].abs() <= 2.0 * f32::EPSILON, "{got:?}");
    }

    /// An axis that names no direction, or an angle or translation that is not a number, is an
    /// error, never a rotation about some other axis.
    #[test]
    fn axes_that_name_no_direction_are_errors() {
        let bad_axes =
            [[0.0; 3], [f64::NAN, 1.0, 0.0], [f64::INFINITY, 0.0, 0.0], [1.0, f64::NEG_INFINITY, 1.0]];
        for axis in bad_axes {
            assert_eq!(Pose::from_axis_angle(axis, 0.5, [0.0; 3]), Err(Error::InvalidRotation), "{axis:?}");
            assert_eq!(Pose::from_axis_angle(axis, 0.0, [0.0; 3]), Err(Error::InvalidRotation), "{axis:?}");
        }
        for angle in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(Pose::from_axis_angle([0.0, 0.0, 1.0], angle, [0.0; 3]), Err(Error::InvalidRotation));
        }
        for t in [[f64::NAN, 0.0, 0.0], [0.0, 0.0, f64::INFINITY]] {
            assert_eq!(Pose::from_axis_angle([0.0, 0.0, 1.0], 0.5, t), Err(Error::InvalidPose), "{t:?}");
        }
        assert_eq!(Pose::<f32>::from_axis_angle([0.0; 3], 0.5, [0.0; 3]), Err(Error::InvalidRotation));
    }
}
