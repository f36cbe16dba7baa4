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

/// Whether the CPU is an AMD family 23 (Zen, Zen+, Zen 2), whose
/// scalar floating-point pipes are too few for the play's paired form (its
/// extra min/max cost what its shorter dependency chain saves), so that
/// the play runs its plain chain there (read once per process).
///
/// The evidence is LLVM's scheduling models of those cores (`llvm-mca
/// -mcpu=znver1|znver2` on the release binary's loops; the benchmarks page
/// gives the cycles), where the paired loop and the chain both take the
/// chain's cycles and the finiteness test of the outputs adds to them; on
/// Zen 3 and later the paired form is the faster.
///
/// ```
/// // whatever it finds, the play's results do not depend on it
/// let _ = hysteron_operators::simd::few_float_pipes();
/// ```
pub fn few_float_pipes() -> bool {
    static FOUND: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *FOUND.get_or_init(|| amd_family() == Some(23))
}

/// The CPU's family number, if it is an AMD one (`CPUID` leaves 0 and 1:
/// the base family, plus the extended family where the base is 15).
#[cfg(target_arch = "x86_64")]
fn amd_family() -> Option<u32> {
    use core::arch::x86_64::__cpuid;
    let vendor = __cpuid(0);
    let amd = [vendor.ebx, vendor.edx, vendor.ecx] == [0x6874_7541, 0x6974_6e65, 0x444d_4163];
    if !amd {
        return None;
    }
    Some(family(__cpuid(1).eax))
}

/// The family number of a processor signature (`CPUID` leaf 1's `eax`).
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
fn family(signature: u32) -> u32 {
    let base = (signature >> 8) & 0xf;
    if base == 0xf {
        base + ((signature >> 20) & 0xff)
    } else {
        base
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn amd_family() -> Option<u32> {
    None
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Signatures of an EPYC 7601 (Zen), an EPYC 9004 (Zen 4) and a
    /// Skylake (Intel family 6).
    #[test]
    fn family_adds_the_extended_family_to_base_15() {
        assert_eq!(family(0x0080_0F12), 23);
        assert_eq!(family(0x00A1_0F11), 25);
        assert_eq!(family(0x0005_06E3), 6);
    }
}
