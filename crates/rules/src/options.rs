//! The options that change a surface or curve, collected in one struct
//! (OpenSubdiv's `Sdc::Options`).

use std::fmt;

use crate::constants::{DEFAULT_FOUR_POINT_TENSION, DENG_MA_TENSION_MAX, FOUR_POINT_TENSION_MAX};
use crate::deng_ma::Tension;
use crate::loop_scheme::LoopBeta;

/// Every scheme parameter that changes the limit surface or curve. Defaults:
/// Warren's β, 4-point ω = 1/16, Deng-Ma global ω = 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SchemeOptions {
    /// β of the Loop vertex rule.
    pub loop_beta: LoopBeta,
    /// Tension ω of the 4-point curve scheme, in (0, 1/8).
    pub four_point_tension: f64,
    /// Tension of the Deng-Ma surface scheme.
    pub deng_ma_tension: Tension,
}

impl Default for SchemeOptions {
    fn default() -> Self {
        Self {
            loop_beta: LoopBeta::default(),
            four_point_tension: DEFAULT_FOUR_POINT_TENSION,
            deng_ma_tension: Tension::default(),
        }
    }
}

impl SchemeOptions {
    /// Checks every parameter against its admissible range.
    ///
    /// ```
    /// use subdiv_rules::{SchemeOptions, OptionsError};
    /// assert!(SchemeOptions::default().validate().is_ok());
    /// let bad = SchemeOptions { four_point_tension: 0.2, ..Default::default() };
    /// assert_eq!(bad.validate(), Err(OptionsError::FourPointTension(0.2)));
    /// ```
    pub fn validate(&self) -> Result<(), OptionsError> {
        let t = self.four_point_tension;
        if !(t > 0.0 && t < FOUR_POINT_TENSION_MAX) {
            return Err(OptionsError::FourPointTension(t));
        }
        match self.deng_ma_tension {
            Tension::Global(w) if !(w > 0.0 && w <= DENG_MA_TENSION_MAX) => Err(OptionsError::DengMaOmega(w)),
            Tension::Variable { lambda } if !(lambda > 0.0 && lambda <= DENG_MA_TENSION_MAX) => {
                Err(OptionsError::DengMaLambda(lambda))
            }
            _ => Ok(()),
        }
    }
}

/// A scheme parameter outside its admissible range (the value is carried).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum OptionsError {
    /// The 4-point tension must lie in (0, 1/8).
    FourPointTension(f64),
    /// The Deng-Ma global tension ω must lie in (0, 1].
    DengMaOmega(f64),
    /// The Deng-Ma shape parameter λ must lie in (0, 1].
    DengMaLambda(f64),
}

impl fmt::Display for OptionsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::FourPointTension(v) => {
                write!(f, "4-point tension {v} is outside (0, 1/8)")
            }
            Self::DengMaOmega(v) => write!(f, "Deng-Ma tension ω = {v} is outside (0, 1]"),
            Self::DengMaLambda(v) => write!(f, "Deng-Ma shape parameter λ = {v} is outside (0, 1]"),
        }
    }
}

impl std::error::Error for OptionsError {}
