//! Four f64 values worked on together, one per independent problem, with the few operations
//! the side-by-side solvers need (`Vector`). Two implementations: `Lanes`, plain arrays that
//! any CPU runs, and on x86-64 `Avx2`, one 256-bit register, for the CPUs that have AVX2
//! (`Isa::widest`). Both do the same IEEE operations in the same order as one lane alone, so
//! every lane's result is bit for bit what a scalar loop would give.

use std::ops::{Add, Div, Mul, Sub};

/// Values side by side: one per lane.
pub const WIDTH: usize = 4;

/// Four f64 as they lie in memory (aligned for one vector load).
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(32))]
pub struct Lanes(pub [f64; WIDTH]);

impl Lanes {
    /// Every lane 0.
    pub const ZERO: Self = Self([0.0; WIDTH]);
}

/// Four f64 in registers and what the solvers do with them; `Mask` is a lane-wise truth.
pub trait Vector:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// A lane-wise truth.
    type Mask: Copy;
    /// v in every lane.
    fn splat(v: f64) -> Self;
    /// The lanes from memory.
    fn load(lanes: Lanes) -> Self;
    /// The lanes to memory.
    fn store(self) -> Lanes;
    /// |v| lane by lane.
    fn abs(self) -> Self;
    /// The smaller lane by lane, `other` where either is NaN (as the vector instruction).
    fn min(self, other: Self) -> Self;
    /// The larger lane by lane, `other` where either is NaN.
    fn max(self, other: Self) -> Self;
    /// self > other lane by lane.
    fn gt(self, other: Self) -> Self::Mask;
    /// self >= other lane by lane.
    fn ge(self, other: Self) -> Self::Mask;
    /// a and b.
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// !a and b.
    fn and_not(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// `yes` where `mask` is set, `no` elsewhere.
    fn select(mask: Self::Mask, yes: Self, no: Self) -> Self;
}

impl Lanes {
    #[inline(always)]
    fn zip(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        Self(std::array::from_fn(|l| f(self.0[l], other.0[l])))
    }

    #[inline(always)]
    fn compare(self, other: Self, f: impl Fn(f64, f64) -> bool) -> [bool; WIDTH] {
        std::array::from_fn(|l| f(self.0[l], other.0[l]))
    }
}

macro_rules! lanes_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for Lanes {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                self.zip(other, |a, b| a $op b)
            }
        }
    };
}

lanes_op!(Add, add, +);
lanes_op!(Sub, sub, -);
lanes_op!(Mul, mul, *);
lanes_op!(Div, div, /);

impl Vector for Lanes {
    type Mask = [bool; WIDTH];

    #[inline(always)]
    fn splat(v: f64) -> Self {
        Self([v; WIDTH])
    }

    #[inline(always)]
    fn load(lanes: Lanes) -> Self {
        lanes
    }

    #[inline(always)]
    fn store(self) -> Lanes {
        self
    }

    #[inline(always)]
    fn abs(self) -> Self {
        Self(self.0.map(f64::abs))
    }

    #[inline(always)]
    fn min(self, other: Self) -> Self {
        self.zip(other, |a, b| if a < b { a } else { b })
    }

    #[inline(always)]
    fn max(self, other: Self) -> Self {
        self.zip(other, |a, b| if a > b { a } else { b })
    }

    #[inline(always)]
    fn gt(self, other: Self) -> Self::Mask {
        self.compare(other, |a, b| a > b)
    }

    #[inline(always)]
    fn ge(self, other: Self) -> Self::Mask {
        self.compare(other, |a, b| a >= b)
    }

    #[inline(always)]
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask {
        std::array::from_fn(|l| a[l] && b[l])
    }

    #[inline(always)]
    fn and_not(a: Self::Mask, b: Self::Mask) -> Self::Mask {
        std::array::from_fn(|l| !a[l] && b[l])
    }

    #[inline(always)]
    fn select(mask: Self::Mask, yes: Self, no: Self) -> Self {
        Self(std::array::from_fn(|l| {
            if mask[l] { yes.0[l] } else { no.0[l] }
        }))
    }
}

#[cfg(target_arch = "x86_64")]
pub use avx2::Avx2;

/// `Vector` in one AVX register.
///
/// Safety: an `Avx2` may only be made where the CPU has AVX2. The type is named only by
/// `smoothing::fit_avx2` and `fit_avx512`, compiled for AVX2 and called only where
/// `Isa::widest` found it (and the tests, under the same check); every operation here is
/// inlined into them.
///
/// Speed: a closure is a function of its own, compiled for the caller's instructions only
/// where it is inlined. Small ones are (`lu.map(V::store)`); one that holds a whole sweep
/// need not be (`bool::then(|| group.evaluate::<V>(..))` was not, and every operation in it
/// became a call, many times slower: docs/benchmarks.md). Call the sweeps directly.
#[cfg(target_arch = "x86_64")]
#[allow(
    unsafe_code,
    reason = "AVX intrinsics, run only where the CPU has AVX2 (see the module's doc)"
)]
mod avx2 {
    use super::{Lanes, Vector};
    use std::arch::x86_64::{
        __m256d, _CMP_GE_OQ, _CMP_GT_OQ, _mm256_and_pd, _mm256_andnot_pd, _mm256_blendv_pd,
        _mm256_cmp_pd, _mm256_div_pd, _mm256_max_pd, _mm256_min_pd, _mm256_mul_pd, _mm256_set1_pd,
        _mm256_sub_pd,
    };
    use std::ops::{Add, Div, Mul, Sub};

    /// Four lanes in one AVX register.
    #[derive(Clone, Copy, Debug)]
    pub struct Avx2(__m256d);

    macro_rules! avx2_op {
        ($trait:ident, $method:ident, $intrinsic:path) => {
            impl $trait for Avx2 {
                type Output = Self;
                #[inline(always)]
                fn $method(self, other: Self) -> Self {
                    // SAFETY: an `Avx2` exists only where the CPU has AVX2 (module doc).
                    Self(unsafe { $intrinsic(self.0, other.0) })
                }
            }
        };
    }

    avx2_op!(Add, add, std::arch::x86_64::_mm256_add_pd);
    avx2_op!(Sub, sub, _mm256_sub_pd);
    avx2_op!(Mul, mul, _mm256_mul_pd);
    avx2_op!(Div, div, _mm256_div_pd);

    impl Vector for Avx2 {
        type Mask = __m256d;

        #[inline(always)]
        fn splat(v: f64) -> Self {
            // SAFETY: as for every operation of `Avx2` (module doc).
            Self(unsafe { _mm256_set1_pd(v) })
        }

        #[inline(always)]
        fn load(lanes: Lanes) -> Self {
            Self(bytemuck::cast(lanes))
        }

        #[inline(always)]
        fn store(self) -> Lanes {
            bytemuck::cast(self.0)
        }

        #[inline(always)]
        fn abs(self) -> Self {
            // SAFETY: as above. Clearing the sign bit.
            Self(unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0) })
        }

        #[inline(always)]
        fn min(self, other: Self) -> Self {
            // SAFETY: as above. vminpd gives its second operand where either is NaN.
            Self(unsafe { _mm256_min_pd(self.0, other.0) })
        }

        #[inline(always)]
        fn max(self, other: Self) -> Self {
            // SAFETY: as above.
            Self(unsafe { _mm256_max_pd(self.0, other.0) })
        }

        #[inline(always)]
        fn gt(self, other: Self) -> __m256d {
            // SAFETY: as above. Ordered, quiet: false where either is NaN, as `>`.
            unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(self.0, other.0) }
        }

        #[inline(always)]
        fn ge(self, other: Self) -> __m256d {
            // SAFETY: as above.
            unsafe { _mm256_cmp_pd::<_CMP_GE_OQ>(self.0, other.0) }
        }

        #[inline(always)]
        fn and(a: __m256d, b: __m256d) -> __m256d {
            // SAFETY: as above.
            unsafe { _mm256_and_pd(a, b) }
        }

        #[inline(always)]
        fn and_not(a: __m256d, b: __m256d) -> __m256d {
            // SAFETY: as above.
            unsafe { _mm256_andnot_pd(a, b) }
        }

        #[inline(always)]
        fn select(mask: __m256d, yes: Self, no: Self) -> Self {
            // SAFETY: as above. blendv takes the second source where the mask's sign bit is set.
            Self(unsafe { _mm256_blendv_pd(no.0, yes.0, mask) })
        }
    }
}

/// The vector instructions this CPU runs, for the choice of a `Vector`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Isa {
    /// Plain arrays, on any CPU.
    Baseline,
    /// AVX2's 256-bit vectors.
    #[cfg(target_arch = "x86_64")]
    Avx2,
    /// AVX2 with AVX-512F and VL: the same vectors, and 32 registers to hold them.
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl Isa {
    /// The widest this CPU runs: the workspace's one test of the CPU's vector features (the
    /// splinegpu crate's CPU evaluator dispatches on it too).
    #[must_use]
    pub fn widest() -> Self {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let registers = std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512vl");
            return if registers { Self::Avx512 } else { Self::Avx2 };
        }
        Self::Baseline
    }

    /// Every one this CPU runs, narrowest first (each includes the ones before it).
    #[must_use]
    pub fn available() -> Vec<Self> {
        let mut all = vec![Self::Baseline];
        #[cfg(target_arch = "x86_64")]
        match Self::widest() {
            Self::Baseline => {}
            Self::Avx2 => all.push(Self::Avx2),
            Self::Avx512 => all.extend([Self::Avx2, Self::Avx512]),
        }
        all
    }
}

#[cfg(test)]
mod tests {
    use super::{Lanes, Vector};

    fn lane_wise<V: Vector>() {
        let a = V::load(Lanes([1.0, -2.0, f64::NAN, 4.0]));
        let b = V::load(Lanes([2.0, -3.0, 1.0, f64::INFINITY]));
        assert_eq!((a + b).store().0[..2], [3.0, -5.0]);
        assert_eq!((a * b).store().0[..2], [2.0, 6.0]);
        assert_eq!((b / a).store().0[..2], [2.0, 1.5]);
        assert_eq!(a.max(b).store().0, [2.0, -2.0, 1.0, f64::INFINITY]);
        assert_eq!(a.min(b).store().0, [1.0, -3.0, 1.0, 4.0]);
        assert_eq!(a.abs().store().0[1], 2.0);
        let picked = V::select(a.gt(b), V::splat(9.0), b).store();
        assert_eq!(picked.0, [2.0, 9.0, 1.0, f64::INFINITY]);
        let both = V::and(a.ge(V::splat(1.0)), V::splat(3.0).ge(a));
        let picked = V::select(V::and_not(both, b.gt(a)), V::splat(9.0), a).store();
        assert_eq!(picked.0[..2], [1.0, -2.0]);
        assert_eq!(picked.0[3], 9.0);
    }

    #[test]
    fn operations_are_lane_wise() {
        lane_wise::<Lanes>();
        #[cfg(target_arch = "x86_64")]
        if super::Isa::widest() != super::Isa::Baseline {
            lane_wise::<super::Avx2>();
        }
    }
}
