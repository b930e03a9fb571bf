//! Default parameters and admissible ranges, in one place.

/// Default tension of the 4-point curve scheme: ω = 1/16, the classical
/// Dyn-Levin-Gregory value, which reproduces cubic polynomials.
pub const DEFAULT_FOUR_POINT_TENSION: f64 = 1.0 / 16.0;

/// Exclusive upper bound of the 4-point tension for a C¹ limit (Deng-Ma §3.1:
/// 0 < ω < 1/8).
pub const FOUR_POINT_TENSION_MAX: f64 = 1.0 / 8.0;

/// Default global tension ω of the Deng-Ma surface scheme (§3.3; ω_P = 1 is the
/// surface analogue of the 4-point ω = 1/16, [correction D4]).
///
/// [correction D4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d4
pub const DEFAULT_DENG_MA_OMEGA: f64 = 1.0;

/// Inclusive upper bound of the Deng-Ma tension ω_P and of λ (§3.3, §3.4:
/// 0 < ω_P ≤ 1, 0 < λ ≤ 1).
pub const DENG_MA_TENSION_MAX: f64 = 1.0;
