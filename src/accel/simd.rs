//! Which traversal kernels run: the environment variable `NFFRT_SIMD`, read once.
//!
//! - unset or `auto`: the widest kernels this CPU runs (AVX2 where present, else the
//!   portable ones);
//! - `avx2`: the AVX2 kernels, the stand-in for an AVX2-only CPU when comparing with
//!   peers pinned to AVX2 (nffrt has no wider kernels, so on an AVX-512 CPU this is
//!   also what `auto` runs);
//! - `portable`: the baseline x86_64 (SSE2) kernels, to measure or check them.
//!
//! Every choice gives bit-identical answers (see `traverse::avx`).

use std::sync::OnceLock;

/// The environment variable that chooses the kernels.
pub const SIMD_VARIABLE: &str = "NFFRT_SIMD";

/// The kernels a BVH's queries run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SimdLevel {
    /// Baseline x86_64 (SSE2) or another architecture's portable code.
    Portable,
    /// Compiled for AVX2 (with BMI1, BMI2 and LZCNT), picked at run time.
    Avx2,
}

impl SimdLevel {
    /// The level's name, as `NFFRT_SIMD` spells it.
    pub fn name(self) -> &'static str {
        match self {
            SimdLevel::Portable => "portable",
            SimdLevel::Avx2 => "avx2",
        }
    }
}

/// What `NFFRT_SIMD` asks for: `Ok(None)` for the automatic choice, an error message
/// for a value it does not know or a level this CPU cannot run.
pub fn requested() -> Result<Option<SimdLevel>, String> {
    static REQUESTED: OnceLock<Result<Option<SimdLevel>, String>> = OnceLock::new();
    REQUESTED.get_or_init(read_request).clone()
}

/// The kernels the queries run: the request when it is valid, else the automatic
/// choice (the command line refuses an invalid request before any work).
pub fn level() -> SimdLevel {
    match requested() {
        Ok(Some(level)) => level,
        _ if cpu_has_avx2() => SimdLevel::Avx2,
        _ => SimdLevel::Portable,
    }
}

fn read_request() -> Result<Option<SimdLevel>, String> {
    let Some(value) = std::env::var_os(SIMD_VARIABLE) else {
        return Ok(None);
    };
    match value.to_str() {
        Some("" | "auto") => Ok(None),
        Some("portable") => Ok(Some(SimdLevel::Portable)),
        Some("avx2") if cpu_has_avx2() => Ok(Some(SimdLevel::Avx2)),
        Some("avx2") => Err(format!("{SIMD_VARIABLE}=avx2: this CPU has no AVX2")),
        _ => Err(format!(
            "{SIMD_VARIABLE}={}: unknown kernels; use auto, avx2 or portable \
             (nffrt's widest kernels are AVX2)",
            value.to_string_lossy()
        )),
    }
}

/// Whether this CPU has the features the AVX2 kernels are compiled for.
fn cpu_has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        is_x86_feature_detected!("avx")
            && is_x86_feature_detected!("avx2")
            && is_x86_feature_detected!("bmi1")
            && is_x86_feature_detected!("bmi2")
            && is_x86_feature_detected!("lzcnt")
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}
