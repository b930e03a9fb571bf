//! USD: `UsdGeomMesh` prims in `.usda` (text), `.usdc` (binary crate) and
//! `.usdz` (zip package) layers, read and written through the `openusd`
//! crate (pure Rust; its parser and writers, our mapping onto subdiv's
//! meshes).
//!
//! A USD file holds any number of meshes, each at a prim path. As a
//! **scene** ([`read_scene`], [`UsdScene`]) every `def Mesh` prim of the
//! layer is read, in the layer's path order, with its prim path and
//! subdivision scheme; [`write_scene_to_vec`] / [`stage_scene`] write
//! meshes back at their prim paths, into a copy of the layer they were read
//! from (its transforms, other prims and metadata kept) or into a new one.
//! As a **single mesh** ([`crate::read_mesh`], [`crate::write_mesh`]) a
//! file must hold exactly one Mesh prim ([`IoError::SeveralMeshes`]
//! otherwise), and a mesh is written at `/Mesh`.
//!
//! What is read and written, per Mesh prim (USD's names → subdiv's):
//!
//! | USD attribute | subdiv |
//! |---|---|
//! | `points` (`point3f[]`; `point3d[]`, `point3h[]` read too) | positions (`f32` when written) |
//! | `faceVertexCounts`, `faceVertexIndices` | faces |
//! | `orientation` | `leftHanded` faces are reversed on read (first corner kept); written `rightHanded` |
//! | `subdivisionScheme` | [`SubdivisionScheme`] (`none` and `bilinear` meshes are read as plain polygons, their tags kept) |
//! | `interpolateBoundary` | [`FileOptions::boundary`] |
//! | `faceVaryingLinearInterpolation` | [`FileOptions::fvar`] (unauthored on a mesh with `primvars:st`: USD's fallback `cornersPlus1`) |
//! | `triangleSubdivisionRule` | [`FileOptions::triangle_rule`] |
//! | `creaseIndices`, `creaseLengths`, `creaseSharpnesses` | edge tags (a crease of n vertices is n − 1 edges; one sharpness per crease or per edge) |
//! | `cornerIndices`, `cornerSharpnesses` | vertex tags |
//! | `holeIndices` | holes |
//! | `primvars:st` (`faceVarying` or `vertex`, with or without `primvars:st:indices`) | texture coordinates (`texCoord2f[]` when written, face-varying and indexed) |
//! | `subdiv:creaseMethod` (ours, custom) | [`FileOptions::crease_method`]: USD has no attribute for Chaikin's rule |
//! | `normals` (written only, per vertex) | the writer's vertex normals |
//!
//! Tags are written as OpenSubdiv and USD mean them (sharpness 10 and
//! above infinitely sharp), one two-vertex crease per edge tag, so a
//! renderer built on OpenSubdiv (Hydra Storm, RenderMan, Karma, Cycles …)
//! shows the surface of the mesh's scheme and tags.
//!
//! What is **not** done: composition. Only the one layer is read
//! (the first of a usdz); references, payloads, sublayers, variants and
//! inherits are not followed, so a Mesh defined only through them is not
//! found. The authored default value of an attribute is read, else its
//! earliest time sample. Points of other prims (`Points`, `BasisCurves`),
//! other primvars and `GeomSubset`s are not read; when a mesh is written
//! into the layer it came from, its geometric attributes are replaced and
//! its other properties kept, except that its `GeomSubset` children and
//! primvars other than `st` are removed when the face or vertex count
//! changes (they would number faces or vertices that no longer exist).
//!
//! Binary files are written by `openusd` 0.6 and then made readable by
//! pxr (`pxr_compatible`: children lists as vectors, integer arrays under
//! 16 elements uncompressed), checked against usd-core in the Python tests.
//!
//! Hostile input: the `openusd` reader is called under
//! [`std::panic::catch_unwind`] (a panic in it becomes
//! [`IoError::Parse`]), and every count of the mesh is checked against
//! the arrays that are present before it is used.

use std::borrow::Cow;
use std::io::Cursor;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use openusd::sdf::{self, AbstractData, ChildrenKey, FieldKey, SpecType, Specifier, Value, Variability};
use subdiv_mesh::{DVec2, DVec3, EdgeTag, FaceList, FaceVarying, FileOptions, PolygonSoup, TagList, VertexTag};
use subdiv_rules::crease::{BoundaryInterpolation, CreaseMethod, FVarInterpolation, TriangleRule};

use crate::error::Ctx;
use crate::{Format, IoError, MeshView, ReadWarning, StagedFile};

/// The prim path [`crate::write_mesh`] writes a single mesh at.
pub const DEFAULT_PRIM_PATH: &str = "/Mesh";

/// USD's `subdivisionScheme` (OpenSubdiv's scheme names).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SubdivisionScheme {
    /// `catmullClark`: USD's fallback when the attribute is not authored.
    #[default]
    CatmullClark,
    /// `loop` (triangle meshes).
    Loop,
    /// `bilinear`: read as plain polygons.
    Bilinear,
    /// `none`: plain polygons, as a refined surface is written.
    None,
}

impl SubdivisionScheme {
    /// The token USD spells it with.
    pub fn token(self) -> &'static str {
        match self {
            SubdivisionScheme::CatmullClark => "catmullClark",
            SubdivisionScheme::Loop => "loop",
            SubdivisionScheme::Bilinear => "bilinear",
            SubdivisionScheme::None => "none",
        }
    }

    /// The scheme of a USD token, `None` for a token USD does not define.
    pub fn from_token(token: &str) -> Option<Self> {
        Some(match token {
            "catmullClark" => SubdivisionScheme::CatmullClark,
            "loop" => SubdivisionScheme::Loop,
            "bilinear" => SubdivisionScheme::Bilinear,
            "none" => SubdivisionScheme::None,
            _ => return None,
        })
    }

    /// Whether a renderer subdivides the mesh (Catmull-Clark, Loop).
    pub fn subdivides(self) -> bool {
        matches!(self, SubdivisionScheme::CatmullClark | SubdivisionScheme::Loop)
    }
}

impl std::fmt::Display for SubdivisionScheme {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.token())
    }
}

/// One `Mesh` prim as read.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct UsdMesh {
    /// Its prim path, e.g. `/World/Body`.
    pub path: String,
    /// Its positions, faces (right-handed), tags, options and texture coordinates.
    pub soup: PolygonSoup,
    /// Its `subdivisionScheme` (the fallback `catmullClark` when not authored).
    pub scheme: SubdivisionScheme,
}

/// The meshes of a USD layer, with the layer itself for writing them back
/// into ([`write_scene_to_vec`] with a template).
pub struct UsdScene {
    /// Every `def Mesh` prim, in the layer's path order.
    pub meshes: Vec<UsdMesh>,
    layer: sdf::Data,
}

impl std::fmt::Debug for UsdScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("UsdScene").field("meshes", &self.meshes).field("specs", &self.layer.len()).finish()
    }
}

impl UsdScene {
    /// The prim paths of the meshes, in order.
    pub fn prim_paths(&self) -> Vec<String> {
        self.meshes.iter().map(|m| m.path.clone()).collect()
    }

    /// Keeps only the mesh at `prim` (its path as [`UsdMesh::path`] spells
    /// it); `None` when there is none (the scene is left as it was).
    pub fn select(&mut self, prim: &str) -> Option<&UsdMesh> {
        let i = self.meshes.iter().position(|m| m.path == prim)?;
        let mesh = self.meshes.swap_remove(i);
        self.meshes = vec![mesh];
        self.meshes.first()
    }
}

/// A mesh to write at a prim path, with the scheme a renderer is to
/// subdivide it with.
#[derive(Clone, Copy, Debug)]
pub struct SceneMesh<'a> {
    /// The prim path, absolute (`/World/Body`); missing parents are
    /// written as `Xform` prims.
    pub path: &'a str,
    /// The mesh (its tags and texture coordinates written when given).
    pub view: MeshView<'a>,
    /// `subdivisionScheme`: `None` leaves it unauthored (USD's fallback,
    /// Catmull-Clark).
    pub scheme: Option<SubdivisionScheme>,
}

/// Reads every Mesh prim of a USD file (`.usda`, `.usdc`, `.usd`, `.usdz`;
/// text, binary or zip told by the content), and what was dropped.
///
/// # Errors
/// Those of [`crate::read_mesh`], except [`IoError::SeveralMeshes`];
/// [`IoError::Empty`] when the layer has no Mesh prim.
pub fn read_scene(path: &Path) -> Result<(UsdScene, Vec<ReadWarning>), IoError> {
    let bytes = crate::read_file(path, None, &mut |_, _| {})?;
    scene_from_bytes(&bytes, Ctx::new(path))
}

/// [`read_scene`] from memory; `name` stands for the file in messages.
///
/// # Errors
/// Those of [`read_scene`].
pub fn read_scene_from_bytes(bytes: &[u8], name: &str) -> Result<(UsdScene, Vec<ReadWarning>), IoError> {
    scene_from_bytes(bytes, Ctx::new(Path::new(name)))
}

fn scene_from_bytes(bytes: &[u8], ctx: Ctx<'_>) -> Result<(UsdScene, Vec<ReadWarning>), IoError> {
    let layer = open_layer(bytes, ctx)?;
    let mut warnings = Vec::new();
    let meshes = guarded(ctx, || read_meshes(&layer, ctx, &mut warnings))??;
    if meshes.is_empty() {
        return Err(ctx.empty());
    }
    Ok((UsdScene { meshes, layer }, warnings))
}

/// The one mesh of a USD file ([`crate::read_mesh`]).
pub(crate) fn read(bytes: &[u8], ctx: Ctx<'_>) -> Result<(PolygonSoup, Vec<ReadWarning>), IoError> {
    let (mut scene, warnings) = scene_from_bytes(bytes, ctx)?;
    if scene.meshes.len() > 1 {
        return Err(IoError::SeveralMeshes { path: ctx.path.to_path_buf(), prims: scene.prim_paths() });
    }
    let mesh = scene.meshes.pop().ok_or_else(|| ctx.empty())?;
    Ok((mesh.soup, warnings))
}

thread_local! {
    /// Set while this thread runs [`guarded`]: its panics are caught and reported as errors.
    static IN_GUARDED: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs a call into `openusd` with its panics caught: a hostile file must
/// not take the process down, nor print a panic message before the error
/// it becomes. The first call installs a panic hook that stays silent while
/// the panicking thread is inside `guarded` and passes every other panic to
/// the hook that was there before.
fn guarded<T>(ctx: Ctx<'_>, f: impl FnOnce() -> T) -> Result<T, IoError> {
    static QUIET_HOOK: std::sync::Once = std::sync::Once::new();
    QUIET_HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !IN_GUARDED.with(std::cell::Cell::get) {
                previous(info);
            }
        }));
    });
    let outer = IN_GUARDED.with(|g| g.replace(true));
    let result = catch_unwind(AssertUnwindSafe(f));
    IN_GUARDED.with(|g| g.set(outer));
    result.map_err(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "malformed data".to_string());
        parse_error(ctx, format!("the USD reader failed: {what}"))
    })
}

/// A parse error whose message may quote the file (tokens, paths, section
/// names): control characters escaped, so that it stays one line.
fn parse_error(ctx: Ctx<'_>, message: String) -> IoError {
    let message = if message.contains(char::is_control) {
        message.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.to_string() }).collect()
    } else {
        message
    };
    ctx.parse(None, message)
}

/// An `openusd` error as ours: its whole chain on one line.
fn usd_error(ctx: Ctx<'_>, what: &str, e: &anyhow_chain::Chain) -> IoError {
    parse_error(ctx, format!("{what}: {}", e.0))
}

/// The error chain of an `anyhow::Error` (the crate's error type) as text,
/// without naming `anyhow` as a dependency of ours.
mod anyhow_chain {
    /// One line: the error and its causes, `: `-separated.
    pub(super) struct Chain(pub(super) String);

    impl<E: std::fmt::Debug + std::fmt::Display> From<E> for Chain {
        fn from(e: E) -> Self {
            // `{:#}` of anyhow's error is the chain on one line.
            Chain(format!("{e:#}").replace('\n', " "))
        }
    }
}

/// The magic bytes of a binary crate file and of a zip archive.
const USDC_MAGIC: &[u8] = b"PXR-USDC";
const ZIP_MAGIC: &[u8] = b"PK\x03\x04";

/// Parses a layer of any of the three kinds, told by the content.
fn open_layer(bytes: &[u8], ctx: Ctx<'_>) -> Result<sdf::Data, IoError> {
    if bytes.starts_with(USDC_MAGIC) {
        return crate_layer(bytes.to_vec(), ctx);
    }
    if bytes.starts_with(ZIP_MAGIC) {
        return guarded(ctx, || {
            let mut archive = openusd::usdz::Archive::from_reader(Cursor::new(bytes.to_vec()))
                .map_err(|e| usd_error(ctx, "usdz", &e.into()))?;
            let first = archive.read_first_layer().map_err(|e| usd_error(ctx, "usdz", &e.into()))?;
            sdf::Data::from_abstract(first.as_ref()).map_err(|e| usd_error(ctx, "usdz", &e.into()))
        })?;
    }
    let text = crate::text::strip_bom(bytes);
    if crate::text::is_blank(text) {
        return Err(ctx.empty());
    }
    crate::text::check_text(text, Format::Usda, ctx)?;
    let text = std::str::from_utf8(text).map_err(|e| ctx.parse(None, format!("not UTF-8 text: {e}")))?;
    if !text.starts_with("#usda") {
        return Err(ctx.parse(1, "not a USD file: a text layer starts with '#usda 1.0'"));
    }
    guarded(ctx, || openusd::usda::parse(text).map_err(|e| usd_error(ctx, "usda", &e.into())))?
}

/// A binary crate layer, all its fields read into memory (so that nothing
/// is decoded lazily outside [`guarded`]), after [`bounded_counts`].
fn crate_layer(bytes: Vec<u8>, ctx: Ctx<'_>) -> Result<sdf::Data, IoError> {
    bounded_counts(&bytes, ctx)?;
    guarded(ctx, || {
        let data =
            openusd::usdc::CrateData::open(Cursor::new(bytes), true).map_err(|e| usd_error(ctx, "usdc", &e.into()))?;
        sdf::Data::from_abstract(&data).map_err(|e| usd_error(ctx, "usdc", &e.into()))
    })?
}

/// How many elements a compressed array may hold per byte of the file: USD's
/// integer coding takes at least 2 bits a value, and LZ4 expands at most
/// ~255 times.
const MOST_PER_BYTE: u64 = 1024;

/// The little-endian word at byte `at` of a crate file; `None` past its end.
fn le_u64(bytes: &[u8], at: u64) -> Option<u64> {
    let at = usize::try_from(at).ok()?;
    Some(u64::from_le_bytes(bytes.get(at..at.checked_add(8)?)?.try_into().ok()?))
}

/// [`le_u64`] for a 32-bit word.
fn le_u32(bytes: &[u8], at: u64) -> Option<u32> {
    let at = usize::try_from(at).ok()?;
    Some(u32::from_le_bytes(bytes.get(at..at.checked_add(4)?)?.try_into().ok()?))
}

/// An entry of a crate file's table of contents: a NUL-padded name, where
/// the section starts and how many bytes it takes.
#[derive(Clone, Copy)]
struct Section {
    name: [u8; 16],
    start: u64,
    size: u64,
}

impl Section {
    /// The name up to its NUL (`?` when it is not UTF-8).
    fn name(&self) -> &str {
        let end = self.name.iter().position(|&b| b == 0).unwrap_or(16);
        std::str::from_utf8(&self.name[..end]).unwrap_or("?")
    }
}

/// The `count` entries of the table of contents at byte `toc` (a count,
/// then 32 bytes an entry); `None` when they run past the end.
fn read_sections(bytes: &[u8], toc: u64, count: u64) -> Option<Vec<Section>> {
    (0..count)
        .map(|i| {
            let at = toc.checked_add(8 + 32 * i)?;
            let name = bytes.get(usize::try_from(at).ok()?..)?.get(..16)?.try_into().ok()?;
            Some(Section { name, start: le_u64(bytes, at + 16)?, size: le_u64(bytes, at + 24)? })
        })
        .collect()
}

/// The `openusd` crate reader allocates what a count in the file asks for
/// before it reads the elements, and a failed allocation aborts the process:
/// every count it would allocate for is checked first against the bytes
/// that could hold it. The table of contents and the structural sections'
/// counts (tokens, strings, fields, field sets, paths, specs) against their
/// section, then every array value's count against the rest of the file
/// (uncompressed: a byte or more an element; compressed: at most
/// [`MOST_PER_BYTE`] elements a byte).
fn bounded_counts(bytes: &[u8], ctx: Ctx<'_>) -> Result<(), IoError> {
    let len = bytes.len() as u64;
    let u64_at = |at: u64| le_u64(bytes, at);
    let corrupt = |what: String| parse_error(ctx, format!("corrupt USD crate file: {what}"));
    if bytes.len() < 24 {
        return Err(ctx.truncated(None, format!("a crate file's header takes 24 bytes, the file has {len}")));
    }
    let version = (bytes[8], bytes[9], bytes[10]);
    let toc = u64_at(16).filter(|&t| t < len).ok_or_else(|| corrupt("table of contents past the end".into()))?;
    let count = u64_at(toc).ok_or_else(|| corrupt("table of contents past the end".into()))?;
    if count > 64 || toc + 8 + 32 * count > len {
        return Err(corrupt(format!("{count} sections in the table of contents")));
    }
    let sections = read_sections(bytes, toc, count).ok_or_else(|| corrupt("table of contents past the end".into()))?;
    for section in &sections {
        let (name, start, size) = (section.name(), section.start, section.size);
        // Named in messages: printable, on one line.
        let shown: String = name.escape_default().collect();
        if start.checked_add(size).is_none_or(|end| end > len) {
            return Err(corrupt(format!("section {shown} lies past the end of the file")));
        }
        let end = start + size;
        let too_many = |count: Option<u64>, most: u64| count.is_none_or(|c| c > most);
        let many = MOST_PER_BYTE * (size + 64);
        // (counts at the start, LZ4 blocks after them) of each structural section.
        let (counts, blocks) = match name {
            "STRINGS" => {
                if too_many(u64_at(start), size / 4) {
                    return Err(corrupt(format!("section {shown} claims more entries than its {size} bytes hold")));
                }
                continue;
            }
            "TOKENS" => (2, 1),
            "FIELDS" => (1, 2),
            "FIELDSETS" => (1, 1),
            "PATHS" => (2, 3),
            "SPECS" => (1, 3),
            _ => continue,
        };
        for k in 0..counts {
            if too_many(u64_at(start + 8 * k), many) {
                return Err(corrupt(format!("section {shown} claims more entries than its {size} bytes hold")));
            }
        }
        let mut at = start + 8 * counts;
        for _ in 0..blocks {
            let room = end.saturating_sub(at + 8);
            match u64_at(at).filter(|&block| block <= room) {
                Some(block) => at += 8 + block,
                None => return Err(corrupt(format!("a compressed block of section {shown} runs past the section"))),
            }
        }
    }
    let file = guarded(ctx, || openusd::usdc::CrateFile::open(Cursor::new(bytes)))?
        .map_err(|e| usd_error(ctx, "usdc", &e.into()))?;
    let mut walk = CrateWalk { bytes, version, decoded: 0, budget: DECODED_BYTES_PER_BYTE * len + DECODED_BYTES_FLOOR };
    guarded(ctx, || walk.every_field(&file))?.map_err(corrupt)
}

/// What decoding a whole crate file may allocate, per byte of the file
/// (plus [`DECODED_BYTES_FLOOR`]): a field shared by many specs, a time
/// sample or a token repeated by index are decoded once per use, so a small
/// file can ask for far more memory than it holds.
const DECODED_BYTES_PER_BYTE: u64 = 256;
/// See [`DECODED_BYTES_PER_BYTE`].
const DECODED_BYTES_FLOOR: u64 = 1 << 30;
/// How deeply dictionaries, time samples and references may nest.
const MOST_NESTING: u32 = 16;

/// A walk over every value the `openusd` crate reader would decode for
/// [`sdf::Data::from_abstract`], mirroring its reads (openusd 0.6's
/// `CrateFile::value`) without allocating: each count it would allocate
/// for is checked against the bytes that could hold it, nesting is bounded
/// (a dictionary that contains itself would overflow the stack), and the
/// sum of what would be decoded against a budget.
struct CrateWalk<'a> {
    bytes: &'a [u8],
    version: (u8, u8, u8),
    decoded: u64,
    budget: u64,
}

/// Bytes a decoded string or path takes besides its text.
const STRING_OVERHEAD: u64 = 24;

impl CrateWalk<'_> {
    fn len(&self) -> u64 {
        self.bytes.len() as u64
    }

    fn u64_at(&self, at: u64) -> Result<u64, String> {
        le_u64(self.bytes, at).ok_or_else(|| format!("a value at byte {at} lies past the end of the file"))
    }

    fn u32_at(&self, at: u64) -> Result<u32, String> {
        le_u32(self.bytes, at).ok_or_else(|| format!("a value at byte {at} lies past the end of the file"))
    }

    /// A count at `at` of items of `item` bytes each that follow it.
    fn count_at(&self, at: u64, item: u64) -> Result<u64, String> {
        let count = self.u64_at(at)?;
        let room = self.len().saturating_sub(at + 8);
        if count > room / item.max(1) {
            return Err(format!("a list at byte {at} claims {count} items, more than the file holds"));
        }
        Ok(count)
    }

    fn decode(&mut self, bytes: u64) -> Result<(), String> {
        self.decoded = self.decoded.saturating_add(bytes);
        if self.decoded > self.budget {
            return Err(format!("decoding it would take more than {} bytes", self.budget));
        }
        Ok(())
    }

    /// Every field of every spec, as `from_abstract` reads them.
    fn every_field<R>(&mut self, file: &openusd::usdc::CrateFile<R>) -> Result<(), String> {
        for spec in &file.specs {
            let slots = file.fieldsets.get(spec.fieldset_index..).unwrap_or(&[]);
            for index in slots.iter().map_while(|slot| *slot) {
                let field = file.fields.get(index).ok_or("a field set names a field that does not exist")?;
                self.value(file, Rep(field.value_rep.0), 0)?;
            }
        }
        Ok(())
    }

    /// The bytes a string-table or token index decodes to.
    fn indexed_text<R>(&self, file: &openusd::usdc::CrateFile<R>, table: Table, index: u32) -> u64 {
        let index = index as usize;
        let text = match table {
            Table::Tokens => file.tokens.get(index).map(String::len),
            Table::Strings => file.strings.get(index).and_then(|&t| file.tokens.get(t)).map(String::len),
            Table::Paths => file.paths.get(index).map(|p| p.as_str().len()),
        };
        STRING_OVERHEAD + text.unwrap_or(0) as u64
    }

    /// A count-prefixed vector of `u32` indices at `at`; where it ends.
    fn indexed_vec<R>(&mut self, file: &openusd::usdc::CrateFile<R>, at: u64, table: Table) -> Result<u64, String> {
        let count = self.count_at(at, 4)?;
        for i in 0..count {
            let bytes = self.indexed_text(file, table, self.u32_at(at + 8 + 4 * i)?);
            self.decode(bytes)?;
        }
        Ok(at + 8 + 4 * count)
    }

    fn value<R>(&mut self, file: &openusd::usdc::CrateFile<R>, rep: Rep, depth: u32) -> Result<(), String> {
        if depth > MOST_NESTING {
            return Err(format!("values nested more than {MOST_NESTING} deep"));
        }
        let ty = rep.ty();
        // The reader takes an array's payload (and a payload list
        // operation's) as an offset even when the inlined flag is set.
        if rep.is_inlined() && !rep.is_array() && ty != 55 {
            return Ok(());
        }
        let at = rep.payload();
        match ty {
            // Arrays of numbers, vectors, matrices and quaternions; a time
            // sample's times (a double vector) and time codes read as arrays.
            1..=9 | 13..=30 | 48 | 56 if rep.is_array() || ty == 48 => self.numbers(ty, rep),
            // Token arrays: indices after an array count.
            11 if rep.is_array() => {
                let (count, data) = self.array_count(rep)?;
                if count > self.len().saturating_sub(data) / 4 {
                    return Err(format!("a token array at byte {at} claims {count} items, more than the file holds"));
                }
                for i in 0..count {
                    let bytes = self.indexed_text(file, Table::Tokens, self.u32_at(data + 4 * i)?);
                    self.decode(bytes)?;
                }
                Ok(())
            }
            // String, asset-path and path-expression arrays, string vectors.
            10 | 12 | 57 if rep.is_array() => self.indexed_vec(file, at, Table::Strings).map(drop),
            50 => self.indexed_vec(file, at, Table::Strings).map(drop),
            // Token and path vectors.
            41 => self.indexed_vec(file, at, Table::Tokens).map(drop),
            40 => self.indexed_vec(file, at, Table::Paths).map(drop),
            // Layer offsets (two doubles each), variant selections and
            // relocates (two indices each).
            49 => self.count_at(at, 16).and_then(|n| self.decode(16 * n)),
            45 | 58 => self.count_at(at, 8).and_then(|n| self.decode(2 * (STRING_OVERHEAD + 64) * n)),
            // List operations of indices or numbers.
            32 => self.list_op(file, at, ListItems::Indexed(Table::Tokens), depth),
            33 | 54 => self.list_op(file, at, ListItems::Indexed(Table::Strings), depth),
            34 => self.list_op(file, at, ListItems::Indexed(Table::Paths), depth),
            36 | 38 => self.list_op(file, at, ListItems::Numbers(4), depth),
            37 | 39 => self.list_op(file, at, ListItems::Numbers(8), depth),
            35 => self.list_op(file, at, ListItems::References, depth),
            55 => self.list_op(file, at, ListItems::Payloads, depth),
            31 => self.dictionary(file, at, depth).map(drop),
            46 => self.time_samples(file, at, depth),
            // Scalars (fixed size), payloads, blocks.
            _ => Ok(()),
        }
    }

    /// An array's element count (after the pre-0.5 shape word; 32 bits
    /// before 0.7) and where its data starts.
    fn array_count(&self, rep: Rep) -> Result<(u64, u64), String> {
        if rep.payload() == 0 {
            return Ok((0, 0));
        }
        let mut at = rep.payload();
        if self.version < (0, 5, 0) {
            at += 4;
        }
        if self.version < (0, 7, 0) {
            Ok((u64::from(self.u32_at(at)?), at + 4))
        } else {
            Ok((self.u64_at(at)?, at + 8))
        }
    }

    /// An array of numbers: uncompressed, a byte or more an element;
    /// compressed integers or floats, at most [`MOST_PER_BYTE`] elements a
    /// byte, with the sizes inside (the LZ4 block's, a lookup table's)
    /// checked too.
    fn numbers(&mut self, ty: u64, rep: Rep) -> Result<(), String> {
        let size: u64 = match ty {
            1 | 2 => 1,
            7 => 2,
            3 | 4 | 8 => 4,
            5 | 6 | 9 | 48 | 56 => 8,
            13 => 32,
            14 => 72,
            15 => 128,
            16 | 27 => 32,
            17 | 30 | 28 => 16,
            18 | 29 | 20 | 22 => 8,
            19 => 16,
            21 => 4,
            23 => 24,
            24 | 26 => 12,
            25 => 6,
            _ => 8,
        };
        let (count, data) = self.array_count(rep)?;
        if count == 0 {
            return Ok(());
        }
        let room = self.len().saturating_sub(data);
        let ints = (3..=6).contains(&ty);
        let floats = matches!(ty, 7..=9 | 48 | 56);
        let compressed = rep.is_compressed()
            && count >= 4
            && ((ints && self.version >= (0, 5, 0)) || (floats && self.version >= (0, 6, 0)));
        let most = if compressed { MOST_PER_BYTE * (room + 64) } else { room / size };
        if count > most {
            return Err(format!(
                "an array at byte {} claims {count} elements, more than the file holds",
                rep.payload()
            ));
        }
        self.decode(count * size.max(4))?;
        if !compressed {
            return Ok(());
        }
        let block = if ints {
            data
        } else {
            match self.bytes.get(data as usize) {
                Some(b'i') => data + 1,
                Some(b't') => {
                    let lut = u64::from(self.u32_at(data + 1)?);
                    if lut > room / size {
                        return Err(format!("a lookup table at byte {data} is larger than the file"));
                    }
                    self.decode(lut * size)?;
                    data + 5 + lut * size
                }
                _ => return Ok(()),
            }
        };
        if self.u64_at(block)? > self.len().saturating_sub(block) {
            return Err(format!("a compressed block at byte {block} is larger than the file"));
        }
        Ok(())
    }

    /// A list operation at `at`: a header byte, then one list per flag
    /// (explicit, added, prepended, appended, deleted, ordered).
    fn list_op<R>(
        &mut self,
        file: &openusd::usdc::CrateFile<R>,
        at: u64,
        items: ListItems,
        depth: u32,
    ) -> Result<(), String> {
        let header = *self.bytes.get(at as usize).ok_or("a list operation lies past the end of the file")?;
        let lists = (header >> 1 & 0x3F).count_ones();
        let mut at = at + 1;
        for _ in 0..lists {
            at = match items {
                ListItems::Indexed(table) => self.indexed_vec(file, at, table)?,
                ListItems::Numbers(size) => {
                    let count = self.count_at(at, size)?;
                    self.decode(count * size)?;
                    at + 8 + count * size
                }
                ListItems::Payloads => {
                    let size = if self.version >= (0, 8, 0) { 24 } else { 8 };
                    let count = self.count_at(at, size)?;
                    self.decode(count * (2 * STRING_OVERHEAD + 128))?;
                    at + 8 + count * size
                }
                ListItems::References => {
                    // Each: asset path and prim path indices, a layer offset
                    // (two doubles), a custom-data dictionary.
                    let count = self.count_at(at, 32)?;
                    let mut next = at + 8;
                    for _ in 0..count {
                        self.decode(2 * STRING_OVERHEAD + 128)?;
                        next = self.dictionary(file, next + 24, depth + 1)?;
                    }
                    next
                }
            };
        }
        Ok(())
    }

    /// A dictionary at `at` (a count, then per entry a key index and a
    /// relative jump to the entry's value representation, the next entry
    /// after it); where it ends.
    fn dictionary<R>(&mut self, file: &openusd::usdc::CrateFile<R>, at: u64, depth: u32) -> Result<u64, String> {
        if depth > MOST_NESTING {
            return Err(format!("values nested more than {MOST_NESTING} deep"));
        }
        let count = self.count_at(at, 12)?;
        let mut at = at + 8;
        for _ in 0..count {
            self.decode(STRING_OVERHEAD + 64)?;
            let rep_at = self.jump(at + 4)?;
            self.value(file, Rep(self.u64_at(rep_at)?), depth + 1)?;
            at = rep_at + 8;
        }
        Ok(at)
    }

    /// Time samples at `at`: a jump to the times' representation, then a
    /// jump to a count of value representations.
    fn time_samples<R>(&mut self, file: &openusd::usdc::CrateFile<R>, at: u64, depth: u32) -> Result<(), String> {
        let times_at = self.jump(at)?;
        self.value(file, Rep(self.u64_at(times_at)?), depth + 1)?;
        let reps_at = self.jump(times_at + 8)?;
        let count = self.count_at(reps_at, 8)?;
        for i in 0..count {
            self.value(file, Rep(self.u64_at(reps_at + 8 + 8 * i)?), depth + 1)?;
        }
        Ok(())
    }

    /// Where a relative jump stored at `at` lands (relative to `at`).
    fn jump(&self, at: u64) -> Result<u64, String> {
        let offset = self.u64_at(at)? as i64;
        at.checked_add_signed(offset)
            .filter(|&to| to < self.len())
            .ok_or_else(|| format!("a jump at byte {at} leaves the file"))
    }
}

/// A crate file's value representation (pxr's `ValueRep`): flags in the
/// top bits, the type in bits 48-55, an inline value or a file offset in
/// the low 48 bits.
#[derive(Clone, Copy)]
struct Rep(u64);

impl Rep {
    fn is_array(self) -> bool {
        self.0 & 1 << 63 != 0
    }
    fn is_inlined(self) -> bool {
        self.0 & 1 << 62 != 0
    }
    fn is_compressed(self) -> bool {
        self.0 & 1 << 61 != 0
    }
    /// The type number (pxr's `crateDataTypes.h`).
    fn ty(self) -> u64 {
        self.0 >> 48 & 0xFF
    }
    fn payload(self) -> u64 {
        self.0 & ((1 << 48) - 1)
    }
}

/// The fields whose value pxr reads as a vector (`TfTokenVector`,
/// `std::vector<std::string>`), not an array (`VtArray`): the children and
/// order lists (Sdf's `_IsVectorField`; `properties` is the crate file's
/// name for `propertyChildren`).
const VECTOR_FIELDS: [&str; 11] = [
    "primChildren",
    "properties",
    "propertyChildren",
    "variantChildren",
    "variantSetChildren",
    "expressionChildren",
    "mapperArgChildren",
    "connectionChildren",
    "primOrder",
    "propertyOrder",
    "subLayers",
];

/// A crate file from `openusd` 0.6's writer, made readable by pxr (checked
/// with usd-core 26.11), two fields at a time:
/// - the children and order fields ([`VECTOR_FIELDS`]) retyped from arrays
///   (token\[\], string\[\]) to vectors (TokenVector, StringVector), as pxr
///   writes them: pxr takes a `primChildren` array for invalid children and
///   refuses the layer. The two share their layout in the file (a count,
///   then 32-bit indices): only the value representation changes.
/// - integer arrays of 4 to 15 elements written uncompressed: openusd
///   compresses from 4 elements, pxr reads an array under 16 elements
///   (its `MinCompressedArraySize`) as stored uncompressed whatever its
///   flag says, so it read `faceVertexCounts` of 9 faces as garbage. Each is
///   written again uncompressed after the values, and its fields point there.
///
/// The `FIELDS` section is rebuilt (its representations LZ4-compressed
/// again), the sections moved and the table of contents rewritten. Values
/// nested in dictionaries and time samples are left as written (our meshes
/// author neither; a layer copied from the input may).
fn pxr_compatible(bytes: Vec<u8>) -> Result<Vec<u8>, String> {
    let mut file = openusd::usdc::CrateFile::open(Cursor::new(&bytes)).map_err(|e| format!("{e:#}"))?;
    let toc = le_u64(&bytes, 16).ok_or("no table of contents")?;
    let count = le_u64(&bytes, toc).ok_or("no table of contents")?;
    let mut sections = read_sections(&bytes, toc, count).ok_or("no table of contents")?;
    let values_end = sections.iter().map(|s| s.start).min().ok_or("no sections")? as usize;
    // Uncompressed copies of the short integer arrays, placed at values_end.
    let mut moved: std::collections::HashMap<u64, u64> = std::collections::HashMap::new();
    let mut extra = Vec::new();
    let mut changed = false;
    let mut reps = Vec::with_capacity(file.fields.len());
    for i in 0..file.fields.len() {
        let (token, value_rep) = (file.fields[i].token_index, file.fields[i].value_rep);
        let rep = Rep(value_rep.0);
        let name = file.tokens.get(token).map_or("", String::as_str);
        let short = rep.is_array() && !rep.is_inlined() && rep.is_compressed() && (3..=6).contains(&rep.ty());
        let len = le_u64(&bytes, rep.payload()).unwrap_or(0);
        let new = match rep.ty() {
            11 | 10 if rep.is_array() && !rep.is_inlined() && !rep.is_compressed() && VECTOR_FIELDS.contains(&name) => {
                (if rep.ty() == 11 { 41 } else { 50 }) << 48 | rep.payload()
            }
            _ if short && (4..16).contains(&len) => {
                let at = match moved.get(&rep.payload()) {
                    Some(&at) => at,
                    None => {
                        let at = (values_end + extra.len()) as u64;
                        extra.extend(len.to_le_bytes());
                        match file.value(value_rep).map_err(|e| format!("{e:#}"))? {
                            Value::IntVec(v) => v.iter().for_each(|x| extra.extend(x.to_le_bytes())),
                            Value::UintVec(v) => v.iter().for_each(|x| extra.extend(x.to_le_bytes())),
                            Value::Int64Vec(v) => v.iter().for_each(|x| extra.extend(x.to_le_bytes())),
                            Value::Uint64Vec(v) => v.iter().for_each(|x| extra.extend(x.to_le_bytes())),
                            other => return Err(format!("an integer array read back as {}", kind(&other))),
                        }
                        moved.insert(rep.payload(), at);
                        at
                    }
                };
                rep.ty() << 48 | 1 << 63 | at
            }
            _ => rep.0,
        };
        changed |= new != rep.0;
        reps.push(new);
    }
    if !changed {
        return Ok(bytes);
    }
    let fields = sections.iter().position(|s| s.name() == "FIELDS").ok_or("no FIELDS section")?;
    let (start, size, toc) = (sections[fields].start as usize, sections[fields].size as usize, toc as usize);
    // FIELDS: the field count, the token indices' compressed block (kept),
    // then the representations' compressed block (rebuilt).
    let indices = le_u64(&bytes, start as u64 + 8).ok_or("FIELDS cut short")? as usize;
    let keep = start + 16 + indices;
    let mut raw = Vec::with_capacity(8 * reps.len());
    reps.iter().for_each(|r| raw.extend_from_slice(&r.to_le_bytes()));
    let mut block = vec![0u8]; // one chunk (pxr's TfFastCompression framing)
    block.extend(lz4_flex::compress(&raw));
    let mut section = bytes.get(start..keep).ok_or("FIELDS cut short")?.to_vec();
    section.extend((block.len() as u64).to_le_bytes());
    section.extend(block);
    let end = start + size;
    let mut out = bytes[..values_end].to_vec();
    out.extend(&extra);
    out.extend(&bytes[values_end..start]);
    out.extend(&section);
    out.extend(&bytes[end..toc]);
    let grown = section.len() as i64 - size as i64;
    for s in &mut sections {
        let after_fields = if s.start >= end as u64 { grown } else { 0 };
        s.start = (s.start as i64 + extra.len() as i64 + after_fields) as u64;
    }
    sections[fields].size = section.len() as u64;
    let new_toc = out.len() as u64;
    out.extend(count.to_le_bytes());
    for s in &sections {
        out.extend(s.name);
        out.extend(s.start.to_le_bytes());
        out.extend(s.size.to_le_bytes());
    }
    out[16..24].copy_from_slice(&new_toc.to_le_bytes());
    Ok(out)
}

/// Which table an index names.
#[derive(Clone, Copy)]
enum Table {
    Tokens,
    Strings,
    Paths,
}

/// What a list operation's lists hold.
#[derive(Clone, Copy)]
enum ListItems {
    Indexed(Table),
    Numbers(u64),
    References,
    Payloads,
}

/// Every `def Mesh` prim of the layer.
fn read_meshes(layer: &sdf::Data, ctx: Ctx<'_>, warnings: &mut Vec<ReadWarning>) -> Result<Vec<UsdMesh>, IoError> {
    let mut meshes = Vec::new();
    for path in layer.spec_paths() {
        if layer.spec_type(&path) != Some(SpecType::Prim) || path.contains_prim_variant_selection() {
            continue;
        }
        let is_mesh =
            matches!(field(layer, &path, FieldKey::TypeName.as_str()).as_deref(), Some(Value::Token(t)) if t == "Mesh");
        let is_def = matches!(
            field(layer, &path, FieldKey::Specifier.as_str()).as_deref(),
            Some(Value::Specifier(Specifier::Def))
        );
        if is_mesh && is_def {
            meshes.push(read_mesh_prim(layer, &path, ctx, warnings)?);
        }
    }
    Ok(meshes)
}

/// A field of a spec, `None` when absent or unreadable.
fn field<'a>(layer: &'a sdf::Data, path: &sdf::Path, name: &str) -> Option<Cow<'a, Value>> {
    layer.try_field(path, name).ok().flatten()
}

/// What one attribute of a prim holds: its default, else its earliest time
/// sample; `None` when neither is authored (or the value is blocked).
fn attribute(layer: &sdf::Data, prim: &sdf::Path, name: &str, ctx: Ctx<'_>) -> Result<Option<Value>, IoError> {
    let path = prim.append_property(name).map_err(|e| usd_error(ctx, name, &e.into()))?;
    if !layer.has_spec(&path) {
        return Ok(None);
    }
    if let Some(value) = field(layer, &path, FieldKey::Default.as_str()) {
        return Ok((!matches!(*value, Value::ValueBlock)).then(|| value.into_owned()));
    }
    if let Some(Value::TimeSamples(samples)) = field(layer, &path, FieldKey::TimeSamples.as_str()).as_deref() {
        let earliest = samples.iter().min_by(|a, b| a.0.total_cmp(&b.0));
        return Ok(earliest.map(|(_, v)| v.clone()).filter(|v| !matches!(v, Value::ValueBlock)));
    }
    Ok(None)
}

/// Names a USD value's kind in messages.
fn kind(value: &Value) -> String {
    let debug = format!("{value:?}");
    debug.split(['(', ' ', '{']).next().unwrap_or("value").to_string()
}

/// Reads one Mesh prim.
fn read_mesh_prim(
    layer: &sdf::Data,
    prim: &sdf::Path,
    ctx: Ctx<'_>,
    warnings: &mut Vec<ReadWarning>,
) -> Result<UsdMesh, IoError> {
    let at = |name: &str| format!("{prim}.{name}");
    let bad = |name: &str, message: String| parse_error(ctx, format!("{}: {message}", at(name)));
    let get = |name: &str| attribute(layer, prim, name, ctx);

    let positions: Vec<DVec3> = match get("points")? {
        None => Vec::new(),
        Some(Value::Vec3fVec(v)) => v.iter().map(|p| DVec3::new(p.x.into(), p.y.into(), p.z.into())).collect(),
        Some(Value::Vec3dVec(v)) => v.iter().map(|p| DVec3::new(p.x, p.y, p.z)).collect(),
        Some(Value::Vec3hVec(v)) => v.iter().map(|p| DVec3::new(p.x.to_f64(), p.y.to_f64(), p.z.to_f64())).collect(),
        Some(other) => return Err(bad("points", format!("expected point3f[], found {}", kind(&other)))),
    };
    let counts = indices(get("faceVertexCounts")?, "faceVertexCounts", &bad)?.unwrap_or_default();
    let corners = indices(get("faceVertexIndices")?, "faceVertexIndices", &bad)?.unwrap_or_default();
    let mut offsets = Vec::with_capacity(counts.len() + 1);
    offsets.push(0u32);
    let mut total = 0u64;
    for &c in &counts {
        total += u64::from(c);
        if total > corners.len() as u64 {
            break;
        }
        offsets.push(total as u32);
    }
    if total != corners.len() as u64 {
        return Err(bad(
            "faceVertexCounts",
            format!("the counts add up to {total}, but faceVertexIndices has {} entries", corners.len()),
        ));
    }
    let left_handed = match get("orientation")? {
        None => false,
        Some(Value::Token(t)) if t == "rightHanded" => false,
        Some(Value::Token(t)) if t == "leftHanded" => true,
        Some(other) => return Err(bad("orientation", format!("expected rightHanded or leftHanded, found {other:?}"))),
    };
    let mut faces = FaceList::from_raw(offsets, corners);
    let scheme = match token(get("subdivisionScheme")?, "subdivisionScheme", &bad)? {
        None => SubdivisionScheme::CatmullClark,
        Some(t) => SubdivisionScheme::from_token(&t).ok_or_else(|| {
            bad("subdivisionScheme", format!("'{t}' is not a scheme (catmullClark, loop, bilinear, none)"))
        })?,
    };

    let mut tags = TagList::default();
    let options = &mut tags.options;
    options.boundary = match token(get("interpolateBoundary")?, "interpolateBoundary", &bad)?.as_deref() {
        None => None,
        Some("none") => Some(BoundaryInterpolation::None),
        Some("edgeOnly") => Some(BoundaryInterpolation::EdgeOnly),
        Some("edgeAndCorner") => Some(BoundaryInterpolation::EdgeAndCorner),
        Some(t) => return Err(bad("interpolateBoundary", format!("'{t}' is not none, edgeOnly or edgeAndCorner"))),
    };
    options.fvar =
        match token(get("faceVaryingLinearInterpolation")?, "faceVaryingLinearInterpolation", &bad)?.as_deref() {
            None => None,
            Some(t) => Some(fvar_from_token(t).ok_or_else(|| {
                bad(
                    "faceVaryingLinearInterpolation",
                    format!("'{t}' is not none, cornersOnly, cornersPlus1, cornersPlus2, boundaries or all"),
                )
            })?),
        };
    options.triangle_rule = match token(get("triangleSubdivisionRule")?, "triangleSubdivisionRule", &bad)?.as_deref() {
        None => None,
        Some("catmullClark") => Some(TriangleRule::Catmark),
        Some("smooth") => Some(TriangleRule::Smooth),
        Some(t) => return Err(bad("triangleSubdivisionRule", format!("'{t}' is not catmullClark or smooth"))),
    };
    options.crease_method = match token(get(CREASE_METHOD)?, CREASE_METHOD, &bad)?.as_deref() {
        None => None,
        Some("uniform") => Some(CreaseMethod::Uniform),
        Some("chaikin") => Some(CreaseMethod::Chaikin),
        Some(t) => return Err(bad(CREASE_METHOD, format!("'{t}' is not uniform or chaikin"))),
    };

    // Creases: chains of `lengths[i]` vertices, one sharpness per chain or per edge.
    let crease_indices = indices(get("creaseIndices")?, "creaseIndices", &bad)?.unwrap_or_default();
    let lengths = indices(get("creaseLengths")?, "creaseLengths", &bad)?.unwrap_or_default();
    let sharpness = floats(get("creaseSharpnesses")?, "creaseSharpnesses", &bad)?.unwrap_or_default();
    let mut in_chains = 0u64;
    let mut edges = 0u64;
    for (i, &n) in lengths.iter().enumerate() {
        if n < 2 {
            return Err(bad("creaseLengths", format!("crease {i} has {n} vertices; a crease has at least 2")));
        }
        in_chains += u64::from(n);
        edges += u64::from(n) - 1;
    }
    if in_chains != crease_indices.len() as u64 {
        return Err(bad(
            "creaseLengths",
            format!("the lengths add up to {in_chains}, but creaseIndices has {} entries", crease_indices.len()),
        ));
    }
    let per_edge = sharpness.len() as u64 == edges && sharpness.len() != lengths.len();
    if !per_edge && sharpness.len() != lengths.len() {
        return Err(bad(
            "creaseSharpnesses",
            format!(
                "{} values for {} creases of {edges} edges (one per crease or one per edge)",
                sharpness.len(),
                lengths.len()
            ),
        ));
    }
    let mut start = 0usize;
    let mut edge = 0usize;
    for (i, &n) in lengths.iter().enumerate() {
        let chain = &crease_indices[start..start + n as usize];
        for pair in chain.windows(2) {
            let s = if per_edge { sharpness[edge] } else { sharpness[i] };
            tags.creases.push(EdgeTag { a: pair[0], b: pair[1], sharpness: s });
            edge += 1;
        }
        start += n as usize;
    }
    let corner_indices = indices(get("cornerIndices")?, "cornerIndices", &bad)?.unwrap_or_default();
    let corner_sharpness = floats(get("cornerSharpnesses")?, "cornerSharpnesses", &bad)?.unwrap_or_default();
    if corner_indices.len() != corner_sharpness.len() {
        return Err(bad(
            "cornerSharpnesses",
            format!("{} values for {} corner indices", corner_sharpness.len(), corner_indices.len()),
        ));
    }
    tags.corners =
        corner_indices.iter().zip(&corner_sharpness).map(|(&vertex, &s)| VertexTag { vertex, sharpness: s }).collect();
    tags.holes = indices(get("holeIndices")?, "holeIndices", &bad)?.unwrap_or_default();

    let mut uvs = read_st(layer, prim, &faces, positions.len(), ctx, &bad, warnings)?;
    if uvs.is_some() && tags.options.fvar.is_none() {
        // USD's fallback, which is not OpenSubdiv's (and our) default `all`.
        tags.options.fvar = Some(FVarInterpolation::LinearCornersPlus1);
    }
    if left_handed {
        faces = reversed(&faces);
        if let Some(uvs) = &mut uvs {
            uvs.indices = reversed(&FaceList::from_raw(faces.offsets().to_vec(), std::mem::take(&mut uvs.indices)))
                .indices()
                .to_vec();
        }
    }
    let soup = PolygonSoup { positions, faces, tags, uvs, ..Default::default() };
    Ok(UsdMesh { path: prim.to_string(), soup, scheme })
}

/// Our custom attribute for the crease method, which USD has no attribute for.
const CREASE_METHOD: &str = "subdiv:creaseMethod";

/// Every face with its corners reversed after the first (`a b c d` → `a d c b`).
fn reversed(faces: &FaceList) -> FaceList {
    let mut indices = Vec::with_capacity(faces.corner_count());
    for face in faces.iter() {
        if let Some((&first, rest)) = face.split_first() {
            indices.push(first);
            indices.extend(rest.iter().rev());
        }
    }
    FaceList::from_raw(faces.offsets().to_vec(), indices)
}

/// `primvars:st` as a face-varying channel (face-varying or per vertex,
/// indexed or not); uniform and constant ones are dropped with a warning.
fn read_st(
    layer: &sdf::Data,
    prim: &sdf::Path,
    faces: &FaceList,
    vertices: usize,
    ctx: Ctx<'_>,
    bad: &dyn Fn(&str, String) -> IoError,
    warnings: &mut Vec<ReadWarning>,
) -> Result<Option<FaceVarying>, IoError> {
    const ST: &str = "primvars:st";
    let values: Vec<DVec2> = match attribute(layer, prim, ST, ctx)? {
        None => return Ok(None),
        Some(Value::Vec2fVec(v)) => v.iter().map(|p| DVec2::new(p.x.into(), p.y.into())).collect(),
        Some(Value::Vec2dVec(v)) => v.iter().map(|p| DVec2::new(p.x, p.y)).collect(),
        Some(Value::Vec2hVec(v)) => v.iter().map(|p| DVec2::new(p.x.to_f64(), p.y.to_f64())).collect(),
        Some(other) => return Err(bad(ST, format!("expected texCoord2f[], found {}", kind(&other)))),
    };
    let path = prim.append_property(ST).map_err(|e| usd_error(ctx, ST, &e.into()))?;
    let interpolation = match field(layer, &path, "interpolation").as_deref() {
        Some(Value::Token(t)) => t.as_str().to_string(),
        _ => "constant".to_string(),
    };
    let indexed = indices(attribute(layer, prim, "primvars:st:indices", ctx)?, "primvars:st:indices", bad)?;
    let corners = faces.corner_count();
    let expected = match interpolation.as_str() {
        "faceVarying" => corners,
        _ => vertices,
    };
    if indexed.is_none()
        && matches!(interpolation.as_str(), "faceVarying" | "vertex" | "varying")
        && values.len() != expected
    {
        return Err(bad(
            ST,
            format!("{} values for {expected} {interpolation} elements (and no indices)", values.len()),
        ));
    }
    let indices: Vec<u32> = match interpolation.as_str() {
        "faceVarying" => match indexed {
            Some(indices) => indices,
            None => (0..corners as u32).collect(),
        },
        "vertex" | "varying" => match indexed {
            Some(indices) if indices.len() != vertices => {
                return Err(bad(
                    "primvars:st:indices",
                    format!("{} indices for the {vertices} points of a per-vertex primvar", indices.len()),
                ))
            }
            // A corner's value is its vertex's (through the indices when given). A corner out of
            // range of the points is the validator's to report: the value index is left past the end.
            Some(indices) => {
                faces.indices().iter().map(|&v| indices.get(v as usize).copied().unwrap_or(u32::MAX)).collect()
            }
            None => faces.indices().to_vec(),
        },
        other => {
            warnings.push(ReadWarning::UvsDropped {
                path: ctx.path.to_path_buf(),
                line: None,
                reason: format!("{prim}.{ST} has {other} interpolation (faceVarying and vertex are read)"),
            });
            return Ok(None);
        }
    };
    if indices.len() != corners {
        return Err(bad(
            "primvars:st",
            format!("{} face-varying values or indices for {corners} face corners", indices.len()),
        ));
    }
    Ok(Some(FaceVarying { values, indices }))
}

/// An `int[]` attribute as indices: negative values are errors (USD's
/// indices and counts are never negative), `None` when unauthored.
fn indices(
    value: Option<Value>,
    name: &str,
    bad: &dyn Fn(&str, String) -> IoError,
) -> Result<Option<Vec<u32>>, IoError> {
    let convert = |v: i64, i: usize| {
        u32::try_from(v).map_err(|_| bad(name, format!("entry {i} is {v}: not an index or count (0 to 2^32 - 1)")))
    };
    Ok(Some(match value {
        None => return Ok(None),
        Some(Value::IntVec(v)) => v.iter().enumerate().map(|(i, &x)| convert(x.into(), i)).collect::<Result<_, _>>()?,
        Some(Value::Int64Vec(v)) => v.iter().enumerate().map(|(i, &x)| convert(x, i)).collect::<Result<_, _>>()?,
        Some(Value::UintVec(v)) => v,
        Some(other) => return Err(bad(name, format!("expected int[], found {}", kind(&other)))),
    }))
}

/// A `float[]` attribute, `None` when unauthored.
fn floats(
    value: Option<Value>,
    name: &str,
    bad: &dyn Fn(&str, String) -> IoError,
) -> Result<Option<Vec<f32>>, IoError> {
    Ok(Some(match value {
        None => return Ok(None),
        Some(Value::FloatVec(v)) => v,
        Some(Value::DoubleVec(v)) => v.iter().map(|&x| x as f32).collect(),
        Some(Value::HalfVec(v)) => v.iter().map(|x| x.to_f32()).collect(),
        Some(other) => return Err(bad(name, format!("expected float[], found {}", kind(&other)))),
    }))
}

/// A `token` attribute, `None` when unauthored.
fn token(value: Option<Value>, name: &str, bad: &dyn Fn(&str, String) -> IoError) -> Result<Option<String>, IoError> {
    match value {
        None => Ok(None),
        Some(Value::Token(t)) => Ok(Some(t.as_str().to_string())),
        Some(Value::String(s)) => Ok(Some(s)),
        Some(other) => Err(bad(name, format!("expected a token, found {}", kind(&other)))),
    }
}

fn fvar_from_token(token: &str) -> Option<FVarInterpolation> {
    FVAR_TOKENS.iter().find(|(t, _)| *t == token).map(|&(_, f)| f)
}

fn fvar_token(fvar: FVarInterpolation) -> &'static str {
    FVAR_TOKENS.iter().find(|(_, f)| *f == fvar).map_or("all", |&(t, _)| t)
}

/// `faceVaryingLinearInterpolation`'s tokens and OpenSubdiv's modes.
const FVAR_TOKENS: [(&str, FVarInterpolation); 6] = [
    ("none", FVarInterpolation::LinearNone),
    ("cornersOnly", FVarInterpolation::LinearCornersOnly),
    ("cornersPlus1", FVarInterpolation::LinearCornersPlus1),
    ("cornersPlus2", FVarInterpolation::LinearCornersPlus2),
    ("boundaries", FVarInterpolation::LinearBoundaries),
    ("all", FVarInterpolation::LinearAll),
];

// ---------------------------------------------------------------- writing

/// Encodes meshes at their prim paths as a USD layer of `format`, into a
/// copy of `template`'s layer when given (each mesh replacing the prim of
/// its path, the rest of the layer kept), else into a new layer.
///
/// # Errors
/// [`IoError::InvalidMesh`] for a prim path that is not an absolute prim
/// path, a path given twice, an index out of range, a coordinate that does
/// not fit `f32`, or a format that is not USD.
pub fn write_scene_to_vec(
    template: Option<&UsdScene>,
    meshes: &[SceneMesh<'_>],
    format: Format,
) -> Result<Vec<u8>, IoError> {
    encode(template, meshes, format, Ctx::new(Path::new("<memory>")))
}

/// [`write_scene_to_vec`] into a temporary file beside `path`, to be
/// committed with [`StagedFile::commit`] or [`crate::commit_all`].
///
/// # Errors
/// Those of [`write_scene_to_vec`] (naming `path`), and [`IoError::Io`].
pub fn stage_scene(
    path: &Path,
    template: Option<&UsdScene>,
    meshes: &[SceneMesh<'_>],
    format: Format,
) -> Result<StagedFile, IoError> {
    let bytes = encode(template, meshes, format, Ctx::new(path))?;
    crate::stage_bytes(path, &bytes)
}

/// The single mesh of [`crate::write_mesh_to_vec`] and its kin, at
/// [`DEFAULT_PRIM_PATH`], its scheme unauthored.
pub(crate) fn write(mesh: &MeshView<'_>, format: Format, ctx: Ctx<'_>) -> Result<Vec<u8>, IoError> {
    encode(None, &[SceneMesh { path: DEFAULT_PRIM_PATH, view: *mesh, scheme: None }], format, ctx)
}

fn encode(
    template: Option<&UsdScene>,
    meshes: &[SceneMesh<'_>],
    format: Format,
    ctx: Ctx<'_>,
) -> Result<Vec<u8>, IoError> {
    if !format.is_usd() {
        return Err(ctx.invalid(format!("{format} is not a USD format")));
    }
    let mut layer = match template {
        Some(scene) => scene.layer.clone(),
        None => sdf::Data::new(),
    };
    let root = sdf::Path::abs_root();
    if !layer.has_spec(&root) {
        layer.create_spec(root.clone(), SpecType::PseudoRoot);
    }
    let mut seen = std::collections::HashSet::new();
    for mesh in meshes {
        crate::check(&mesh.view, format, ctx)?;
        let path = sdf::Path::new(mesh.path)
            .ok()
            .filter(|p| p.is_abs() && !p.is_abs_root() && !p.is_property_path() && !p.contains_prim_variant_selection())
            .ok_or_else(|| ctx.invalid(format!("'{}' is not an absolute prim path", mesh.path)))?;
        if !seen.insert(path.clone()) {
            return Err(ctx.invalid(format!("two meshes at {path}")));
        }
        define_ancestors(&mut layer, &path);
        write_mesh_prim(&mut layer, &path, mesh)?;
    }
    if field(&layer, &root, FieldKey::DefaultPrim.as_str()).is_none() {
        if let Some(Value::TokenVec(children)) = field(&layer, &root, ChildrenKey::PrimChildren.as_str()).as_deref() {
            if let Some(first) = children.first().cloned() {
                layer.set_field(&root, FieldKey::DefaultPrim.as_str(), Value::Token(first));
            }
        }
    }
    let written = guarded(ctx, || -> Result<Vec<u8>, IoError> {
        let fail = |e: anyhow_chain::Chain| ctx.invalid(format!("the USD writer failed: {}", e.0));
        let crate_bytes = || {
            let mut out = Cursor::new(Vec::new());
            openusd::usdc::CrateWriter::write(&layer, &mut out).map_err(|e| fail(e.into()))?;
            pxr_compatible(out.into_inner()).map_err(|e| ctx.invalid(format!("the USD writer failed: {e}")))
        };
        match format {
            Format::Usda => {
                let mut out = Vec::new();
                openusd::usda::TextWriter::write(&layer, &mut out).map_err(|e| fail(e.into()))?;
                Ok(out)
            }
            Format::Usdz => {
                let layer_bytes = crate_bytes()?;
                let mut archive = openusd::usdz::ArchiveWriter::new(Cursor::new(Vec::new()));
                archive.add_layer("scene.usdc", &layer_bytes).map_err(|e| fail(e.into()))?;
                Ok(archive.finish().map_err(|e| fail(e.into()))?.into_inner())
            }
            _ => crate_bytes(),
        }
    });
    written?
}

/// Adds `name` to a token-list field of a spec (children lists), once.
fn add_child(layer: &mut sdf::Data, parent: &sdf::Path, key: ChildrenKey, name: &str) {
    let mut children = match field(layer, parent, key.as_str()).as_deref() {
        Some(Value::TokenVec(v)) => v.clone(),
        _ => Vec::new(),
    };
    if !children.iter().any(|c| c == name) {
        children.push(name.into());
        layer.set_field(parent, key.as_str(), Value::TokenVec(children));
    }
}

/// Defines every missing ancestor of `path` as an `Xform`, and lists each
/// prim among its parent's children.
fn define_ancestors(layer: &mut sdf::Data, path: &sdf::Path) {
    let mut chain: Vec<sdf::Path> = path.ancestors().take_while(|p| !p.is_abs_root()).collect();
    chain.reverse();
    for (i, prim) in chain.iter().enumerate() {
        let parent = prim.parent().unwrap_or_else(sdf::Path::abs_root);
        if let Some(name) = prim.name() {
            let name = name.to_string();
            add_child(layer, &parent, ChildrenKey::PrimChildren, &name);
        }
        if !layer.has_spec(prim) {
            layer.create_spec(prim.clone(), SpecType::Prim);
            layer.set_field(prim, FieldKey::Specifier.as_str(), Value::Specifier(Specifier::Def));
            if i + 1 < chain.len() {
                layer.set_field(prim, FieldKey::TypeName.as_str(), Value::Token("Xform".into()));
            }
        }
    }
}

/// The properties of a mesh prim that the writer owns: replaced on every
/// write. `primvars:st*`, `normals` and `extent` are among them.
const GEOMETRY: [&str; 18] = [
    "points",
    "faceVertexCounts",
    "faceVertexIndices",
    "orientation",
    "subdivisionScheme",
    "interpolateBoundary",
    "faceVaryingLinearInterpolation",
    "triangleSubdivisionRule",
    "creaseIndices",
    "creaseLengths",
    "creaseSharpnesses",
    "cornerIndices",
    "cornerSharpnesses",
    "holeIndices",
    "normals",
    "extent",
    "primvars:st",
    "primvars:st:indices",
];

/// Writes one Mesh prim at `path` (replacing what a template had there).
fn write_mesh_prim(layer: &mut sdf::Data, path: &sdf::Path, mesh: &SceneMesh<'_>) -> Result<(), IoError> {
    let view = &mesh.view;
    // What the template's prim had, to tell whether its other primvars and
    // subsets still number the same faces and vertices.
    let before = read_counts(layer, path);
    let same_counts = before == Some((view.positions.len(), view.faces.len()));
    let mut properties: Vec<String> = match field(layer, path, ChildrenKey::PropertyChildren.as_str()).as_deref() {
        Some(Value::TokenVec(v)) => v.iter().map(|t| t.as_str().to_string()).collect(),
        _ => Vec::new(),
    };
    let owned = |name: &str| {
        GEOMETRY.contains(&name) || name == CREASE_METHOD || (!same_counts && name.starts_with("primvars:"))
    };
    for name in properties.iter().filter(|n| owned(n)) {
        if let Ok(p) = path.append_property(name.as_str()) {
            layer.erase_spec(&p);
        }
    }
    properties.retain(|n| !owned(n));
    if !same_counts {
        // GeomSubsets number faces that no longer exist.
        let children = match field(layer, path, ChildrenKey::PrimChildren.as_str()).as_deref() {
            Some(Value::TokenVec(v)) => v.clone(),
            _ => Vec::new(),
        };
        let mut kept = Vec::new();
        for child in children {
            let Ok(child_path) = path.append_path(child.as_str()) else { continue };
            let subset = matches!(field(layer, &child_path, FieldKey::TypeName.as_str()).as_deref(),
                Some(Value::Token(t)) if t == "GeomSubset");
            if subset {
                let doomed: Vec<sdf::Path> =
                    layer.spec_paths().into_iter().filter(|p| p.has_prefix(&child_path)).collect();
                doomed.iter().for_each(|p| {
                    layer.erase_spec(p);
                });
            } else {
                kept.push(child);
            }
        }
        if kept.is_empty() {
            layer.erase_field(path, ChildrenKey::PrimChildren.as_str());
        } else {
            layer.set_field(path, ChildrenKey::PrimChildren.as_str(), Value::TokenVec(kept));
        }
    }
    if !layer.has_spec(path) {
        layer.create_spec(path.clone(), SpecType::Prim);
    }
    layer.set_field(path, FieldKey::Specifier.as_str(), Value::Specifier(Specifier::Def));
    layer.set_field(path, FieldKey::TypeName.as_str(), Value::Token("Mesh".into()));

    let mut attrs: Vec<(&str, &str, bool, Value)> = Vec::new();
    let points: Vec<openusd::gf::Vec3f> = view.positions.iter().map(|p| vec3f(*p)).collect();
    if let Some((lo, hi)) = extent(&points) {
        attrs.push(("extent", "float3[]", false, Value::Vec3fVec(vec![lo, hi])));
    }
    attrs.push(("faceVertexCounts", "int[]", false, ints(view.faces.offsets().windows(2).map(|w| w[1] - w[0]))));
    attrs.push(("faceVertexIndices", "int[]", false, ints(view.faces.indices().iter().copied())));
    attrs.push(("orientation", "token", true, Value::Token("rightHanded".into())));
    attrs.push(("points", "point3f[]", false, Value::Vec3fVec(points)));
    if let Some(scheme) = mesh.scheme {
        attrs.push(("subdivisionScheme", "token", true, Value::Token(scheme.token().into())));
    }
    let empty = TagList::default();
    let tags = view.tags.unwrap_or(&empty);
    let options: FileOptions = tags.options;
    if let Some(b) = options.boundary {
        let t = match b {
            BoundaryInterpolation::None => "none",
            BoundaryInterpolation::EdgeOnly => "edgeOnly",
            BoundaryInterpolation::EdgeAndCorner => "edgeAndCorner",
        };
        attrs.push(("interpolateBoundary", "token", false, Value::Token(t.into())));
    }
    // USD's fallback (cornersPlus1) is not OpenSubdiv's default (all): with
    // texture coordinates the mode is always written.
    let fvar = match (options.fvar, view.uvs) {
        (Some(f), _) => Some(f),
        (None, Some(_)) => Some(FVarInterpolation::default()),
        (None, None) => None,
    };
    if let Some(f) = fvar {
        attrs.push(("faceVaryingLinearInterpolation", "token", false, Value::Token(fvar_token(f).into())));
    }
    if let Some(rule) = options.triangle_rule {
        let t = match rule {
            TriangleRule::Catmark => "catmullClark",
            TriangleRule::Smooth => "smooth",
        };
        attrs.push(("triangleSubdivisionRule", "token", false, Value::Token(t.into())));
    }
    if let Some(method) = options.crease_method {
        let t = match method {
            CreaseMethod::Uniform => "uniform",
            CreaseMethod::Chaikin => "chaikin",
        };
        attrs.push((CREASE_METHOD, "token", true, Value::Token(t.into())));
    }
    if !tags.creases.is_empty() {
        attrs.push(("creaseIndices", "int[]", false, ints(tags.creases.iter().flat_map(|t| [t.a, t.b]))));
        attrs.push(("creaseLengths", "int[]", false, ints(tags.creases.iter().map(|_| 2))));
        let s = tags.creases.iter().map(|t| t.sharpness).collect();
        attrs.push(("creaseSharpnesses", "float[]", false, Value::FloatVec(s)));
    }
    if !tags.corners.is_empty() {
        attrs.push(("cornerIndices", "int[]", false, ints(tags.corners.iter().map(|t| t.vertex))));
        let s = tags.corners.iter().map(|t| t.sharpness).collect();
        attrs.push(("cornerSharpnesses", "float[]", false, Value::FloatVec(s)));
    }
    if !tags.holes.is_empty() {
        attrs.push(("holeIndices", "int[]", false, ints(tags.holes.iter().copied())));
    }
    if let Some(normals) = view.normals {
        let n = normals.iter().map(|p| vec3f(*p)).collect();
        attrs.push(("normals", "normal3f[]", false, Value::Vec3fVec(n)));
    }
    if let Some(uvs) = view.uvs {
        let values = uvs.values.iter().map(|uv| openusd::gf::Vec2f { x: uv.x as f32, y: uv.y as f32 }).collect();
        attrs.push(("primvars:st", "texCoord2f[]", false, Value::Vec2fVec(values)));
        attrs.push(("primvars:st:indices", "int[]", false, ints(uvs.indices.iter().copied())));
    }
    for (name, type_name, uniform, value) in attrs {
        let attr = path.append_property(name).map_err(|e| IoError::InvalidMesh {
            path: Path::new(mesh.path).to_path_buf(),
            message: format!("{name}: {}", anyhow_chain::Chain::from(e).0),
        })?;
        layer.create_spec(attr.clone(), SpecType::Attribute);
        layer.set_field(&attr, FieldKey::TypeName.as_str(), Value::Token(type_name.into()));
        if uniform {
            layer.set_field(&attr, FieldKey::Variability.as_str(), Value::Variability(Variability::Uniform));
        }
        if name == CREASE_METHOD {
            layer.set_field(&attr, FieldKey::Custom.as_str(), Value::Bool(true));
        }
        if name == "primvars:st" {
            layer.set_field(&attr, "interpolation", Value::Token("faceVarying".into()));
        }
        if name == "normals" {
            layer.set_field(&attr, "interpolation", Value::Token("vertex".into()));
        }
        layer.set_field(&attr, FieldKey::Default.as_str(), value);
        if !properties.iter().any(|p| p == name) {
            properties.push(name.to_string());
        }
    }
    let tokens = properties.into_iter().map(Into::into).collect();
    layer.set_field(path, ChildrenKey::PropertyChildren.as_str(), Value::TokenVec(tokens));
    Ok(())
}

/// The point and face counts of the mesh prim a template has at `path`.
fn read_counts(layer: &sdf::Data, path: &sdf::Path) -> Option<(usize, usize)> {
    let len = |name: &str| {
        let attr = path.append_property(name).ok()?;
        match field(layer, &attr, FieldKey::Default.as_str()).as_deref()? {
            Value::Vec3fVec(v) => Some(v.len()),
            Value::Vec3dVec(v) => Some(v.len()),
            Value::Vec3hVec(v) => Some(v.len()),
            Value::IntVec(v) => Some(v.len()),
            _ => None,
        }
    };
    Some((len("points")?, len("faceVertexCounts")?))
}

fn vec3f(p: DVec3) -> openusd::gf::Vec3f {
    openusd::gf::Vec3f { x: p.x as f32, y: p.y as f32, z: p.z as f32 }
}

/// USD's `int[]` from indices (every writer's index fits: `check` saw them
/// below the point count, which is a `Vec` length of `f32` triples).
fn ints(values: impl Iterator<Item = u32>) -> Value {
    Value::IntVec(values.map(|v| v as i32).collect())
}

/// The bounding box of the points, `extent`'s two corners.
fn extent(points: &[openusd::gf::Vec3f]) -> Option<(openusd::gf::Vec3f, openusd::gf::Vec3f)> {
    let first = *points.first()?;
    Some(points.iter().fold((first, first), |(lo, hi), p| {
        (
            openusd::gf::Vec3f { x: lo.x.min(p.x), y: lo.y.min(p.y), z: lo.z.min(p.z) },
            openusd::gf::Vec3f { x: hi.x.max(p.x), y: hi.y.max(p.y), z: hi.z.max(p.z) },
        )
    }))
}
