//! Range checks of the parameters that change a surface or curve (the
//! surface options themselves are `subdiv_stencil::Options`, which call these).

use std::fmt;

use crate::constants::{DENG_MA_TENSION_MAX, FOUR_POINT_TENSION_MAX};
use crate::deng_ma::Tension;

impl Tension {
    /// Checks the parameter against its range: ω or λ in (0, 1]. The one
    /// place Deng-Ma's tension is validated (the surface options and the
    /// interpolation method both call it).
    ///
    /// ```
    /// use subdiv_rules::{deng_ma::Tension, OptionsError};
    /// assert!(Tension::default().validate().is_ok());
    /// assert_eq!(Tension::Global(1.5).validate(), Err(OptionsError::DengMaOmega(1.5)));
    /// ```
    pub fn validate(&self) -> Result<(), OptionsError> {
        match *self {
            Tension::Global(w) if !(w > 0.0 && w <= DENG_MA_TENSION_MAX) => Err(OptionsError::DengMaOmega(w)),
            Tension::Variable { lambda } if !(lambda > 0.0 && lambda <= DENG_MA_TENSION_MAX) => {
                Err(OptionsError::DengMaLambda(lambda))
            }
            _ => Ok(()),
        }
    }
}

/// Checks a 4-point curve tension: in (0, 1/8).
pub fn validate_four_point_tension(t: f64) -> Result<(), OptionsError> {
    if t > 0.0 && t < FOUR_POINT_TENSION_MAX {
        Ok(())
    } else {
        Err(OptionsError::FourPointTension(t))
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
