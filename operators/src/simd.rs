//! Which vector instructions the batch kernels use, detected at run time.
//!
//! The kernels written for several instruction sets (the Prandtl-Ishlinskii
//! bank's, the MMS exponential's) give the same bits on each: they do the
//! same operations in the same order (the bank's sums in fused
//! multiply-adds everywhere, the exponential's in none).

/// A vector instruction set a batch kernel has a version for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// AVX2 with FMA: four `f64` per instruction.
    Avx2,
    /// AVX-512 (foundation) with FMA: eight `f64` per instruction.
    Avx512,
}

impl Isa {
    /// The widest supported on this CPU, if any, unless the environment
    /// variable `HYSTERON_ISA` caps it (read once per process): `avx2`
    /// stops at AVX2, `portable` uses no vector kernel. For measuring an
    /// AVX2-only machine on an AVX-512 one, and for testing each kernel on
    /// any machine; the results are the same bit for bit.
    ///
    /// ```
    /// // whatever it finds, the kernels' results do not depend on it
    /// let _ = hysteron_operators::simd::Isa::detect();
    /// ```
    pub fn detect() -> Option<Isa> {
        static FOUND: std::sync::OnceLock<Option<Isa>> = std::sync::OnceLock::new();
        *FOUND.get_or_init(|| Self::find(std::env::var("HYSTERON_ISA").ok().as_deref()))
    }

    #[cfg(target_arch = "x86_64")]
    fn find(cap: Option<&str>) -> Option<Isa> {
        // (every AVX-512 CPU has FMA; AVX2 ones nearly all, and the
        // kernels use it)
        let avx2 = std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma");
        match cap {
            Some("portable") => None,
            Some("avx2") => avx2.then_some(Isa::Avx2),
            _ if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("fma") =>
            {
                Some(Isa::Avx512)
            }
            _ => avx2.then_some(Isa::Avx2),
        }
    }

    #[cfg(not(target_arch = "x86_64"))]
    fn find(_cap: Option<&str>) -> Option<Isa> {
        None
    }
}

/// `s` as a slice of `f64`, if `T` is `f64` (for a generic loop that has a
/// vector kernel over `f64`).
pub fn as_f64<T: 'static>(s: &[T]) -> Option<&[f64]> {
    // SAFETY: `T` and `f64` are the same type (equal type ids).
    (core::any::TypeId::of::<T>() == core::any::TypeId::of::<f64>())
        .then(|| unsafe { &*(s as *const [T] as *const [f64]) })
}

/// `s` as a mutable slice of `f64`, if `T` is `f64`.
pub fn as_f64_mut<T: 'static>(s: &mut [T]) -> Option<&mut [f64]> {
    // SAFETY: `T` and `f64` are the same type (equal type ids).
    (core::any::TypeId::of::<T>() == core::any::TypeId::of::<f64>())
        .then(|| unsafe { &mut *(s as *mut [T] as *mut [f64]) })
}
