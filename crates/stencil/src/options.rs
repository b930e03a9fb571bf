//! What decides a subdivision surface: the scheme with its own parameters
//! and OpenSubdiv's `Sdc::Options` (boundary interpolation, crease method,
//! face-varying interpolation), in one struct built and validated once and
//! passed to every layer.

use crate::scheme::{Domain, FVarSupport, SchemeTraits, Split};
use crate::LevelSharpness;
use crate::StencilError;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;
use std::str::FromStr;
use subdiv_mesh::Tags;
use subdiv_rules::constants::DEFAULT_DENG_MA_OMEGA;
use subdiv_rules::deng_ma::Tension;
use subdiv_rules::{BoundaryInterpolation, CreaseMethod, DartLimit, FVarInterpolation, LoopBeta, TriangleRule};

/// A subdivision scheme with the parameters that belong to it alone: the
/// one table of schemes. Everything the other layers ask of a scheme that is
/// not a subdivision rule — its name, its parameter domain, its split, what
/// it supports — is answered here ([`Scheme::traits`], in the spirit of
/// OpenSubdiv's `Sdc::SchemeTypeTraits`); the rules themselves are one
/// `impl SchemeRules` per scheme ([`Scheme::rules`]). Exhaustive on purpose:
/// a new variant must break every match over schemes.
///
/// ```
/// use subdiv_stencil::{Domain, Scheme, Split};
/// for scheme in Scheme::ALL {
///     assert_eq!(scheme.name().parse::<Scheme>(), Ok(scheme));
/// }
/// let loop_traits = Scheme::Loop(Default::default()).traits();
/// assert_eq!((loop_traits.domain, loop_traits.split), (Domain::Triangle, Split::Triangle));
/// assert!(loop_traits.triangles_only);
/// assert_eq!(
///     "butterfly".parse::<Scheme>().unwrap_err().to_string(),
///     "unknown scheme `butterfly` (expected one of: catmull-clark, loop, doo-sabin, deng-ma, sqrt3)"
/// );
/// ```
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
    /// Every scheme, each with its default parameters (Loop's β, ω = 1), in
    /// the order help texts list them.
    pub const ALL: [Scheme; 5] = [
        Scheme::CatmullClark,
        Scheme::Loop(LoopBeta::Loop),
        Scheme::DooSabin,
        Scheme::DengMa(Tension::Global(DEFAULT_DENG_MA_OMEGA)),
        Scheme::Sqrt3,
    ];

    /// Short name, as on the command line (parsed back by [`FromStr`]).
    pub fn name(&self) -> &'static str {
        match self {
            Scheme::CatmullClark => "catmull-clark",
            Scheme::Loop(_) => "loop",
            Scheme::DooSabin => "doo-sabin",
            Scheme::DengMa(_) => "deng-ma",
            Scheme::Sqrt3 => "sqrt3",
        }
    }

    /// One line for help texts.
    pub fn summary(&self) -> &'static str {
        match self {
            Scheme::CatmullClark => "Catmull-Clark: any polygons, quads after one step (bicubic B-spline limit)",
            Scheme::Loop(_) => "Loop: triangles only (quartic box-spline limit), Warren's or Loop's β",
            Scheme::DooSabin => "Doo-Sabin: any polygons, the dual split (biquadratic B-spline limit)",
            Scheme::DengMa(_) => "Deng-Ma: interpolatory, any polygons on the quad split, global or variable tension",
            Scheme::Sqrt3 => "√3 (Kobbelt 2000): triangles only, the 1-to-3 split with edge flips (C² limit)",
        }
    }

    /// What the layers ask of the scheme besides its rules (the struct's
    /// field docs say who asks what).
    pub const fn traits(&self) -> SchemeTraits {
        match self {
            Scheme::CatmullClark => SchemeTraits {
                domain: Domain::Quad,
                split: Split::Quad,
                regular_valence: 4,
                regular_face_size: 4,
                triangles_only: false,
                interpolating: false,
                face_varying: FVarSupport::Full,
                evaluable: true,
                bytes_per_corner: 45,
            },
            Scheme::Loop(_) => SchemeTraits {
                domain: Domain::Triangle,
                split: Split::Triangle,
                regular_valence: 6,
                regular_face_size: 3,
                triangles_only: true,
                interpolating: false,
                face_varying: FVarSupport::Full,
                evaluable: true,
                bytes_per_corner: 44,
            },
            // Evaluated on quarter domains, one per face corner (the
            // biquadratic patch's own parameterisation): a quad domain.
            Scheme::DooSabin => SchemeTraits {
                domain: Domain::Quad,
                split: Split::Dual,
                regular_valence: 4,
                regular_face_size: 4,
                triangles_only: false,
                interpolating: false,
                face_varying: FVarSupport::SeamlessUntagged,
                evaluable: true,
                bytes_per_corner: 55,
            },
            // The quad split of Catmull-Clark; no limit masks, so nothing to
            // evaluate; its channel follows Catmull-Clark's face-varying rules.
            Scheme::DengMa(_) => SchemeTraits {
                domain: Domain::Quad,
                split: Split::Quad,
                regular_valence: 4,
                regular_face_size: 4,
                triangles_only: false,
                interpolating: true,
                face_varying: FVarSupport::Full,
                evaluable: false,
                bytes_per_corner: 61,
            },
            // Triangles, but no polynomial patches: limit points and refinement, no evaluation.
            Scheme::Sqrt3 => SchemeTraits {
                domain: Domain::Triangle,
                split: Split::Sqrt3,
                regular_valence: 6,
                regular_face_size: 3,
                triangles_only: true,
                interpolating: false,
                face_varying: FVarSupport::None,
                evaluable: false,
                bytes_per_corner: 44,
            },
        }
    }

    /// The parameters of the scheme, as [`Scheme::with_parameters`] takes them: Loop's β and
    /// Deng-Ma's tension (`None` for a scheme without that parameter).
    pub fn parameters(&self) -> (Option<LoopBeta>, Option<Tension>) {
        match *self {
            Scheme::Loop(beta) => (Some(beta), None),
            Scheme::DengMa(tension) => (None, Some(tension)),
            Scheme::CatmullClark | Scheme::DooSabin | Scheme::Sqrt3 => (None, None),
        }
    }

    /// The scheme with Loop's β or Deng-Ma's tension set where given (the
    /// scheme's own parameters are kept where not).
    ///
    /// ```
    /// use subdiv_stencil::{LoopBeta, Scheme, Tension};
    /// let loop_ = Scheme::Loop(LoopBeta::Warren).with_parameters(Some(LoopBeta::Loop), None);
    /// assert_eq!(loop_, Ok(Scheme::Loop(LoopBeta::Loop)));
    /// assert!(Scheme::CatmullClark.with_parameters(None, Some(Tension::Global(0.5))).is_err());
    /// ```
    ///
    /// # Errors
    /// [`StencilError::ParameterNotApplicable`] for a parameter that does not
    /// belong to the scheme, in command-line terms ("--beta applies to
    /// --scheme loop only").
    pub fn with_parameters(self, beta: Option<LoopBeta>, tension: Option<Tension>) -> Result<Self, StencilError> {
        if beta.is_some() && !matches!(self, Scheme::Loop(_)) {
            return Err(StencilError::ParameterNotApplicable("--beta applies to --scheme loop only".into()));
        }
        if tension.is_some() && !matches!(self, Scheme::DengMa(_)) {
            return Err(StencilError::ParameterNotApplicable(
                "--omega/--variable-tension apply to --scheme deng-ma only".into(),
            ));
        }
        Ok(match self {
            Scheme::Loop(own) => Scheme::Loop(beta.unwrap_or(own)),
            Scheme::DengMa(own) => Scheme::DengMa(tension.unwrap_or(own)),
            Scheme::CatmullClark | Scheme::DooSabin | Scheme::Sqrt3 => self,
        })
    }
}

impl fmt::Display for Scheme {
    /// The name ([`Scheme::name`]).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Scheme {
    type Err = StencilError;

    /// A name of [`Scheme::ALL`], exactly → that scheme with its default
    /// parameters.
    ///
    /// # Errors
    /// [`StencilError::UnknownScheme`], whose message lists the valid names.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Scheme::ALL
            .into_iter()
            .find(|scheme| scheme.name() == s)
            .ok_or_else(|| StencilError::UnknownScheme { name: s.to_string() })
    }
}

impl Serialize for Scheme {
    /// As its name (the parameters are not part of it).
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Scheme {
    /// From its name ([`FromStr`]): the scheme with its default parameters.
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let name = String::deserialize(deserializer)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}

/// Everything that changes the limit surface (and the face-varying data on
/// it), and the one choice of which limit point a dart gets. Defaults as
/// OpenSubdiv's Far tools use them: Catmull-Clark, `edge-and-corner`
/// boundaries, uniform creasing, `linear-all` face-varying data; except at
/// darts, which get their exact limit ([`DartLimit::Exact`]) where
/// OpenSubdiv's limit stencils take the smooth mask
/// ([`DartLimit::SmoothMask`]).
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
    /// Catmull-Clark's rule for triangles (OpenSubdiv's `TriangleSubdivision`);
    /// the other schemes ignore it.
    pub triangle_rule: TriangleRule,
    /// Which limit point a dart gets (the limit stencils of Catmull-Clark
    /// and Loop; refinement is the same either way).
    pub dart_limit: DartLimit,
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
            triangle_rule: TriangleRule::default(),
            dart_limit: DartLimit::default(),
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

    /// With another triangle rule (Catmull-Clark).
    pub fn with_triangle_rule(self, triangle_rule: TriangleRule) -> Self {
        Self { triangle_rule, ..self }
    }

    /// The base level's rules for a mesh with `tags`: the tags with the
    /// boundary option, the crease method, the triangle rule and the dart limit.
    pub fn sharpness(&self, tags: &Tags) -> LevelSharpness {
        LevelSharpness::from_options(tags, self)
    }

    /// With another dart limit ([`DartLimit::SmoothMask`]: OpenSubdiv's
    /// limit stencils and `Far::PrimvarRefiner::Limit`).
    pub fn with_dart_limit(self, dart_limit: DartLimit) -> Self {
        Self { dart_limit, ..self }
    }

    /// Checks every parameter's range (the one place: Deng-Ma's tension).
    ///
    /// # Errors
    /// [`StencilError::InvalidParameter`] naming the parameter.
    pub fn validate(&self) -> Result<(), StencilError> {
        if let Scheme::DengMa(tension) = self.scheme {
            tension.validate().map_err(|e| StencilError::InvalidParameter(e.to_string()))?;
        }
        if self.triangle_rule == TriangleRule::Smooth && self.scheme != Scheme::CatmullClark {
            return Err(StencilError::InvalidParameter(format!(
                "the smooth triangle rule is Catmull-Clark's (OpenSubdiv's TRI_SUB_SMOOTH), not {}'s",
                self.scheme
            )));
        }
        Ok(())
    }
}
