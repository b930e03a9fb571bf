//! Headless figures: a small deterministic software rasteriser for meshes, RGB images,
//! text from the embedded DejaVu Sans, and side-by-side composition with captions.
//!
//! No GPU, no system fonts, no network: the same inputs give the same bytes on every run.
//!
//! - [`render_panels`]: the panels of one model's figure (input mesh, control mesh, limit
//!   surface), each in its [`Style`], through one [`Camera`] fitted to all of them.
//! - [`render_mesh`]: one mesh, one panel; panels given the same `frame` box ([`frame_of`])
//!   share one camera. [`render_with`] takes the [`Camera`] itself.
//! - [`Canvas`]: several layers in one z-buffer (a limit surface, then its control mesh's
//!   wireframe, then the data points it interpolates, hidden ones left out).
//! - [`overlay_points`] / [`draw_dots`]: dots on a finished [`Image`] (no occlusion).
//! - [`side_by_side`] and [`stack`]: panels with captions and a title, as in the papers' figures.
//!
//! The pipeline: a [`Camera`] looks at the centre of the frame box from the [`View`]'s direction
//! with a perspective of vertical field of view [`FIELD_OF_VIEW_DEG`], scaled so that the
//! projected box corners (or mesh vertices) fill the panel less [`MARGIN`]. Faces are
//! triangulated by ear clipping (non-convex n-gons fill correctly), rasterised at
//! [`SUPERSAMPLING`]² samples per pixel with a z-buffer, shaded in linear light (hemispheric
//! ambient, a Lambert key light above-left of the viewer, a weak fill, a little Blinn-Phong), and
//! box-filtered down. On open meshes the inside is tinted ([`BACK_TINT`]). Edges are
//! capsule-shaped lines tested against the z-buffer with a small depth offset toward the viewer
//! ([`DEPTH_OFFSET`]); dots are drawn where their centre is not hidden.
//!
//! `cargo xtask render MESH -o OUT.png [--style surface|control|input] [--yaw …] [--pitch …]`
//! tries it on a mesh file.
// The figure API is called by the reproduce-paper task; until each entry point has a caller in the
// binary, rustc would report the rest as dead code.
#![allow(dead_code)]

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use ab_glyph::{point, Font, FontRef, PxScale, ScaleFont};
use anyhow::Context;
use subdiv_mesh::{Aabb, DVec3, Mesh};

/// The embedded font, DejaVu Sans (see `xtask/assets/README.md` for its licence).
pub const FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Samples per pixel along each axis; the image is rendered this much larger, then averaged.
pub const SUPERSAMPLING: u32 = 3;
/// Vertical field of view of the perspective camera, in degrees (small: little distortion).
pub const FIELD_OF_VIEW_DEG: f64 = 24.0;
/// Blank border around the projected frame box, as a fraction of the panel's smaller side.
pub const MARGIN: f64 = 0.04;
/// Mean on-screen edge length (pixels) below which [`render_with`] thins edges.
pub const EDGE_THINNING_LENGTH: f64 = 14.0;
/// Edges and dots are drawn when they are at most this far behind the surface, as a fraction of
/// the frame's half-diagonal, so that edges lying on a surface are not lost to round-off.
pub const DEPTH_OFFSET: f64 = 0.006;

/// White.
pub const WHITE: [u8; 3] = [255, 255, 255];
/// Black.
pub const BLACK: [u8; 3] = [0, 0, 0];
/// Fill of limit surfaces: a light steel blue.
pub const SURFACE_FILL: [u8; 3] = [168, 194, 226];
/// Fill of control meshes: a light warm grey, so that the dark edges read.
pub const CONTROL_FILL: [u8; 3] = [222, 216, 204];
/// Fill of input (data) meshes: a pale sand.
pub const INPUT_FILL: [u8; 3] = [236, 214, 160];
/// Colour of polygon edges.
pub const EDGE_COLOUR: [u8; 3] = [38, 38, 52];
/// Colour of data points (interpolated vertices): a strong red.
pub const POINT_COLOUR: [u8; 3] = [214, 39, 40];
/// Back faces (inside of open meshes) are the fill mixed half-and-half with this tint.
pub const BACK_TINT: [u8; 3] = [196, 104, 96];

/// Which model axis points up on screen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Up {
    /// +y is up (most OBJ models, e.g. Spot and the Stanford bunny).
    #[default]
    Y,
    /// +z is up (CAD and scanning conventions); the model's −y then faces the default viewer.
    Z,
}

/// Where the camera looks from. Angles are in degrees.
///
/// With `yaw = pitch = 0` the camera looks at the front of the model (from the +z side of a
/// y-up model) with up on screen. `yaw` turns the camera to the model's right around the up
/// axis, `pitch` lifts it above the model. The [`Default`] is a 3/4 view from above-right.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Rotation of the camera around the up axis, degrees (positive: toward the model's +x).
    pub yaw: f64,
    /// Elevation of the camera above the horizontal, degrees (positive: looking down).
    pub pitch: f64,
    /// Magnification over the auto-fitted size (1: the frame box fills the panel).
    pub zoom: f64,
    /// Which model axis is up on screen.
    pub up: Up,
}

impl Default for View {
    fn default() -> Self {
        Self { yaw: 35.0, pitch: 20.0, zoom: 1.0, up: Up::Y }
    }
}

impl View {
    /// The default 3/4 view turned by `yaw` degrees.
    pub fn yawed(yaw: f64) -> Self {
        Self { yaw, ..Self::default() }
    }
}

/// How one mesh is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Colour of front faces (back faces get it mixed with [`BACK_TINT`]).
    pub fill: [u8; 3],
    /// Draw polygon edges in this colour (for control and input meshes); `None`: no edges.
    pub edges: Option<[u8; 3]>,
    /// Width of edges in output pixels (thinned on dense meshes, see [`render_with`]).
    pub edge_width: f32,
    /// Interpolated per-vertex normals (smooth surfaces) instead of one normal per face.
    pub smooth: bool,
    /// Draw the mesh's vertices as dots of this colour and radius in output pixels
    /// (data points, control points); hidden vertices are not drawn.
    pub points: Option<([u8; 3], f32)>,
    /// Colour behind the model.
    pub background: [u8; 3],
}

impl Default for Style {
    fn default() -> Self {
        Self::surface()
    }
}

impl Style {
    /// A smooth-shaded limit (or refined) surface without edges.
    pub fn surface() -> Self {
        Self { fill: SURFACE_FILL, edges: None, edge_width: 1.3, smooth: true, points: None, background: WHITE }
    }
    /// A flat-shaded control mesh with its edges drawn.
    pub fn control_mesh() -> Self {
        Self { fill: CONTROL_FILL, edges: Some(EDGE_COLOUR), smooth: false, ..Self::surface() }
    }
    /// A flat-shaded input mesh with its edges drawn.
    pub fn input_mesh() -> Self {
        Self { fill: INPUT_FILL, edges: Some(EDGE_COLOUR), smooth: false, ..Self::surface() }
    }
    /// This style with the mesh's vertices drawn as dots of `colour` and `radius` pixels.
    pub fn with_points(self, colour: [u8; 3], radius: f32) -> Self {
        Self { points: Some((colour, radius)), ..self }
    }
}

/// An 8-bit RGB image, rows top to bottom, `rgb.len() == 3 · width · height`.
#[derive(Clone, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels row by row, three bytes (red, green, blue) each.
    pub rgb: Vec<u8>,
}

impl fmt::Debug for Image {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Image({}×{})", self.width, self.height)
    }
}

fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(FONT_BYTES).expect("the embedded DejaVu Sans parses"))
}

/// Width in pixels of `text` set at `size` pixels (the font's em height).
pub fn text_width(text: &str, size: f32) -> f32 {
    let font = font().as_scaled(PxScale::from(size));
    let mut width = 0.0;
    let mut prev = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = prev {
            width += font.kern(p, id);
        }
        width += font.h_advance(id);
        prev = Some(id);
    }
    width
}

impl Image {
    /// A `width × height` image filled with `colour`.
    pub fn new(width: u32, height: u32, colour: [u8; 3]) -> Self {
        let rgb = colour.iter().copied().cycle().take(3 * width as usize * height as usize).collect();
        Self { width, height, rgb }
    }

    /// The colour at column `x`, row `y` (panics outside the image).
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        assert!(x < self.width && y < self.height, "pixel ({x}, {y}) outside {self:?}");
        let i = 3 * (y as usize * self.width as usize + x as usize);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }

    /// Sets the colour at column `x`, row `y`; does nothing outside the image.
    pub fn set_pixel(&mut self, x: i64, y: i64, colour: [u8; 3]) {
        self.blend_pixel(x, y, colour, 1.0);
    }

    /// Mixes `colour` into the pixel at (`x`, `y`) with opacity `alpha` ∈ [0, 1]; does nothing
    /// outside the image.
    pub fn blend_pixel(&mut self, x: i64, y: i64, colour: [u8; 3], alpha: f32) {
        if x < 0 || y < 0 || x >= i64::from(self.width) || y >= i64::from(self.height) {
            return;
        }
        let a = alpha.clamp(0.0, 1.0);
        let i = 3 * (y as usize * self.width as usize + x as usize);
        for k in 0..3 {
            let old = f32::from(self.rgb[i + k]);
            self.rgb[i + k] = (old + (f32::from(colour[k]) - old) * a).round() as u8;
        }
    }

    /// Fills the rectangle with top-left corner (`x`, `y`), clipped to the image.
    pub fn fill_rect(&mut self, x: i64, y: i64, width: u32, height: u32, colour: [u8; 3]) {
        for yy in y..y + i64::from(height) {
            for xx in x..x + i64::from(width) {
                self.set_pixel(xx, yy, colour);
            }
        }
    }

    /// Copies `src` with its top-left corner at (`x`, `y`), clipped to this image.
    pub fn blit(&mut self, src: &Image, x: i64, y: i64) {
        for sy in 0..src.height {
            let ty = y + i64::from(sy);
            if ty < 0 || ty >= i64::from(self.height) {
                continue;
            }
            for sx in 0..src.width {
                self.set_pixel(x + i64::from(sx), ty, src.pixel(sx, sy));
            }
        }
    }

    /// Draws `text` at `size` pixels with its baseline starting at (`x`, `baseline`), anti-aliased.
    pub fn draw_text(&mut self, x: f32, baseline: f32, size: f32, text: &str, colour: [u8; 3]) {
        let font = font();
        let scaled = font.as_scaled(PxScale::from(size));
        let mut caret = x;
        let mut prev = None;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = prev {
                caret += scaled.kern(p, id);
            }
            let glyph = id.with_scale_and_position(size, point(caret, baseline));
            if let Some(outline) = font.outline_glyph(glyph) {
                let bounds = outline.px_bounds();
                let (x0, y0) = (bounds.min.x as i64, bounds.min.y as i64);
                outline.draw(|gx, gy, coverage| {
                    self.blend_pixel(x0 + i64::from(gx), y0 + i64::from(gy), colour, coverage);
                });
            }
            caret += scaled.h_advance(id);
            prev = Some(id);
        }
    }

    /// Draws `text` centred on column `centre_x` with its top at row `top`, shrunk below `size`
    /// when needed to fit in `max_width` pixels. Returns the height used.
    pub fn draw_text_centred(
        &mut self,
        centre_x: f32,
        top: f32,
        size: f32,
        max_width: f32,
        text: &str,
        colour: [u8; 3],
    ) -> f32 {
        let natural = text_width(text, size);
        let size = if natural > max_width && natural > 0.0 { size * max_width / natural } else { size };
        let width = text_width(text, size);
        let ascent = font().as_scaled(PxScale::from(size)).ascent();
        self.draw_text(centre_x - 0.5 * width, top + ascent, size, text, colour);
        line_height(size)
    }

    /// Number of pixels whose colour differs from `colour` (e.g. the background).
    pub fn count_pixels_not(&self, colour: [u8; 3]) -> usize {
        self.rgb.chunks_exact(3).filter(|p| *p != colour).count()
    }

    /// Writes the image as an 8-bit RGB PNG, creating parent folders as needed.
    pub fn save_png(&self, path: &Path) -> anyhow::Result<()> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        }
        let file = std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
        let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().with_context(|| format!("writing {}", path.display()))?;
        writer.write_image_data(&self.rgb).with_context(|| format!("writing {}", path.display()))?;
        writer.finish().with_context(|| format!("writing {}", path.display()))?;
        Ok(())
    }
}

fn line_height(size: f32) -> f32 {
    (1.3 * size).ceil()
}

/// The smallest box holding all `boxes` (for a camera shared by several panels).
pub fn union(boxes: impl IntoIterator<Item = Aabb>) -> Option<Aabb> {
    boxes.into_iter().reduce(|a, b| Aabb { min: a.min.min(b.min), max: a.max.max(b.max) })
}

/// The bounding box of all `meshes`: pass it as `frame` to render them with one camera.
pub fn frame_of(meshes: &[&Mesh]) -> Aabb {
    union(meshes.iter().map(|m| m.bbox())).expect("frame_of needs at least one mesh")
}

/// A perspective camera fitted to a `width × height` panel.
///
/// It looks at the centre of a box from [`View`]'s direction, from a distance set by the box's
/// size (vertical field of view [`FIELD_OF_VIEW_DEG`]), scaled so that the projection of a set of
/// points fills the panel less [`MARGIN`]. Panels drawn with one camera line up exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    right: DVec3,
    up: DVec3,
    back: DVec3,
    centre: DVec3,
    distance: f64,
    radius: f64,
    scale: f64,
    offset: (f64, f64),
    up_axis: Up,
    width: u32,
    height: u32,
}

impl Camera {
    /// A camera that shows all of `frame` (the projections of its eight corners fit).
    pub fn framing(view: &View, frame: &Aabb, width: u32, height: u32) -> Self {
        Self::fitted(view, frame, &corners(frame), width, height)
    }

    /// A camera fitted tightly to the vertices of all `meshes` (e.g. the input mesh, control
    /// mesh and limit surface of one model), for panels that share it.
    pub fn fitting(view: &View, meshes: &[&Mesh], width: u32, height: u32) -> Self {
        let frame = frame_of(meshes);
        let used: Vec<DVec3> = meshes
            .iter()
            .flat_map(|m| {
                let t = m.topology();
                t.vertices().filter(|&v| !t.is_isolated(v)).map(|v| m.position(v))
            })
            .collect();
        Self::fitted(view, &frame, &used, width, height)
    }

    /// Width of the panel in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height of the panel in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Pixel column and row (fractional, origin at the top-left corner of the panel) and depth
    /// (distance along the viewing axis) of a model point; `None` behind the camera.
    pub fn project(&self, p: DVec3) -> Option<(f64, f64, f64)> {
        let q = self.raster(p);
        (q.is_finite() && q.z > self.near()).then_some((q.x, q.y, q.z))
    }

    /// The same camera for a raster `factor` times larger along each axis.
    fn supersampled(&self, factor: u32) -> Self {
        let f = f64::from(factor);
        Self {
            scale: self.scale * f,
            offset: (self.offset.0 * f, self.offset.1 * f),
            width: self.width * factor,
            height: self.height * factor,
            ..self.clone()
        }
    }

    fn fitted(view: &View, frame: &Aabb, fit: &[DVec3], width: u32, height: u32) -> Self {
        let up_axis = view.up;
        let corners: Vec<DVec3> = corners(frame).iter().map(|&p| to_y_up(p, up_axis)).collect();
        let (lo, hi) = corners.iter().fold((corners[0], corners[0]), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let centre = 0.5 * (lo + hi);
        let half_diagonal = 0.5 * (hi - lo).length();
        let radius = if half_diagonal.is_finite() && half_diagonal > 0.0 { half_diagonal } else { 1.0 };
        let (yaw, pitch) = (view.yaw.to_radians(), view.pitch.to_radians());
        let back = DVec3::new(yaw.sin() * pitch.cos(), pitch.sin(), yaw.cos() * pitch.cos());
        let right = DVec3::Y.cross(back).try_normalize().unwrap_or(DVec3::X);
        let up = back.cross(right);
        let distance = radius / (0.5 * FIELD_OF_VIEW_DEG.to_radians()).sin();
        let mut camera =
            Self { right, up, back, centre, distance, radius, scale: 1.0, offset: (0.0, 0.0), up_axis, width, height };
        // Fit the projected points into the raster less the margin.
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &p in fit {
            let e = camera.eye(to_y_up(p, up_axis));
            let (x, y) = (e.x / e.z, e.y / e.z);
            if e.z > camera.near() && x.is_finite() && y.is_finite() {
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
        }
        if x0 > x1 {
            (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
        }
        let (w, h) = (f64::from(width), f64::from(height));
        let border = 2.0 * MARGIN * w.min(h);
        let span = |a: f64, b: f64| (b - a).max(1e-12);
        let scale = ((w - border).max(1.0) / span(x0, x1)).min((h - border).max(1.0) / span(y0, y1));
        camera.scale = scale * if view.zoom > 0.0 { view.zoom } else { 1.0 };
        camera.offset = (0.5 * w - camera.scale * 0.5 * (x0 + x1), 0.5 * h + camera.scale * 0.5 * (y0 + y1));
        camera
    }

    /// Camera-space coordinates (right, up, depth) of a model point already turned y-up.
    fn eye(&self, p: DVec3) -> DVec3 {
        let d = p - self.centre;
        DVec3::new(d.dot(self.right), d.dot(self.up), self.distance - d.dot(self.back))
    }

    /// Raster column, row and depth of a model point (not checked against the near plane).
    fn raster(&self, p: DVec3) -> DVec3 {
        let e = self.eye(to_y_up(p, self.up_axis));
        DVec3::new(self.offset.0 + self.scale * e.x / e.z, self.offset.1 - self.scale * e.y / e.z, e.z)
    }

    /// A model direction in camera space (x right, y up, z toward the viewer).
    fn direction(&self, n: DVec3) -> DVec3 {
        let n = to_y_up(n, self.up_axis);
        DVec3::new(n.dot(self.right), n.dot(self.up), n.dot(self.back))
    }

    /// Nearest depth that is drawn; geometry closer than this is skipped.
    fn near(&self) -> f64 {
        1e-3 * self.distance
    }
}

/// The eight corners of a box.
fn corners(frame: &Aabb) -> [DVec3; 8] {
    std::array::from_fn(|i| {
        let pick = |bit: usize, lo: f64, hi: f64| if i & bit == 0 { lo } else { hi };
        DVec3::new(
            pick(1, frame.min.x, frame.max.x),
            pick(2, frame.min.y, frame.max.y),
            pick(4, frame.min.z, frame.max.z),
        )
    })
}

fn to_y_up(p: DVec3, up: Up) -> DVec3 {
    match up {
        Up::Y => p,
        // Rotate −90° about x: z becomes y and −y becomes z (the front).
        Up::Z => DVec3::new(p.x, p.z, -p.y),
    }
}

fn to_linear(c: u8) -> f64 {
    (f64::from(c) / 255.0).powf(2.2)
}

fn to_srgb(l: f64) -> u8 {
    (255.0 * l.clamp(0.0, 1.0).powf(1.0 / 2.2)).round() as u8
}

fn mix(a: [u8; 3], b: [u8; 3], t: f64) -> [u8; 3] {
    std::array::from_fn(|k| (f64::from(a[k]) * (1.0 - t) + f64::from(b[k]) * t).round() as u8)
}

/// Hemispheric ambient + key (Lambert, above-left of the viewer) + fill (below-right) +
/// Blinn-Phong specular, in linear light, for a camera-space unit normal facing the viewer.
fn shade(base: [f64; 3], n: DVec3) -> [u8; 3] {
    const AMBIENT: f64 = 0.14;
    const KEY: f64 = 0.80;
    const FILL: f64 = 0.16;
    const SPECULAR: f64 = 0.12;
    const SHININESS: i32 = 48;
    let key = DVec3::new(-0.45, 0.65, 0.85).normalize();
    let fill = DVec3::new(0.7, -0.3, 0.6).normalize();
    let half = (key + DVec3::Z).normalize();
    // Sky above, ground below: surfaces facing up get a little more ambient light.
    let ambient = AMBIENT * (0.75 + 0.25 * n.y);
    let diffuse = ambient + KEY * n.dot(key).max(0.0) + FILL * n.dot(fill).max(0.0);
    let specular = SPECULAR * n.dot(half).max(0.0).powi(SHININESS);
    std::array::from_fn(|k| to_srgb(base[k] * diffuse + specular))
}

/// A z-buffered, supersampled raster for drawing several meshes, edges and points with one
/// camera; [`Canvas::finish`] averages it down to an [`Image`].
pub struct Canvas {
    camera: Camera,
    width: u32,
    height: u32,
    /// Supersampled size.
    sw: usize,
    sh: usize,
    colour: Vec<[u8; 3]>,
    depth: Vec<f32>,
}

impl Canvas {
    /// An empty canvas of the camera's panel size.
    pub fn new(camera: &Camera, background: [u8; 3]) -> Self {
        let (width, height) = (camera.width, camera.height);
        Self::with_camera(camera.supersampled(SUPERSAMPLING), width, height, background)
    }

    fn with_camera(camera: Camera, width: u32, height: u32, background: [u8; 3]) -> Self {
        let (sw, sh) = ((width * SUPERSAMPLING) as usize, (height * SUPERSAMPLING) as usize);
        Self { camera, width, height, sw, sh, colour: vec![background; sw * sh], depth: vec![f32::INFINITY; sw * sh] }
    }

    /// Fills and shades the faces of `mesh`; `smooth` interpolates vertex normals.
    ///
    /// On an open mesh, faces whose outward side looks at the viewer get `fill` and the others
    /// (its inside) `fill` tinted with [`BACK_TINT`]; both sides are lit alike. "Outward" is the
    /// mesh's orientation, reversed when its signed volume about the centroid is negative, so
    /// inward-oriented files look right.
    pub fn draw_surface(&mut self, mesh: &Mesh, fill: [u8; 3], smooth: bool) {
        self.draw_surface_coloured(mesh, |_| fill, smooth);
    }

    /// [`Self::draw_surface`] with a colour per face (`fill(face)`), e.g. a distance map.
    pub fn draw_surface_coloured(&mut self, mesh: &Mesh, fill: impl Fn(subdiv_mesh::FaceId) -> [u8; 3], smooth: bool) {
        let t = mesh.topology();
        let flip = if outward_sign(mesh) < 0.0 { -1.0 } else { 1.0 };
        let screen: Vec<DVec3> = mesh.positions().iter().map(|&p| self.camera.raster(p)).collect();
        let vertex_normals: Vec<DVec3> = if smooth {
            mesh.vertex_normals().iter().map(|&n| flip * self.camera.direction(n)).collect()
        } else {
            Vec::new()
        };
        let closed = t.is_closed();
        let (mut corners, mut triangles) = (Vec::new(), Vec::new());
        for f in t.face_ids() {
            let colour = fill(f);
            let front = colour.map(to_linear);
            // On a closed mesh the inside shows only through folded or non-planar faces: no tint.
            let back = if closed { front } else { mix(colour, BACK_TINT, 0.5).map(to_linear) };
            let face = t.face(f);
            let face_normal = flip * self.camera.direction(mesh.face_normal(f));
            // Flat faces are front or back as a whole (a fan over a non-planar or non-convex
            // polygon may hold folded triangles); smooth ones triangle by triangle.
            let facing = if smooth {
                None
            } else {
                let e = self.camera.eye(to_y_up(mesh.face_centroid(f), self.camera.up_axis));
                Some(face_normal.dot(DVec3::new(-e.x, -e.y, e.z)) >= 0.0)
            };
            corners.clear();
            corners.extend(face.iter().map(|&v| mesh.positions()[v as usize]));
            triangulate(&corners, mesh.face_normal(f), &mut triangles);
            for local in &triangles {
                let ids = local.map(|k| face[k] as usize);
                let normals = if smooth { ids.map(|i| vertex_normals[i]) } else { [face_normal; 3] };
                self.triangle(ids.map(|i| screen[i]), normals, facing, flip, (&front, &back));
            }
        }
    }

    /// Rasterises one triangle given in raster coordinates; `front` says whether its outward side
    /// faces the viewer (`None`: decide from its winding and the mesh orientation `flip`).
    fn triangle(
        &mut self,
        p: [DVec3; 3],
        n: [DVec3; 3],
        front: Option<bool>,
        flip: f64,
        fills: (&[f64; 3], &[f64; 3]),
    ) {
        let near = self.camera.near();
        if p.iter().any(|q| !q.is_finite() || q.z <= near) {
            return;
        }
        let area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
        if area == 0.0 {
            return;
        }
        // Rows grow downward, so a counter-clockwise (outward-facing) triangle has negative area.
        let front = front.unwrap_or((area < 0.0) == (flip > 0.0));
        let (base, sign) = if front { (fills.0, 1.0) } else { (fills.1, -1.0) };
        let x0 = p.iter().map(|q| q.x).fold(f64::MAX, f64::min).floor().max(0.0) as usize;
        let x1 = p.iter().map(|q| q.x).fold(f64::MIN, f64::max).ceil().min(self.sw as f64) as usize;
        let y0 = p.iter().map(|q| q.y).fold(f64::MAX, f64::min).floor().max(0.0) as usize;
        let y1 = p.iter().map(|q| q.y).fold(f64::MIN, f64::max).ceil().min(self.sh as f64) as usize;
        let inv_z = p.map(|q| 1.0 / q.z);
        let edge = |a: DVec3, b: DVec3, x: f64, y: f64| (b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y);
        for y in y0..y1 {
            let yc = y as f64 + 0.5;
            for x in x0..x1 {
                let xc = x as f64 + 0.5;
                let w =
                    [edge(p[1], p[2], xc, yc) / area, edge(p[2], p[0], xc, yc) / area, edge(p[0], p[1], xc, yc) / area];
                if w.iter().any(|&wi| wi < 0.0) {
                    continue;
                }
                let iz = w[0] * inv_z[0] + w[1] * inv_z[1] + w[2] * inv_z[2];
                let depth = (1.0 / iz) as f32;
                let i = y * self.sw + x;
                if depth >= self.depth[i] {
                    continue;
                }
                // Perspective-correct normal.
                let normal = (w[0] * inv_z[0] * n[0] + w[1] * inv_z[1] * n[1] + w[2] * inv_z[2] * n[2]) / iz;
                let normal = (sign * normal).try_normalize().unwrap_or(DVec3::Z);
                self.depth[i] = depth;
                self.colour[i] = shade(*base, normal);
            }
        }
    }

    /// Draws every edge of `mesh` as a line `width` output pixels wide, hidden where a surface
    /// already drawn lies in front of it.
    pub fn draw_edges(&mut self, mesh: &Mesh, colour: [u8; 3], width: f32) {
        let t = mesh.topology();
        let screen: Vec<DVec3> = mesh.positions().iter().map(|&p| self.camera.raster(p)).collect();
        let half = 0.5 * f64::from(width) * f64::from(SUPERSAMPLING);
        for e in t.edges() {
            let (a, b) = t.edge_vertices(e);
            self.segment(screen[a.index()], screen[b.index()], half, colour);
        }
    }

    /// Draws the polyline through `points` (model space), e.g. a boundary or a curve.
    pub fn draw_polyline(&mut self, points: &[DVec3], colour: [u8; 3], width: f32) {
        let half = 0.5 * f64::from(width) * f64::from(SUPERSAMPLING);
        for pair in points.windows(2) {
            self.segment(self.camera.raster(pair[0]), self.camera.raster(pair[1]), half, colour);
        }
    }

    fn segment(&mut self, a: DVec3, b: DVec3, half: f64, colour: [u8; 3]) {
        let near = self.camera.near();
        if !a.is_finite() || !b.is_finite() || a.z <= near || b.z <= near {
            return;
        }
        let offset = DEPTH_OFFSET * self.camera.radius;
        let x0 = (a.x.min(b.x) - half).floor().max(0.0) as usize;
        let x1 = (a.x.max(b.x) + half).ceil().min(self.sw as f64) as usize;
        let y0 = (a.y.min(b.y) - half).floor().max(0.0) as usize;
        let y1 = (a.y.max(b.y) + half).ceil().min(self.sh as f64) as usize;
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let len2 = dx * dx + dy * dy;
        for y in y0..y1 {
            let yc = y as f64 + 0.5;
            for x in x0..x1 {
                let xc = x as f64 + 0.5;
                let s = if len2 > 0.0 { (((xc - a.x) * dx + (yc - a.y) * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
                let (px, py) = (a.x + s * dx - xc, a.y + s * dy - yc);
                if px * px + py * py > half * half {
                    continue;
                }
                // 1/depth is affine along the projected segment.
                let depth = 1.0 / ((1.0 - s) / a.z + s / b.z);
                let i = y * self.sw + x;
                if depth - offset <= f64::from(self.depth[i]) {
                    self.colour[i] = colour;
                }
            }
        }
    }

    /// Draws a dot of `radius` output pixels at each of `points` (model space) whose centre is
    /// not hidden by a surface already drawn; dots get a thin dark rim so they read on any fill.
    pub fn draw_points(&mut self, points: &[DVec3], colour: [u8; 3], radius: f32) {
        let offset = DEPTH_OFFSET * self.camera.radius;
        let r = f64::from(radius) * f64::from(SUPERSAMPLING);
        let rim = mix(colour, BLACK, 0.55);
        for &p in points {
            let q = self.camera.raster(p);
            if !q.is_finite() || q.z <= self.camera.near() {
                continue;
            }
            let (cx, cy) = (q.x.floor(), q.y.floor());
            if cx < 0.0 || cy < 0.0 || cx >= self.sw as f64 || cy >= self.sh as f64 {
                continue;
            }
            // Visible when in front of the nearest surface sample around the centre, give or take.
            let mut nearest = f64::INFINITY;
            for oy in -1..=1_i64 {
                for ox in -1..=1_i64 {
                    let (x, y) = (cx as i64 + ox, cy as i64 + oy);
                    if x >= 0 && y >= 0 && (x as usize) < self.sw && (y as usize) < self.sh {
                        nearest = nearest.min(f64::from(self.depth[y as usize * self.sw + x as usize]));
                    }
                }
            }
            if q.z - 2.0 * offset > nearest {
                continue;
            }
            self.disc(q.x, q.y, r, colour, rim);
        }
    }

    fn disc(&mut self, cx: f64, cy: f64, r: f64, colour: [u8; 3], rim: [u8; 3]) {
        let rim_width = f64::from(SUPERSAMPLING) * 0.8;
        let x0 = (cx - r).floor().max(0.0) as usize;
        let x1 = (cx + r).ceil().min(self.sw as f64) as usize;
        let y0 = (cy - r).floor().max(0.0) as usize;
        let y1 = (cy + r).ceil().min(self.sh as f64) as usize;
        for y in y0..y1 {
            for x in x0..x1 {
                let d = ((x as f64 + 0.5 - cx).powi(2) + (y as f64 + 0.5 - cy).powi(2)).sqrt();
                if d <= r {
                    self.colour[y * self.sw + x] = if d > r - rim_width { rim } else { colour };
                }
            }
        }
    }

    /// Averages the supersampled raster down to the output image.
    pub fn finish(self) -> Image {
        let s = SUPERSAMPLING as usize;
        let mut image = Image::new(self.width, self.height, WHITE);
        for y in 0..self.height as usize {
            for x in 0..self.width as usize {
                let mut sum = [0u32; 3];
                for sy in 0..s {
                    for sx in 0..s {
                        let c = self.colour[(y * s + sy) * self.sw + x * s + sx];
                        for k in 0..3 {
                            sum[k] += u32::from(c[k]);
                        }
                    }
                }
                let n = (s * s) as u32;
                let i = 3 * (y * self.width as usize + x);
                for k in 0..3 {
                    image.rgb[i + k] = ((sum[k] + n / 2) / n) as u8;
                }
            }
        }
        image
    }
}

/// Triangulates the polygon `corners` (unit normal `normal`, zero when degenerate) by ear
/// clipping in its plane, so that non-convex faces (letters, L-shapes) fill correctly; the
/// triangles keep the polygon's winding. Writes corner indices into `out`. A polygon with no
/// ear left (degenerate, self-intersecting) is finished as a fan.
fn triangulate(corners: &[DVec3], normal: DVec3, out: &mut Vec<[usize; 3]>) {
    out.clear();
    let n = corners.len();
    if n < 3 {
        return;
    }
    if n == 3 || normal == DVec3::ZERO {
        out.extend((1..n - 1).map(|k| [0, k, k + 1]));
        return;
    }
    // (u, v, normal) is right-handed, so the polygon runs counter-clockwise in (u, v).
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let p: Vec<(f64, f64)> = corners.iter().map(|&c| (c.dot(u), c.dot(v))).collect();
    let cross =
        |a: usize, b: usize, c: usize| (p[b].0 - p[a].0) * (p[c].1 - p[a].1) - (p[b].1 - p[a].1) * (p[c].0 - p[a].0);
    let mut ring: Vec<usize> = (0..n).collect();
    let mut i = 0;
    let mut misses = 0;
    while ring.len() > 3 {
        let m = ring.len();
        let (a, b, c) = (ring[(i + m - 1) % m], ring[i % m], ring[(i + 1) % m]);
        let convex = cross(a, b, c) > 0.0;
        let empty = convex
            && ring.iter().all(|&q| {
                q == a || q == b || q == c || cross(a, b, q) < 0.0 || cross(b, c, q) < 0.0 || cross(c, a, q) < 0.0
            });
        if empty {
            out.push([a, b, c]);
            ring.remove(i % m);
            misses = 0;
        } else {
            i += 1;
            misses += 1;
            if misses > m {
                break;
            }
        }
    }
    out.extend((1..ring.len() - 1).map(|k| [ring[0], ring[k], ring[k + 1]]));
}

/// Σ over faces of (face centroid − mesh centroid) · (face area vector): positive when the
/// faces are oriented outward (for closed meshes this is 3× the enclosed volume).
fn outward_sign(mesh: &Mesh) -> f64 {
    let t = mesh.topology();
    let centroids = mesh.face_centroids();
    let centre = centroids.iter().copied().sum::<DVec3>() / centroids.len().max(1) as f64;
    t.face_ids()
        .map(|f| {
            let area_vector = mesh.face_normal(f) * mesh.face_area(f);
            (centroids[f.index()] - centre).dot(area_vector)
        })
        .sum()
}

/// Renders `mesh` in `style` as a `width × height` panel.
///
/// The camera looks at `frame` from `view` and fits the whole box into the panel, so panels
/// rendered with the same `frame` and `view` share one camera: the input mesh, control mesh and
/// limit surface of one model line up side by side. Without a frame the camera is fitted
/// tightly to the mesh's own vertices. ([`render_panels`] fits one camera tightly to several
/// meshes.)
pub fn render_mesh(mesh: &Mesh, view: &View, style: &Style, width: u32, height: u32, frame: Option<&Aabb>) -> Image {
    let camera = match frame {
        Some(frame) => Camera::framing(view, frame, width, height),
        None => Camera::fitting(view, &[mesh], width, height),
    };
    render_with(mesh, &camera, style)
}

/// Renders each mesh in its style through one camera fitted tightly to all of them: the panels
/// of one model's figure (input mesh, control mesh, limit surface) at the same scale and place.
pub fn render_panels(panels: &[(&Mesh, Style)], view: &View, width: u32, height: u32) -> Vec<Image> {
    if panels.is_empty() {
        return Vec::new();
    }
    let meshes: Vec<&Mesh> = panels.iter().map(|(m, _)| *m).collect();
    let camera = Camera::fitting(view, &meshes, width, height);
    panels.iter().map(|(mesh, style)| render_with(mesh, &camera, style)).collect()
}

/// Renders `mesh` in `style` through `camera`.
///
/// Edges are thinned (down to half of [`Style::edge_width`]) and lightened toward the fill when
/// the mesh's edges are short on screen, so that a dense mesh still shows its surface rather
/// than a dark mat of lines.
pub fn render_with(mesh: &Mesh, camera: &Camera, style: &Style) -> Image {
    let mut canvas = Canvas::new(camera, style.background);
    canvas.draw_surface(mesh, style.fill, style.smooth);
    if let Some(colour) = style.edges {
        let t = mesh.topology();
        let lengths: Vec<f64> = t
            .edges()
            .filter_map(|e| {
                let (a, b) = t.edge_vertices(e);
                let (pa, pb) = (camera.project(mesh.position(a))?, camera.project(mesh.position(b))?);
                Some((pa.0 - pb.0).hypot(pa.1 - pb.1))
            })
            .collect();
        let mean = lengths.iter().sum::<f64>() / lengths.len().max(1) as f64;
        let thinning = (mean / EDGE_THINNING_LENGTH).clamp(0.5, 1.0);
        let colour = mix(colour, style.fill, 0.6 * (1.0 - thinning));
        canvas.draw_edges(mesh, colour, style.edge_width * thinning as f32);
    }
    if let Some((colour, radius)) = style.points {
        let t = mesh.topology();
        let used: Vec<DVec3> = t.vertices().filter(|&v| !t.is_isolated(v)).map(|v| mesh.position(v)).collect();
        canvas.draw_points(&used, colour, radius);
    }
    canvas.finish()
}

/// Draws dots of `radius` pixels at `points` on an image rendered by [`render_mesh`] with the
/// same `view` and `frame` (a frame is needed: an image rendered without one used a camera
/// fitted to its mesh's vertices, which this function cannot know).
///
/// The image has no depth, so hidden points are drawn too; for occlusion use
/// [`Canvas::draw_points`] or [`Style::points`].
pub fn overlay_points(img: &mut Image, points: &[DVec3], view: &View, frame: &Aabb, colour: [u8; 3], radius: f32) {
    let camera = Camera::framing(view, frame, img.width, img.height);
    draw_dots(img, &camera, points, colour, radius);
}

/// Draws dots of `radius` pixels at `points` through `camera` (no occlusion: see
/// [`overlay_points`]).
pub fn draw_dots(img: &mut Image, camera: &Camera, points: &[DVec3], colour: [u8; 3], radius: f32) {
    let rim = mix(colour, BLACK, 0.55);
    let r = f64::from(radius);
    for &p in points {
        let Some((qx, qy, _)) = camera.project(p) else { continue };
        let q = DVec3::new(qx, qy, 0.0);
        let (x0, x1) = ((q.x - r - 1.0).floor() as i64, (q.x + r + 1.0).ceil() as i64);
        let (y0, y1) = ((q.y - r - 1.0).floor() as i64, (q.y + r + 1.0).ceil() as i64);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let d = ((x as f64 + 0.5 - q.x).powi(2) + (y as f64 + 0.5 - q.y).powi(2)).sqrt();
                // One pixel of anti-aliasing at the outside, a thin rim inside it.
                let coverage = (r + 0.5 - d).clamp(0.0, 1.0) as f32;
                if coverage > 0.0 {
                    let c = if d > r - 1.0 { rim } else { colour };
                    img.blend_pixel(x, y, c, coverage);
                }
            }
        }
    }
}

/// Layout constants of composed figures, in pixels.
const GAP: u32 = 12;
const BORDER: u32 = 16;
const CAPTION_SIZE: f32 = 18.0;
const TITLE_SIZE: f32 = 22.0;
const TEXT_COLOUR: [u8; 3] = [20, 20, 20];

/// Composes `panels` left to right on white, each with its caption centred below it, under
/// `title` (no title row when empty). Panels are top-aligned; captions too wide for their panel
/// are set smaller.
pub fn side_by_side(panels: &[(Image, &str)], title: &str) -> Image {
    let title_h = if title.is_empty() { 0 } else { line_height(TITLE_SIZE) as u32 + GAP / 2 };
    let caption_h = if panels.iter().any(|(_, c)| !c.is_empty()) { line_height(CAPTION_SIZE) as u32 } else { 0 };
    let panels_w: u32 = panels.iter().map(|(p, _)| p.width).sum::<u32>() + GAP * (panels.len().max(1) as u32 - 1);
    let panels_h = panels.iter().map(|(p, _)| p.height).max().unwrap_or(0);
    let title_w = if title.is_empty() { 0 } else { text_width(title, TITLE_SIZE).ceil() as u32 };
    let width = 2 * BORDER + panels_w.max(title_w);
    let height = 2 * BORDER + title_h + panels_h + caption_h;
    let mut out = Image::new(width, height, WHITE);
    if !title.is_empty() {
        let w = (width - 2 * BORDER) as f32;
        out.draw_text_centred(0.5 * width as f32, BORDER as f32, TITLE_SIZE, w, title, TEXT_COLOUR);
    }
    let mut x = BORDER + (width - 2 * BORDER - panels_w) / 2;
    let top = BORDER + title_h;
    for (panel, caption) in panels {
        out.blit(panel, i64::from(x), i64::from(top));
        if !caption.is_empty() {
            let centre = x as f32 + 0.5 * panel.width as f32;
            let caption_top = (top + panels_h) as f32 + 2.0;
            out.draw_text_centred(centre, caption_top, CAPTION_SIZE, panel.width as f32, caption, TEXT_COLOUR);
        }
        x += panel.width + GAP;
    }
    out
}

/// Stacks `rows` top to bottom on white, centred, under `title` (no title row when empty):
/// rows of [`side_by_side`] panels become one figure, e.g. one row per model.
pub fn stack(rows: &[Image], title: &str) -> Image {
    let title_h = if title.is_empty() { 0 } else { line_height(TITLE_SIZE) as u32 + GAP / 2 };
    let title_w = if title.is_empty() { 0 } else { text_width(title, TITLE_SIZE).ceil() as u32 + 2 * BORDER };
    let width = rows.iter().map(|r| r.width).max().unwrap_or(0).max(title_w);
    let height = title_h + rows.iter().map(|r| r.height).sum::<u32>() + if title.is_empty() { 0 } else { BORDER };
    let mut out = Image::new(width, height, WHITE);
    if !title.is_empty() {
        out.draw_text_centred(0.5 * width as f32, BORDER as f32, TITLE_SIZE, width as f32, title, TEXT_COLOUR);
    }
    let mut y = if title.is_empty() { 0 } else { BORDER + title_h };
    for row in rows {
        out.blit(row, i64::from((width - row.width) / 2), i64::from(y));
        y += row.height;
    }
    out
}

/// Which preset [`Style`] `cargo xtask render` uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum StyleName {
    /// [`Style::surface`]: smooth, no edges.
    Surface,
    /// [`Style::control_mesh`]: flat, grey, edges.
    Control,
    /// [`Style::input_mesh`]: flat, sand, edges.
    Input,
}

/// `cargo xtask render MESH -o OUT.png`: one mesh file to one PNG.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Mesh file (any format subdiv-io reads).
    pub mesh: PathBuf,
    /// PNG to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 800)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 600)]
    pub height: u32,
    /// Camera turn around the up axis, degrees.
    #[arg(long, default_value_t = View::default().yaw, allow_negative_numbers = true)]
    pub yaw: f64,
    /// Camera elevation, degrees.
    #[arg(long, default_value_t = View::default().pitch, allow_negative_numbers = true)]
    pub pitch: f64,
    /// Magnification over the auto-fit.
    #[arg(long, default_value_t = 1.0)]
    pub zoom: f64,
    /// The model's +z is up (default: +y).
    #[arg(long)]
    pub z_up: bool,
    /// Drawing style.
    #[arg(long, value_enum, default_value_t = StyleName::Control)]
    pub style: StyleName,
    /// Also draw the vertices as red dots.
    #[arg(long)]
    pub points: bool,
    /// Caption under the panel (a titled figure when given).
    #[arg(long)]
    pub title: Option<String>,
}

/// Runs `cargo xtask render`.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let soup = subdiv_io::read_mesh(&args.mesh).with_context(|| format!("reading {}", args.mesh.display()))?;
    let (mesh, _warnings) = Mesh::from_soup(soup).with_context(|| format!("validating {}", args.mesh.display()))?;
    let view = View { yaw: args.yaw, pitch: args.pitch, zoom: args.zoom, up: if args.z_up { Up::Z } else { Up::Y } };
    let mut style = match args.style {
        StyleName::Surface => Style::surface(),
        StyleName::Control => Style::control_mesh(),
        StyleName::Input => Style::input_mesh(),
    };
    if args.points {
        style = style.with_points(POINT_COLOUR, 3.0);
    }
    anyhow::ensure!(args.width > 0 && args.height > 0, "the image needs a positive width and height");
    let image = render_mesh(&mesh, &view, &style, args.width, args.height, None);
    let image = match &args.title {
        Some(title) => side_by_side(&[(image, "")], title),
        None => image,
    };
    image.save_png(&args.output)?;
    let t = mesh.topology();
    println!(
        "{}: {} vertices, {} faces -> {} ({}×{})",
        args.mesh.display(),
        t.vertex_count(),
        t.face_count(),
        args.output.display(),
        image.width,
        image.height
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::{shapes, FaceList};

    fn distinct_colours(img: &Image) -> usize {
        let mut colours: Vec<&[u8]> = img.rgb.chunks_exact(3).collect();
        colours.sort_unstable();
        colours.dedup();
        colours.len()
    }

    #[test]
    fn cube_renders_shaded_within_frame_and_deterministically() {
        let cube = shapes::cube();
        let style = Style::surface();
        let img = render_mesh(&cube, &View::default(), &style, 200, 160, None);
        assert_eq!((img.width, img.height, img.rgb.len()), (200, 160, 200 * 160 * 3));
        let covered = img.count_pixels_not(WHITE) as f64 / (200.0 * 160.0);
        assert!((0.2..0.9).contains(&covered), "cube covers {covered:.2} of the panel");
        // Three visible faces at different angles to the light, plus anti-aliased borders.
        assert!(distinct_colours(&img) >= 4, "shading does not vary");
        // Nothing touches the border: the fit leaves a margin.
        for x in 0..img.width {
            assert_eq!(img.pixel(x, 0), WHITE);
            assert_eq!(img.pixel(x, img.height - 1), WHITE);
        }
        let again = render_mesh(&cube, &View::default(), &style, 200, 160, None);
        assert!(img == again, "rendering is not deterministic");
    }

    #[test]
    fn torus_smooth_shading_has_a_gradient() {
        let torus = shapes::torus(24, 12);
        let img = render_mesh(&torus, &View::default(), &Style::surface(), 160, 160, None);
        assert!(distinct_colours(&img) > 50, "smooth shading shows only {} colours", distinct_colours(&img));
        let covered = img.count_pixels_not(WHITE) as f64 / (160.0 * 160.0);
        assert!((0.15..0.9).contains(&covered), "torus covers {covered:.2} of the panel");
        // The hole: the panel centre shows the background.
        let top = render_mesh(&torus, &View { pitch: 89.0, ..View::default() }, &Style::surface(), 160, 160, None);
        let z_up =
            render_mesh(&torus, &View { pitch: 89.0, up: Up::Z, ..View::default() }, &Style::surface(), 160, 160, None);
        // The torus axis is z: seen from above with z up, the hole is in the middle.
        assert_eq!(z_up.pixel(80, 80), WHITE);
        assert_ne!(top, z_up);
    }

    #[test]
    fn edges_are_drawn_in_their_colour() {
        let cube = shapes::cube();
        let edge = [255, 0, 255];
        let plain = Style { edges: None, ..Style::control_mesh() };
        let with_edges = Style { edges: Some(edge), edge_width: 2.0, ..Style::control_mesh() };
        let a = render_mesh(&cube, &View::default(), &plain, 160, 160, None);
        let b = render_mesh(&cube, &View::default(), &with_edges, 160, 160, None);
        let magenta = b.rgb.chunks_exact(3).filter(|p| *p == edge).count();
        assert!(magenta > 100, "only {magenta} edge pixels");
        assert_eq!(a.rgb.chunks_exact(3).filter(|p| *p == edge).count(), 0);
    }

    #[test]
    fn hidden_edges_are_hidden() {
        // Seen straight from the front in perspective, the cube's back face projects to a smaller
        // square inside the front one: its edges must not show through. Along the middle row,
        // edge pixels are found only at the outline.
        let cube = shapes::cube();
        let magenta = [255, 0, 255];
        let style = Style { edges: Some(magenta), ..Style::control_mesh() };
        let view = View { yaw: 0.0, pitch: 0.0, ..View::default() };
        let img = render_mesh(&cube, &view, &style, 120, 120, None);
        let row = 60;
        let covered: Vec<u32> = (0..img.width).filter(|&x| img.pixel(x, row) != WHITE).collect();
        let (left, right) = (covered[0], covered[covered.len() - 1]);
        let edges: Vec<u32> = (0..img.width).filter(|&x| img.pixel(x, row) == magenta).collect();
        assert!(!edges.is_empty(), "the outline is drawn");
        assert!(edges.iter().all(|&x| x <= left + 3 || x + 3 >= right), "inner edges at {edges:?}");
        // Without the surface in front they would be: the wireframe alone shows the back square.
        let mut wire = Canvas::new(&Camera::fitting(&view, &[&cube], 120, 120), WHITE);
        wire.draw_edges(&cube, magenta, 1.3);
        let wire = wire.finish();
        assert!((left + 6..right - 5).any(|x| wire.pixel(x, row) != WHITE));
    }

    #[test]
    fn orientation_of_the_file_does_not_matter() {
        let cube = shapes::cube();
        let reversed: Vec<Vec<u32>> =
            cube.topology().faces().iter().map(|f| f.iter().rev().copied().collect()).collect();
        let inward = Mesh::new(cube.positions().to_vec(), FaceList::from_faces(reversed)).unwrap();
        let style = Style::surface();
        let a = render_mesh(&cube, &View::default(), &style, 100, 100, None);
        let b = render_mesh(&inward, &View::default(), &style, 100, 100, None);
        assert!(a == b);
    }

    #[test]
    fn open_meshes_show_their_back_in_another_tint() {
        let grid = shapes::quad_grid(4, 4);
        let style = Style { fill: [128, 128, 128], ..Style::surface() };
        let above = render_mesh(&grid, &View { pitch: 60.0, up: Up::Z, ..View::default() }, &style, 80, 80, None);
        let below = render_mesh(&grid, &View { pitch: -60.0, up: Up::Z, ..View::default() }, &style, 80, 80, None);
        let reddish = |img: &Image| img.rgb.chunks_exact(3).filter(|p| u16::from(p[0]) > u16::from(p[2]) + 20).count();
        assert!(reddish(&above).min(reddish(&below)) < 10);
        assert!(reddish(&above).max(reddish(&below)) > 500);
    }

    #[test]
    fn shared_frame_shares_the_camera_and_points_land_on_vertices() {
        let cube = shapes::cube();
        let big = cube.with_positions(cube.positions().iter().map(|&p| 2.0 * p - DVec3::splat(0.5)).collect());
        let frame = frame_of(&[&cube, &big]);
        let small_alone = render_mesh(&cube, &View::default(), &Style::surface(), 120, 120, None);
        let small_framed = render_mesh(&cube, &View::default(), &Style::surface(), 120, 120, Some(&frame));
        assert!(small_framed.count_pixels_not(WHITE) < small_alone.count_pixels_not(WHITE) / 2);
        let mut dotted = small_framed.clone();
        let red = [255, 0, 0];
        overlay_points(&mut dotted, cube.positions(), &View::default(), &frame, red, 3.0);
        assert!(dotted.count_pixels_not(WHITE) > small_framed.count_pixels_not(WHITE));
        // With occlusion (Style::points) one of the 8 corners is hidden, so fewer dots.
        let occluded =
            render_mesh(&cube, &View::default(), &Style::surface().with_points(red, 3.0), 120, 120, Some(&frame));
        let rim = mix(red, BLACK, 0.55);
        let count = |img: &Image| img.rgb.chunks_exact(3).filter(|p| *p == rim.as_slice()).count();
        assert!(count(&occluded) > 0 && count(&occluded) < count(&dotted));
    }

    #[test]
    fn side_by_side_is_three_panels_wide() {
        let cube = shapes::cube();
        let panel = render_mesh(&cube, &View::default(), &Style::surface(), 150, 120, None);
        let fig = side_by_side(
            &[(panel.clone(), "input"), (panel.clone(), "control mesh"), (panel.clone(), "limit surface")],
            "Cube",
        );
        let ratio = f64::from(fig.width) / f64::from(3 * panel.width);
        assert!((1.0..1.15).contains(&ratio), "width {} for three panels of {}", fig.width, panel.width);
        assert!(fig.height > panel.height + 30, "no room for title and captions");
        // Text was drawn: dark pixels in the title band.
        let dark = (0..fig.width).flat_map(|x| (0..BORDER + 24).map(move |y| (x, y)));
        assert!(dark.filter(|&(x, y)| fig.pixel(x, y)[0] < 100).count() > 20);
        let tall = stack(&[fig.clone(), fig.clone()], "");
        assert_eq!((tall.width, tall.height), (fig.width, 2 * fig.height));
    }

    #[test]
    fn non_convex_polygons_are_triangulated_inside() {
        // An L-shaped hexagon: a fan from corner 0 would cover the notch.
        let l = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)].map(|(x, y)| DVec3::new(x, y, 0.0));
        let mut triangles = Vec::new();
        triangulate(&l, DVec3::Z, &mut triangles);
        assert_eq!(triangles.len(), 4);
        let area: f64 = triangles.iter().map(|t| 0.5 * (l[t[1]] - l[t[0]]).cross(l[t[2]] - l[t[0]]).z).sum();
        assert!((area - 3.0).abs() < 1e-12, "area {area}");
        // Each triangle keeps the polygon's (counter-clockwise) winding.
        assert!(triangles.iter().all(|t| (l[t[1]] - l[t[0]]).cross(l[t[2]] - l[t[0]]).z > 0.0));
        let quad = [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].map(|(x, y)| DVec3::new(x, y, 0.0));
        triangulate(&quad, DVec3::Z, &mut triangles);
        assert_eq!(triangles.len(), 2);
    }

    #[test]
    fn png_round_trip() {
        let img = render_mesh(&shapes::icosahedron(), &View::default(), &Style::control_mesh(), 64, 48, None);
        let file = tempfile::Builder::new().prefix("xtask-render-").suffix(".png").tempfile().unwrap();
        img.save_png(file.path()).unwrap();
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(file.path()).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height, info.color_type), (64, 48, png::ColorType::Rgb));
        assert_eq!(&buf[..info.buffer_size()], img.rgb.as_slice());
    }

    fn fixture(path: &str) -> Mesh {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        Mesh::from_soup(subdiv_io::read_mesh(&root.join(path)).unwrap()).unwrap().0
    }

    /// Writes sample figures for a person to look at:
    /// `cargo test -p xtask --release -- --ignored sample_figures` (into the temp folder).
    #[test]
    #[ignore = "writes PNGs for visual inspection"]
    fn sample_figures() {
        use crate::plot::{line_plot, Series};
        let dir = std::env::temp_dir().join("xtask-samples");
        let (w, h) = (360, 320);
        // Spot: its Catmull-Clark control mesh and the triangulated surface made from it.
        let control = fixture("fixtures/quad/spot_control_mesh.obj");
        let surface = fixture("fixtures/tri/spot_triangulated.obj");
        let view = View { yaw: -145.0, pitch: 15.0, ..View::default() };
        let camera = Camera::fitting(&view, &[&control, &surface], w, h);
        let input = render_with(&control, &camera, &Style::input_mesh().with_points(POINT_COLOUR, 2.5));
        let ctrl = render_with(&control, &camera, &Style::control_mesh());
        let mut canvas = Canvas::new(&camera, WHITE);
        canvas.draw_surface(&surface, SURFACE_FILL, true);
        canvas.draw_points(control.positions(), POINT_COLOUR, 2.5);
        let limit = canvas.finish();
        let mut wire = Canvas::new(&camera, WHITE);
        wire.draw_surface(&surface, SURFACE_FILL, true);
        wire.draw_edges(&control, EDGE_COLOUR, 1.0);
        let wire = wire.finish();
        let spot = side_by_side(
            &[
                (input, "input mesh (data points red)"),
                (ctrl, "control mesh"),
                (limit, "limit surface"),
                (wire, "surface + control edges"),
            ],
            "Spot (Catmull-Clark): input, control mesh and limit surface",
        );
        spot.save_png(&dir.join("spot_side_by_side.png")).unwrap();
        // Bunny (Loop) and an open mesh, whose inside shows tinted.
        let bunny = fixture("fixtures/tri/bunny_npm.obj");
        let b1 = render_mesh(&bunny, &View::default(), &Style::input_mesh(), w, h, None);
        let b2 = render_mesh(&bunny, &View::default(), &Style::surface(), w, h, None);
        let camel = fixture("fixtures/open/camelhead.off");
        let camel_view = View { yaw: 150.0, pitch: 10.0, ..View::default() };
        let c1 = render_mesh(&camel, &camel_view, &Style::surface(), w, h, None);
        let row = side_by_side(&[(b1, "bunny, flat with edges"), (b2, "bunny, smooth"), (c1, "camel head (open)")], "");
        stack(&[spot, row], "Sample figures").save_png(&dir.join("stack.png")).unwrap();
        // Plots: convergence histories and a size series.
        let history =
            |rate: f64, n: usize| Series::from_history("", &(0..n).map(|k| rate.powi(k as i32)).collect::<Vec<_>>());
        let names = ["PIA", "weighted PIA", "Chebyshev", "CG", "LDLᵀ"];
        let series: Vec<Series> = [0.95, 0.8, 0.6, 0.4, 0.01]
            .iter()
            .zip(names)
            .map(|(&r, name)| Series { name: name.into(), ..history(r, (4.0 / -r.log10()).ceil() as usize + 1) })
            .collect();
        line_plot("Convergence on spot (Catmull-Clark)", "iteration", "max error / d", &series, false, true, 720, 480)
            .save_png(&dir.join("convergence.png"))
            .unwrap();
        let sizes = [1e3_f64, 1e4, 1e5, 1e6];
        let timing: Vec<Series> = [(1.0, "PIA"), (1.2, "LDLᵀ"), (3.0, "dense Gauss")]
            .iter()
            .map(|&(p, name)| {
                Series::new(
                    name,
                    sizes.iter().take(if p > 2.0 { 2 } else { 4 }).map(|&n| (n, 1e-6 * n.powf(p))).collect(),
                )
            })
            .collect();
        line_plot("Time against size", "vertices", "time (s)", &timing, true, true, 720, 480)
            .save_png(&dir.join("timing.png"))
            .unwrap();
    }
}
