//! The graphics state machine of pbrt-v4: transforms, attribute stack, named coordinate
//! systems, materials, textures and object instances, turning directives into a `SceneDesc`.

use crate::lexer::tokenize;
use crate::params::Values;
use crate::parser::{parse, Directive};
use crate::{Loc, PbrtError, Topic, Warning};
use fenestra_core::image::Image;
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::filter::PixelFilter;
use fenestra_scene::material::{self, Relief};
use fenestra_scene::texture::ImageTexture;
use fenestra_scene::transform::transformed;
use fenestra_scene::{Camera, FieldOfView, LightDesc, Material, RenderDefaults, SceneDesc, Shape};
use glam::{DMat4, DVec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// How deep Include may nest before it is taken for a cycle.
const MAX_INCLUDE_DEPTH: usize = 32;

/// An area light attached to the shapes that follow ("AreaLightSource diffuse").
#[derive(Clone, Debug)]
pub(super) struct AreaSpec {
    pub radiance: Rgb,
    pub two_sided: bool,
    /// Total emitted power (W) of each shape, replacing the radiance's magnitude.
    pub power: Option<f32>,
}

#[derive(Clone, Debug)]
pub(super) struct GraphicsState {
    pub ctm: DMat4,
    /// "ActiveTransform EndTime": transforms move objects at the shutter's close only, and
    /// fenestra renders the scene as it is when the shutter opens.
    pub end_time_only: bool,
    pub reverse: bool,
    pub material: usize,
    pub area: Option<AreaSpec>,
}

struct Saved {
    state: GraphicsState,
    transform_only: bool,
    loc: Loc,
}

/// What motion blur becomes.
const MOTION_BLUR: &str =
    "motion blur (objects are rendered where they are when the shutter opens)";

/// Warnings of one kind counted, not repeated, in the order first met.
#[derive(Default)]
pub struct Tally {
    /// One entry per kind.
    pub list: Vec<Warning>,
    index: HashMap<String, usize>,
}

impl Tally {
    fn add(&mut self, topic: Topic, what: String, loc: &Loc) {
        match self.index.get(&what) {
            Some(&i) => self.list[i].count += 1,
            None => {
                self.index.insert(what.clone(), self.list.len());
                self.list.push(Warning {
                    topic,
                    what,
                    count: 1,
                    first: loc.clone(),
                });
            }
        }
    }
}

/// A named float texture.
#[derive(Clone, Debug)]
pub(crate) enum FloatTex {
    /// A value where a material takes a constant (a constant, a checkerboard's mean), or
    /// `None` for a class fenestra does not read.
    Value(Option<f32>),
    /// An image, which rough conductors look up at each hit.
    Image(Arc<ImageTexture>),
}

impl FloatTex {
    /// The value a material that takes constants uses: the image's mean.
    pub fn average(&self) -> Option<f32> {
        match self {
            FloatTex::Value(v) => *v,
            FloatTex::Image(t) => Some(t.average().average()),
        }
    }
}

/// A named texture.
#[derive(Clone, Debug)]
pub(super) enum Tex {
    Rgb(Rgb),
    Image(Arc<ImageTexture>),
}

/// The camera as the Camera directive gave it, kept until the world begins.
pub(crate) struct CameraSpec {
    pub(crate) camera_from_world: DMat4,
    pub(crate) fov: f32,
    pub(crate) screen_window: Option<[f32; 4]>,
    pub(crate) loc: Loc,
}

pub(super) struct Builder {
    pub shapes: Vec<Shape>,
    pub materials: Vec<Material>,
    pub lights: Vec<LightDesc>,
    pub portals: Vec<[Vec3; 4]>,
    pub gs: GraphicsState,
    stack: Vec<Saved>,
    pub(crate) named_coords: HashMap<String, DMat4>,
    pub named_materials: HashMap<String, usize>,
    pub textures: HashMap<String, Tex>,
    /// Float textures by name.
    pub float_textures: HashMap<String, FloatTex>,
    /// Images read, by path and whether 8-bit values were decoded from sRGB (colour) or
    /// not (data: normal maps).
    pub(crate) images: HashMap<(PathBuf, bool), Arc<Image>>,
    /// The bump or normal map of each material that has one, by material index.
    pub(crate) reliefs: HashMap<usize, Arc<Relief>>,
    objects: HashMap<String, Vec<Shape>>,
    /// The instance being defined (ObjectBegin .. ObjectEnd) and its shapes.
    pub object: Option<(String, Vec<Shape>)>,
    pub(crate) camera: Option<CameraSpec>,
    /// The PixelFilter, if the scene names one (pbrt-v4's default is a gaussian).
    pub(crate) filter: Option<PixelFilter>,
    /// The film's white balance (Film "whitebalance" of the CIE 1931 sensor), in kelvin.
    pub(crate) white_balance: Option<f32>,
    pub(crate) defaults: RenderDefaults,
    /// The film's sensitivity (Film "iso") and the camera's shutter time (shutterclose -
    /// shutteropen): pbrt-v4 exposes the image by iso / 100 x seconds, with where it was set.
    pub(crate) iso: (f32, Option<Loc>),
    pub(crate) shutter: (f32, Option<Loc>),
    warnings: Tally,
    /// Documented approximations met (see [`crate::Loaded::notes`]).
    pub notes: Tally,
    depth: usize,
    /// Every file read besides the main one: includes, PLY meshes, images.
    pub files: Vec<PathBuf>,
}

impl Builder {
    pub fn new() -> Self {
        Builder {
            shapes: Vec::new(),
            // pbrt-v4's default material: diffuse, reflectance 0.5.
            materials: vec![Material::diffuse(0.5)],
            lights: Vec::new(),
            portals: Vec::new(),
            gs: GraphicsState {
                ctm: DMat4::IDENTITY,
                end_time_only: false,
                reverse: false,
                material: 0,
                area: None,
            },
            stack: Vec::new(),
            named_coords: HashMap::new(),
            named_materials: HashMap::new(),
            textures: HashMap::new(),
            float_textures: HashMap::new(),
            images: HashMap::new(),
            reliefs: HashMap::new(),
            objects: HashMap::new(),
            object: None,
            camera: None,
            filter: None,
            white_balance: None,
            iso: (100.0, None),
            shutter: (1.0, None),
            defaults: RenderDefaults {
                width: 1280,
                height: 720,
                spp: 16,
                max_depth: 6,
                // pbrt-v4's path tracers let a path go on through a surface where its shading
                // normal says so and its geometric one does not (docs/scenes.md).
                options: vec![("path.sides".into(), "shading".into())],
            },
            warnings: Tally::default(),
            notes: Tally::default(),
            depth: 0,
            files: Vec::new(),
        }
    }

    /// Records something unsupported and what stands in for it.
    pub fn warn(&mut self, topic: Topic, what: impl Into<String>, loc: &Loc) {
        self.warnings.add(topic, what.into(), loc);
    }

    /// Records a documented approximation.
    pub fn note(&mut self, topic: Topic, what: impl Into<String>, loc: &Loc) {
        self.notes.add(topic, what.into(), loc);
    }

    /// Parses and runs the file `path` whose contents are `bytes`; `from` is the Include
    /// directive that named it.
    pub fn run_bytes(
        &mut self,
        bytes: &[u8],
        path: &Path,
        from: Option<&Loc>,
    ) -> Result<(), PbrtError> {
        let file = Arc::new(path.to_path_buf());
        let text = std::str::from_utf8(bytes).map_err(|e| {
            let good = &bytes[..e.valid_up_to()];
            let line = good.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
            let line_start = good.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
            let col = String::from_utf8_lossy(&good[line_start..]).chars().count() as u32 + 1;
            let bad = bytes[e.valid_up_to()];
            PbrtError {
                loc: Loc {
                    file: file.clone(),
                    line,
                    col,
                },
                msg: format!("not a text file: invalid UTF-8 byte 0x{bad:02x}"),
            }
        })?;
        let tokens = tokenize(text, &file)?;
        let end = tokens.last().map_or(
            Loc {
                file: file.clone(),
                line: 1,
                col: 1,
            },
            |t| t.loc.clone(),
        );
        let directives = parse(&tokens, end)?;
        if directives.is_empty() && from.is_none() {
            return Err(PbrtError::at(
                &Loc {
                    file,
                    line: 1,
                    col: 1,
                },
                "the scene file has no directives (empty or only comments)",
            ));
        }
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        for d in &directives {
            self.directive(d, &dir)?;
            for p in d.params.unused() {
                let what = format!(
                    "parameter \"{} {}\" of {} \"{}\" (ignored)",
                    p.ty,
                    p.name,
                    d.name,
                    d.str(0)
                );
                self.warn(Topic::of_directive(d.name), what, &p.loc);
            }
        }
        Ok(())
    }

    fn include(&mut self, d: &Directive, dir: &Path) -> Result<(), PbrtError> {
        let path = dir.join(d.str(0));
        if self.depth >= MAX_INCLUDE_DEPTH {
            return Err(PbrtError::at(
                &d.loc,
                format!(
                    "{} nests more than {MAX_INCLUDE_DEPTH} files deep (an include cycle?)",
                    d.name
                ),
            ));
        }
        let cannot = |e: String| {
            PbrtError::at(
                &d.loc,
                format!("cannot read included file {}: {e}", path.display()),
            )
        };
        // Only regular files: a device such as /dev/zero would never end.
        let meta = std::fs::metadata(&path).map_err(|e| cannot(e.to_string()))?;
        if !meta.is_file() {
            return Err(cannot("not a regular file".into()));
        }
        let bytes = fenestra_scene::compressed::read(&path).map_err(|e| cannot(e.to_string()))?;
        self.files.push(path.clone());
        self.depth += 1;
        let r = self.run_bytes(&bytes, &path, Some(&d.loc));
        self.depth -= 1;
        r
    }

    fn directive(&mut self, d: &Directive, dir: &Path) -> Result<(), PbrtError> {
        const TRANSFORMS: [&str; 8] = [
            "Identity",
            "Translate",
            "Scale",
            "Rotate",
            "LookAt",
            "Transform",
            "ConcatTransform",
            "CoordSysTransform",
        ];
        if self.gs.end_time_only && TRANSFORMS.contains(&d.name) {
            self.warn(Topic::Camera, MOTION_BLUR, &d.loc);
            return Ok(());
        }
        // Spectrum files are inputs too (no command may write over them).
        for p in &d.params.params {
            if let (Values::Strs(s), "spectrum") = (&p.values, p.ty.as_str()) {
                if let [name] = &s[..] {
                    if crate::spectra::names_file(name) {
                        self.files.push(dir.join(name));
                    }
                }
            }
        }
        match d.name {
            "Include" | "Import" => self.include(d, dir)?,
            "Identity" | "Translate" | "Scale" | "Rotate" | "LookAt" | "Transform"
            | "ConcatTransform" | "CoordinateSystem" | "CoordSysTransform" => self.transform(d)?,
            "ReverseOrientation" => self.gs.reverse = !self.gs.reverse,
            "AttributeBegin" | "TransformBegin" => self.stack.push(Saved {
                state: self.gs.clone(),
                transform_only: d.name == "TransformBegin",
                loc: d.loc.clone(),
            }),
            "AttributeEnd" | "TransformEnd" => self.pop(d)?,
            "ActiveTransform" => {
                self.gs.end_time_only = d.str(0) == "EndTime";
                if d.str(0) != "All" {
                    self.warn(Topic::Camera, MOTION_BLUR, &d.loc);
                }
            }
            "TransformTimes" => self.warn(Topic::Camera, MOTION_BLUR, &d.loc),
            "WorldBegin" => {
                self.gs.ctm = DMat4::IDENTITY;
                self.named_coords.insert("world".into(), DMat4::IDENTITY);
            }
            "WorldEnd" => {}
            "Camera" => self.camera(d),
            "Film" | "Sampler" | "Integrator" | "PixelFilter" | "Accelerator" | "ColorSpace"
            | "Option" | "Attribute" | "MakeNamedMedium" | "MediumInterface" => {
                self.rendering(d)?
            }
            "Material" | "MakeNamedMaterial" | "NamedMaterial" => {
                self.material_directive(d, dir)?
            }
            "ObjectBegin" | "ObjectEnd" | "ObjectInstance" => self.object(d)?,
            "Texture" => self.texture(d, dir)?,
            "LightSource" => self.light(d, dir)?,
            "AreaLightSource" => self.area_light(d)?,
            "Shape" => self.shape(d, dir)?,
            other => {
                return Err(PbrtError::at(
                    &d.loc,
                    format!("directive {other} is not handled"),
                ))
            }
        }
        Ok(())
    }

    /// Transform directives: the current transform and named coordinate systems.
    fn transform(&mut self, d: &Directive) -> Result<(), PbrtError> {
        let num3 = |o: usize| DVec3::new(d.num(o), d.num(o + 1), d.num(o + 2));
        let matrix = || DMat4::from_cols_array(&std::array::from_fn(|i| d.num(i)));
        match d.name {
            "Identity" => self.gs.ctm = DMat4::IDENTITY,
            "Translate" => self.gs.ctm *= DMat4::from_translation(num3(0)),
            "Scale" => self.gs.ctm *= DMat4::from_scale(num3(0)),
            "Rotate" => {
                let axis = num3(1);
                if axis.length() == 0.0 {
                    return Err(PbrtError::at(&d.loc, "Rotate axis is the zero vector"));
                }
                self.gs.ctm *= DMat4::from_axis_angle(axis.normalize(), d.num(0).to_radians());
            }
            "LookAt" => self.gs.ctm *= look_at(num3(0), num3(3), num3(6), &d.loc)?,
            "Transform" => self.gs.ctm = matrix(),
            "ConcatTransform" => self.gs.ctm *= matrix(),
            "CoordinateSystem" => {
                self.named_coords.insert(d.str(0).into(), self.gs.ctm);
            }
            "CoordSysTransform" => match self.named_coords.get(d.str(0)) {
                Some(m) => self.gs.ctm = *m,
                None => {
                    return Err(PbrtError::at(
                        &d.loc,
                        format!("unknown coordinate system \"{}\"", d.str(0)),
                    ))
                }
            },
            other => unreachable!("directive {other} is dispatched here by its name"),
        }
        Ok(())
    }

    /// Material directives: the current material, named ones.
    fn material_directive(&mut self, d: &Directive, dir: &Path) -> Result<(), PbrtError> {
        match d.name {
            "Material" => self.gs.material = self.material(d.str(0), &d.params, &d.loc, dir)?,
            "MakeNamedMaterial" => {
                let Some(ty) = d.params.string("type")? else {
                    return Err(PbrtError::at(
                        &d.loc,
                        format!(
                            "MakeNamedMaterial \"{}\" needs a \"string type\" parameter",
                            d.str(0)
                        ),
                    ));
                };
                let index = self.material(&ty, &d.params, &d.loc, dir)?;
                self.named_materials.insert(d.str(0).into(), index);
            }
            "NamedMaterial" => match self.named_materials.get(d.str(0)) {
                Some(&i) => self.gs.material = i,
                None => {
                    return Err(PbrtError::at(
                        &d.loc,
                        format!(
                        "unknown named material \"{}\" (define it with MakeNamedMaterial first)",
                        d.str(0)
                    ),
                    ))
                }
            },
            other => unreachable!("directive {other} is dispatched here by its name"),
        }
        Ok(())
    }

    /// Object instancing: definitions and instances.
    fn object(&mut self, d: &Directive) -> Result<(), PbrtError> {
        match d.name {
            "ObjectBegin" => {
                if let Some((name, _)) = &self.object {
                    return Err(PbrtError::at(
                        &d.loc,
                        format!("ObjectBegin inside the definition of object \"{name}\""),
                    ));
                }
                self.stack.push(Saved {
                    state: self.gs.clone(),
                    transform_only: false,
                    loc: d.loc.clone(),
                });
                self.object = Some((d.str(0).into(), Vec::new()));
            }
            "ObjectEnd" => {
                let Some((name, shapes)) = self.object.take() else {
                    return Err(PbrtError::at(&d.loc, "ObjectEnd without ObjectBegin"));
                };
                self.objects.insert(name, shapes);
                self.pop(d)?;
            }
            "ObjectInstance" => {
                let Some(shapes) = self.objects.get(d.str(0)) else {
                    return Err(PbrtError::at(
                        &d.loc,
                        format!(
                            "unknown object \"{}\" (define it with ObjectBegin first)",
                            d.str(0)
                        ),
                    ));
                };
                if self.object.is_some() {
                    return Err(PbrtError::at(
                        &d.loc,
                        "ObjectInstance inside an object definition",
                    ));
                }
                let ctm = self.gs.ctm;
                let placed: Vec<Shape> = shapes
                    .iter()
                    .map(|s| {
                        let s = place(s, &ctm, &d.loc)?;
                        check_extent(&s, &d.loc).map(|_| s)
                    })
                    .collect::<Result<_, _>>()?;
                self.shapes.extend(placed);
            }
            other => unreachable!("directive {other} is dispatched here by its name"),
        }
        Ok(())
    }

    fn pop(&mut self, d: &Directive) -> Result<(), PbrtError> {
        let Some(saved) = self.stack.pop() else {
            return Err(PbrtError::at(
                &d.loc,
                format!("{} without a matching begin", d.name),
            ));
        };
        if saved.transform_only {
            self.gs.ctm = saved.state.ctm;
        } else {
            self.gs = saved.state;
        }
        Ok(())
    }

    /// Adds a finished shape (made by the directive at `loc`) to the scene or to the object
    /// being defined; refuses one beyond what f32 ray tracing resolves.
    pub fn add_shape(&mut self, shape: Shape, loc: &Loc) -> Result<(), PbrtError> {
        check_extent(&shape, loc)?;
        match &mut self.object {
            Some((_, shapes)) => shapes.push(shape),
            None => self.shapes.push(shape),
        }
        Ok(())
    }

    /// The scene, with the warnings and notes its directives gave.
    pub fn finish(
        mut self,
        name: String,
    ) -> Result<(SceneDesc, Vec<Warning>, Vec<Warning>), PbrtError> {
        let exposure = self.exposure();
        if let Some(open) = self.stack.last() {
            return Err(PbrtError::at(
                &open.loc,
                "this begin has no matching AttributeEnd/TransformEnd/ObjectEnd before the end of the scene",
            ));
        }
        let mut camera = match &self.camera {
            Some(c) => c.build()?,
            None => Camera::from_basis(
                Vec3::ZERO,
                Vec3::Z,
                Vec3::X,
                Vec3::Y,
                FieldOfView::ShorterAxis(90.0),
                None,
            )
            .map_err(|e| {
                PbrtError::at(
                    &Loc {
                        file: Arc::new(PathBuf::new()),
                        line: 1,
                        col: 1,
                    },
                    e.to_string(),
                )
            })?,
        };
        camera.filter = self.filter.unwrap_or_else(PixelFilter::pbrt_default);
        camera.white_balance = self.white_balance;
        let mut shapes = self.shapes;
        let mut materials = self.materials;
        // Drop pbrt's default material when no shape and no mix uses it.
        let mixes_default = materials
            .iter()
            .any(|m| matches!(m, Material::Mix(material::Mix { materials, .. }) if materials.contains(&0)));
        if !mixes_default && shapes.iter().all(|s| s.material != 0) {
            materials.remove(0);
            shapes.iter_mut().for_each(|s| s.material -= 1);
            for m in &mut materials {
                if let Material::Mix(material::Mix { materials, .. }) = m {
                    materials.iter_mut().for_each(|i| *i -= 1);
                }
            }
        }
        let desc = SceneDesc {
            name,
            shapes,
            materials,
            lights: self.lights,
            camera,
            defaults: self.defaults,
            portals: self.portals,
        };
        Ok((desc.exposed(exposure), self.warnings.list, self.notes.list))
    }
}

impl Builder {
    /// pbrt-v4's imaging ratio, iso / 100 x the shutter's seconds, which scales the image
    /// (noted where it is not 1).
    fn exposure(&mut self) -> f32 {
        let ((iso, iso_at), (seconds, shutter_at)) = (self.iso.clone(), self.shutter.clone());
        let ratio = iso / 100.0 * seconds;
        if let Some(loc) = iso_at.or(shutter_at).filter(|_| ratio != 1.0) {
            self.note(
                Topic::Camera,
                format!("the film's iso {iso} and the shutter's {seconds} s expose the image {ratio}x (pbrt-v4's imaging ratio)"),
                &loc,
            );
        }
        ratio
    }
}

pub(crate) fn positive(v: i64, what: &str, loc: &Loc) -> Result<u32, PbrtError> {
    if v > 0 && v <= 1 << 24 {
        Ok(v as u32)
    } else {
        Err(PbrtError::at(
            loc,
            format!("{what} must be a positive integer, found {v}"),
        ))
    }
}

/// pbrt's LookAt: the camera-from-world matrix of a camera at `pos` looking at `look`, whose
/// camera-space +x is up x dir (pbrt's screen space is left-handed).
fn look_at(pos: DVec3, look: DVec3, up: DVec3, loc: &Loc) -> Result<DMat4, PbrtError> {
    let dir = (look - pos).normalize_or_zero();
    let right = up.normalize_or_zero().cross(dir);
    if dir == DVec3::ZERO || right.length() < 1e-12 {
        return Err(PbrtError::at(
            loc,
            "LookAt: the eye equals the target, or the up vector is parallel to the view direction",
        ));
    }
    let right = right.normalize();
    let new_up = dir.cross(right);
    let world_from_camera = DMat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        pos.extend(1.0),
    );
    Ok(world_from_camera.inverse())
}

/// Refuses a shape beyond what f32 ray tracing resolves, at the directive that made it.
fn check_extent(shape: &Shape, loc: &Loc) -> Result<(), PbrtError> {
    match fenestra_scene::extent::extent_error(shape.extent()) {
        Some(what) => Err(PbrtError::at(loc, what)),
        None => Ok(()),
    }
}

/// `shape` moved by the transform `m` in effect at `loc`.
pub(crate) fn place(shape: &Shape, m: &DMat4, loc: &Loc) -> Result<Shape, PbrtError> {
    transformed(shape, m).map_err(|e| PbrtError::at(loc, format!("the current {e}")))
}
