//! The scalar abstraction that lets one body of tracer code run in f64 (the
//! CPU reference) and in f32 (the same arithmetic the WGSL shader does).
//!
//! glam keeps `DVec4`/`Vec4` as concrete twins; this trait names the pair for
//! each precision so the geometry steps are written once.

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};
use glam::{DMat4, DVec4, Mat4, Vec4};

/// A floating-point precision with its glam 4-vector and 4x4 matrix types.
pub trait Real:
    Copy
    + Debug
    + PartialOrd
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Homogeneous 4-vector (`DVec4` or `Vec4`).
    type V4: Copy
        + Debug
        + Send
        + Sync
        + Add<Output = Self::V4>
        + Sub<Output = Self::V4>
        + Mul<Self, Output = Self::V4>
        + Neg<Output = Self::V4>;
    /// 4x4 matrix acting on column vectors (`DMat4` or `Mat4`).
    type M4: Copy + Debug + Send + Sync + Mul<Self::V4, Output = Self::V4> + Mul<Output = Self::M4>;

    /// Machine epsilon of this precision.
    const EPSILON: Self;
    /// How far (as `|w|` of a copy's centre) a cell element accumulated in
    /// this precision still names its copy (see `crate::space::cells`).
    const CELL_HORIZON: f64;
    /// Converts from f64 (rounding for f32).
    fn of(x: f64) -> Self;
    /// Widens to f64.
    fn f64(self) -> f64;
    /// Builds a 4-vector.
    fn v4(x: Self, y: Self, z: Self, w: Self) -> Self::V4;
    /// The components of a 4-vector.
    fn xyzw(v: Self::V4) -> [Self; 4];
    /// Converts an f64 vector to this precision.
    fn v4_of(v: DVec4) -> Self::V4;
    /// Widens a vector to f64.
    fn v4_f64(v: Self::V4) -> DVec4;
    /// Converts an f64 matrix to this precision.
    fn m4_of(m: DMat4) -> Self::M4;
    /// Widens a matrix to f64.
    fn m4_f64(m: Self::M4) -> DMat4;
    /// Plain (Euclidean) dot product of 4-vectors: how a plane `n` meets a point.
    fn dot4(a: Self::V4, b: Self::V4) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Larger of two.
    fn max(self, other: Self) -> Self;
    /// Smaller of two.
    fn min(self, other: Self) -> Self;
    /// Sine.
    fn sin(self) -> Self;
    /// Cosine.
    fn cos(self) -> Self;
    /// Hyperbolic sine.
    fn sinh(self) -> Self;
    /// Hyperbolic cosine.
    fn cosh(self) -> Self;
    /// Arc tangent.
    fn atan(self) -> Self;
    /// Two-argument arc tangent of `self / x`.
    fn atan2(self, x: Self) -> Self;
    /// Inverse hyperbolic tangent.
    fn atanh(self) -> Self;
    /// Inverse hyperbolic sine.
    fn asinh(self) -> Self;
    /// Natural exponential.
    fn exp(self) -> Self;
    /// True when neither NaN nor infinite.
    fn is_finite(self) -> bool;
    /// `m^T v`: how a plane (covector) is carried back by `m`.
    fn transpose_mul(m: Self::M4, v: Self::V4) -> Self::V4;
}

macro_rules! impl_real {
    ($t:ty, $v:ty, $m:ty, $horizon:expr, $to_v:expr, $from_v:expr, $to_m:expr, $from_m:expr) => {
        impl Real for $t {
            type V4 = $v;
            type M4 = $m;
            const EPSILON: Self = <$t>::EPSILON;
            const CELL_HORIZON: f64 = $horizon;
            #[inline]
            fn of(x: f64) -> Self {
                x as $t
            }
            #[inline]
            fn f64(self) -> f64 {
                self as f64
            }
            #[inline]
            fn v4(x: Self, y: Self, z: Self, w: Self) -> $v {
                <$v>::new(x, y, z, w)
            }
            #[inline]
            fn xyzw(v: $v) -> [Self; 4] {
                v.to_array()
            }
            #[inline]
            fn v4_of(v: DVec4) -> $v {
                $to_v(v)
            }
            #[inline]
            fn v4_f64(v: $v) -> DVec4 {
                $from_v(v)
            }
            #[inline]
            fn m4_of(m: DMat4) -> $m {
                $to_m(m)
            }
            #[inline]
            fn m4_f64(m: $m) -> DMat4 {
                $from_m(m)
            }
            #[inline]
            fn dot4(a: $v, b: $v) -> Self {
                a.dot(b)
            }
            #[inline]
            fn transpose_mul(m: $m, v: $v) -> $v {
                m.transpose() * v
            }
            #[inline]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline]
            fn max(self, o: Self) -> Self {
                <$t>::max(self, o)
            }
            #[inline]
            fn min(self, o: Self) -> Self {
                <$t>::min(self, o)
            }
            #[inline]
            fn sin(self) -> Self {
                <$t>::sin(self)
            }
            #[inline]
            fn cos(self) -> Self {
                <$t>::cos(self)
            }
            #[inline]
            fn sinh(self) -> Self {
                <$t>::sinh(self)
            }
            #[inline]
            fn cosh(self) -> Self {
                <$t>::cosh(self)
            }
            #[inline]
            fn atan(self) -> Self {
                <$t>::atan(self)
            }
            #[inline]
            fn atan2(self, x: Self) -> Self {
                <$t>::atan2(self, x)
            }
            #[inline]
            fn atanh(self) -> Self {
                <$t>::atanh(self)
            }
            #[inline]
            fn asinh(self) -> Self {
                <$t>::asinh(self)
            }
            #[inline]
            fn exp(self) -> Self {
                <$t>::exp(self)
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
        }
    };
}

impl_real!(
    f64,
    DVec4,
    DMat4,
    // |w| 1e5: distance acosh(1e5) ~ 12.2 (f64 names copies well past it).
    1e5,
    |v: DVec4| v,
    |v: DVec4| v,
    |m: DMat4| m,
    |m: DMat4| m
);
impl_real!(
    f32,
    Vec4,
    Mat4,
    // A product of a few H3 matrices in f32 is off by about eps_32 |w|^2
    // in its centre, a good fraction of a grid step once |w| passes a few
    // hundred (distance ~6).
    200.0,
    |v: DVec4| v.as_vec4(),
    |v: Vec4| v.as_dvec4(),
    |m: DMat4| m.as_mat4(),
    |m: Mat4| m.as_dmat4()
);
