//! The instruction set the render kernels run with, chosen at run time as Embree and Cycles
//! choose theirs: the hot loops are compiled twice, once for the portable x86-64 baseline (SSE2)
//! and once for x86-64-v3 (AVX2, FMA, BMI1/2, LZCNT, MOVBE, F16C: every x86-64 CPU since Intel
//! Haswell, 2013, and AMD Excavator, 2015), and a render takes the v3 copy where the CPU has it.
//!
//! A kernel is an `#[inline(always)]` closure handed to [`Isa::run`], whose body (with the
//! `#[inline(always)]` functions it calls: the path loops, the BVH traversal, the BSDFs) is
//! compiled into both copies. Rust contracts no `a * b + c` into an FMA, so both
//! copies compute the same floating-point operations and give the same image, bit for bit
//! (tests/isa.rs); the v3 copy is faster by its three-operand AVX encodings, blends and bit
//! instructions (BENCHMARKS.md "Seventh engine round").

/// An instruction set the render kernels are compiled for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Isa {
    /// The portable build's own instruction set (x86-64 with SSE2, or any other architecture).
    #[default]
    Baseline,
    /// x86-64-v3: AVX2, FMA, BMI1, BMI2, LZCNT, MOVBE, F16C (and x86-64-v2's SSE4.2, POPCNT).
    X86_64V3,
}

/// Names of `--isa`.
pub const ISA_NAMES: [&str; 3] = ["auto", "baseline", "x86-64-v3"];

impl Isa {
    /// The fastest instruction set this CPU runs.
    pub fn best() -> Self {
        if Self::X86_64V3.available() { Self::X86_64V3 } else { Self::Baseline }
    }

    /// True when this CPU can run kernels compiled for `self` (std caches the CPUID query).
    #[inline]
    pub fn available(self) -> bool {
        match self {
            Self::Baseline => true,
            Self::X86_64V3 => has_x86_64_v3(),
        }
    }

    /// True when a kernel should run its x86-64-v3 copy: `self` asks for it and the CPU has it
    /// (checked again here, so that no caller can run AVX2 code on a CPU without it).
    #[inline]
    pub fn runs_x86_64_v3(self) -> bool {
        self == Self::X86_64V3 && has_x86_64_v3()
    }

    /// Runs `kernel` compiled for this instruction set where the CPU has it, else for the
    /// baseline. `kernel` must be an `#[inline(always)]` closure, whose body, with everything it
    /// inlines, is then compiled once per instruction set; a closure the compiler does not
    /// inline would run its baseline code either way.
    #[inline(always)]
    pub fn run<R>(self, kernel: impl FnOnce() -> R) -> R {
        if self.runs_x86_64_v3() {
            // SAFETY: the CPU has every feature the function is compiled for (runs_x86_64_v3)
            unsafe { run_x86_64_v3(kernel) }
        } else {
            kernel()
        }
    }

    /// Name in headers and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Baseline => "baseline",
            Self::X86_64V3 => "x86-64-v3",
        }
    }

    /// Parses `--isa`: `auto` (None: the best available), `baseline` or `x86-64-v3`; an
    /// instruction set this CPU lacks is an error.
    pub fn from_name(s: &str) -> Result<Option<Self>, String> {
        let isa = match s {
            "auto" => return Ok(None),
            "baseline" => Self::Baseline,
            "x86-64-v3" => Self::X86_64V3,
            _ => return Err(format!("expected one of {}, got {s:?}", ISA_NAMES.join(", "))),
        };
        if !isa.available() {
            return Err(format!("this CPU lacks {} (AVX2, FMA, BMI1/2, LZCNT, MOVBE, F16C)", isa.name()));
        }
        Ok(Some(isa))
    }
}

#[cfg(target_arch = "x86_64")]
#[inline]
fn has_x86_64_v3() -> bool {
    use std::arch::is_x86_feature_detected as has;
    // every feature `run_x86_64_v3` is compiled with
    has!("avx2")
        && has!("fma")
        && has!("bmi1")
        && has!("bmi2")
        && has!("lzcnt")
        && has!("movbe")
        && has!("f16c")
        && has!("popcnt")
}

#[cfg(not(target_arch = "x86_64"))]
#[inline]
fn has_x86_64_v3() -> bool {
    false
}

/// `kernel()` in a function compiled for x86-64-v3, which the `#[inline(always)]` closure is
/// inlined into (on other architectures a plain function that is never called).
#[cfg_attr(target_arch = "x86_64", target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe,f16c,popcnt"))]
unsafe fn run_x86_64_v3<R>(kernel: impl FnOnce() -> R) -> R {
    kernel()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_an_unknown_one_is_refused() {
        assert_eq!(Isa::from_name("auto"), Ok(None));
        assert_eq!(Isa::from_name("baseline"), Ok(Some(Isa::Baseline)));
        match Isa::from_name("x86-64-v3") {
            Ok(isa) => assert_eq!(isa, Some(Isa::X86_64V3)),
            Err(e) => assert!(!Isa::X86_64V3.available() && e.contains("lacks"), "{e}"),
        }
        let e = Isa::from_name("avx9").unwrap_err();
        assert!(e.contains("avx9") && e.contains("x86-64-v3"), "{e}");
        for isa in [Isa::Baseline, Isa::X86_64V3] {
            if isa.available() {
                assert_eq!(Isa::from_name(isa.name()), Ok(Some(isa)));
            }
        }
    }

    #[test]
    fn the_best_is_available_and_only_an_available_v3_runs() {
        assert!(Isa::best().available());
        assert!(!Isa::Baseline.runs_x86_64_v3());
        assert_eq!(Isa::X86_64V3.runs_x86_64_v3(), Isa::X86_64V3.available());
    }
}
