//! What decides a subdivision surface: the scheme with its own parameters
//! and OpenSubdiv's `Sdc::Options` (boundary interpolation, crease method,
//! face-varying interpolation), in one struct built and validated once and
//! passed to every layer.

use crate::StencilError;
use subdiv_rules::deng_ma::Tension;
use subdiv_rules::{BoundaryInterpolation, CreaseMethod, FVarInterpolation, LoopBeta};

/// A subdivision scheme with the parameters that belong to it alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scheme {
    /// Catmull-Clark (any polygons; quads after one step).
    CatmullClark,
    /// Loop (triangles only), with Warren's or Loop's β.
    Loop(LoopBeta),
    /// Standard Doo-Sabin (any polygons).
    DooSabin,
    /// Deng-Ma's interpolatory scheme (any polygons, open or closed: 4-point
    /// boundary curves), global or variable tension.
    DengMa(Tension),
    /// Kobbelt's √3 scheme (triangles only; boundaries trisected every
    /// second step; corners, no creases).
    Sqrt3,
}

impl Scheme {
    /// Short name, as on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Scheme::CatmullClark => "catmull-clark",
            Scheme::Loop(_) => "loop",
            Scheme::DooSabin => "doo-sabin",
            Scheme::DengMa(_) => "deng-ma",
            Scheme::Sqrt3 => "sqrt3",
        }
    }

    /// Whether the scheme takes sharpness tags: Catmull-Clark and Loop take
    /// every tag (OpenSubdiv's rules), Doo-Sabin and Deng-Ma infinitely sharp
    /// creases and corners (semi-sharp values are refused) — all of them now.
    pub fn takes_tags(&self) -> bool {
        true
    }
}

/// Everything that changes the limit surface (and the face-varying data on
/// it). Defaults as OpenSubdiv's Far tools use them: Catmull-Clark,
/// `edge-and-corner` boundaries, uniform creasing, `linear-all` face-varying
/// data.
///
/// `#[non_exhaustive]`: build it with [`Options::new`] (or [`Default`]) and
/// the `with_*` setters (one per field); the fields stay public for
/// reading. Adding a field is then not a breaking change.
///
/// ```
/// use subdiv_stencil::{Options, Scheme};
/// use subdiv_rules::{BoundaryInterpolation, CreaseMethod};
/// let options = Options::new(Scheme::CatmullClark)
///     .with_boundary(BoundaryInterpolation::EdgeOnly)
///     .with_crease_method(CreaseMethod::Chaikin);
/// assert!(options.validate().is_ok());
/// assert_eq!(Options::from(Scheme::DooSabin).boundary, BoundaryInterpolation::EdgeAndCorner);
/// assert_eq!(Options::default().with_scheme(Scheme::DooSabin), Options::new(Scheme::DooSabin));
/// ```
///
/// A struct literal does not compile outside the crate:
///
/// ```compile_fail,E0639
/// use subdiv_stencil::{Options, Scheme};
/// let options = Options { scheme: Scheme::DooSabin, ..Options::default() };
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Options {
    /// The scheme and its parameters (Loop's β, Deng-Ma's tension).
    pub scheme: Scheme,
    /// How boundary vertices are treated.
    pub boundary: BoundaryInterpolation,
    /// How semi-sharp creases decay.
    pub crease_method: CreaseMethod,
    /// How face-varying data (UVs) is interpolated.
    pub fvar: FVarInterpolation,
}

impl From<Scheme> for Options {
    fn from(scheme: Scheme) -> Self {
        Self::new(scheme)
    }
}

impl Default for Options {
    /// Catmull-Clark with the default options (OpenSubdiv's default scheme).
    fn default() -> Self {
        Self::new(Scheme::CatmullClark)
    }
}

impl Options {
    /// The scheme with the default options.
    pub fn new(scheme: Scheme) -> Self {
        Self {
            scheme,
            boundary: BoundaryInterpolation::default(),
            crease_method: CreaseMethod::default(),
            fvar: FVarInterpolation::default(),
        }
    }

    /// With another scheme (and its parameters); the other options are kept.
    pub fn with_scheme(self, scheme: Scheme) -> Self {
        Self { scheme, ..self }
    }

    /// With another boundary interpolation.
    pub fn with_boundary(self, boundary: BoundaryInterpolation) -> Self {
        Self { boundary, ..self }
    }

    /// With another crease method.
    pub fn with_crease_method(self, crease_method: CreaseMethod) -> Self {
        Self { crease_method, ..self }
    }

    /// With another face-varying interpolation.
    pub fn with_fvar(self, fvar: FVarInterpolation) -> Self {
        Self { fvar, ..self }
    }

    /// Checks every parameter's range (the one place: Deng-Ma's tension).
    ///
    /// # Errors
    /// [`StencilError::InvalidParameter`] naming the parameter.
    pub fn validate(&self) -> Result<(), StencilError> {
        if let Scheme::DengMa(tension) = self.scheme {
            tension.validate().map_err(|e| StencilError::InvalidParameter(e.to_string()))?;
        }
        Ok(())
    }
}
