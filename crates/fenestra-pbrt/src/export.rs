//! Writes a scene as a pbrt-v4 file that [`crate::load`] reads back to the same scene. Large
//! meshes go to binary PLY files and environment images to EXR, in a folder beside the file.
//! Phong and Ward materials use fenestra's own "phong"/"ward" types (pbrt-v4 has no
//! equivalent); everything else is plain pbrt-v4.

use fenestra_core::fs::{write_atomically, write_text_atomically};
use fenestra_core::{Rgb, Vec3};
use fenestra_scene::filter::{FilterShape, PixelFilter};
use fenestra_scene::light::{EnvironmentDesc, LightDesc};
use fenestra_scene::material::{self, Relief};
use fenestra_scene::{
    Camera, FieldOfView, ImageTexture, Material, SceneDesc, ShapeKind, TriangleMesh,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

mod metallic_roughness;
mod named_material;

use named_material::material;

/// Meshes with more triangles than this are written as PLY files.
const INLINE_TRIANGLES: usize = 4096;

/// An export that failed.
#[derive(Debug, thiserror::Error)]
#[error("exporting to {path}: {reason}")]
pub struct ExportError {
    /// The file being written.
    pub path: PathBuf,
    /// What went wrong.
    pub reason: String,
}

/// What an export wrote.
pub struct Exported {
    /// Every file written, the scene file first.
    pub files: Vec<PathBuf>,
    /// What pbrt-v4 cannot express and the file approximates, one line each.
    pub approximations: Vec<String>,
}

/// The folder beside `path` where an export puts its meshes and images: `<stem>-data/`.
pub fn data_folder(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    path.with_file_name(format!("{stem}-data"))
}

/// Writes `desc` to `path` (a .pbrt file) and its data folder `<stem>-data/` when needed.
pub fn write(desc: &SceneDesc, path: &Path) -> Result<Exported, ExportError> {
    let err = |reason: String| ExportError {
        path: path.to_path_buf(),
        reason,
    };
    let stem = path
        .file_stem()
        .ok_or_else(|| err("the output needs a file name".into()))?
        .to_string_lossy()
        .into_owned();
    let data_name = format!("{stem}-data");
    let mut e = Export {
        s: String::new(),
        path,
        data_dir: path.with_file_name(&data_name),
        data_name,
        files: Vec::new(),
        approximations: Vec::new(),
    };
    e.header(desc);
    e.materials(desc)?;
    let reliefs = e.reliefs(desc)?;
    let portal_written = e.lights(desc)?;
    e.portals(desc, portal_written);
    e.shapes(desc, &reliefs)?;
    write_text_atomically(path, &e.s).map_err(|x| err(x.reason))?;
    e.files.insert(0, path.to_path_buf());
    Ok(Exported {
        files: e.files,
        approximations: e.approximations,
    })
}

/// An export under way: the scene file's text and the data files written so far.
struct Export<'a> {
    s: String,
    path: &'a Path,
    data_dir: PathBuf,
    data_name: String,
    files: Vec<PathBuf>,
    approximations: Vec<String>,
}

impl Export<'_> {
    /// Writes data file `name` into the data folder with `write` (atomically); its path as
    /// the scene file names it.
    fn data<E: std::fmt::Display>(
        &mut self,
        name: String,
        write: impl FnOnce(&Path) -> Result<(), E>,
    ) -> Result<String, ExportError> {
        let err = |reason: String| ExportError {
            path: self.path.to_path_buf(),
            reason,
        };
        std::fs::create_dir_all(&self.data_dir).map_err(|e| err(e.to_string()))?;
        let file = self.data_dir.join(&name);
        write_atomically(&file, write).map_err(|e| err(e.to_string()))?;
        self.files.push(file);
        Ok(format!("{}/{name}", self.data_name))
    }

    /// The film, sampler, integrator and camera.
    fn header(&mut self, desc: &SceneDesc) {
        let d = &desc.defaults;
        let _ = writeln!(
            self.s,
            "# {} exported by fenestra {}",
            desc.name,
            env!("CARGO_PKG_VERSION")
        );
        let balance = match desc.camera.white_balance {
            Some(k) => format!(" \"float whitebalance\" [ {k} ]"),
            None => String::new(),
        };
        let _ = writeln!(
            self.s,
            "Film \"rgb\" \"integer xresolution\" [ {} ] \"integer yresolution\" [ {} ]{balance}",
            d.width, d.height
        );
        let _ = writeln!(
            self.s,
            "Sampler \"zsobol\" \"integer pixelsamples\" [ {} ]",
            d.spp
        );
        // fenestra counts path segments (2 = direct light), pbrt bounces.
        let _ = write!(
            self.s,
            "Integrator \"path\" \"integer maxdepth\" [ {} ]",
            d.max_depth.saturating_sub(1)
        );
        // The options a pbrt-v4 Integrator directive can say (the light sampler).
        for (key, value) in &d.options {
            if key == "light.selection" && matches!(value.as_str(), "bvh" | "power" | "uniform") {
                let _ = write!(self.s, " \"string lightsampler\" \"{value}\"");
            }
        }
        self.s.push('\n');
        camera(&mut self.s, &desc.camera, d.width, d.height);
        self.s.push_str("\nWorldBegin\n\n");
    }

    /// Every material, with the textures it reads.
    fn materials(&mut self, desc: &SceneDesc) -> Result<(), ExportError> {
        for (i, m) in desc.materials.iter().enumerate() {
            // Texel values as loaded (linear), whatever files they came from.
            let mut textures: Vec<(String, &str, &ImageTexture)> = Vec::new();
            if let Some(texture) = m.texture() {
                textures.push((format!("t{i}"), "spectrum", texture));
            }
            if let Material::RoughConductor(material::RoughConductor {
                roughness: Some(map),
                ..
            }) = m
            {
                for (axis, t) in [("u", &map.u), ("v", &map.v)] {
                    if let Some(t) = t {
                        textures.push((format!("r{i}{axis}"), "float", t));
                    }
                }
            }
            for (name, kind, texture) in textures {
                let file = self.data(format!("texture-{}.exr", &name[1..]), |tmp| {
                    texture.image.write_exr(tmp, &Default::default())
                })?;
                let _ = writeln!(self.s,
                    "Texture \"{name}\" \"{kind}\" \"imagemap\" \"string filename\" \"{file}\" \"float scale\" [ {} ] \"bool invert\" {} \"float uscale\" [ {} ] \"float vscale\" [ {} ] \"float udelta\" [ {} ] \"float vdelta\" [ {} ]",
                    texture.scale, texture.invert, texture.uscale, texture.vscale, texture.udelta, texture.vdelta
                );
            }
            if let Material::MetallicRoughness(m) = m {
                for (name, parameters) in metallic_roughness::parts(i, m) {
                    let _ = writeln!(self.s, "MakeNamedMaterial \"{name}\" {parameters}");
                }
                self.approximations
                    .extend(metallic_roughness::approximations(i, m));
            }
            material(&mut self.s, i, m);
        }
        Ok(())
    }

    /// The lights that are not shapes; whether the scene's first portal went with an
    /// infinite light.
    fn lights(&mut self, desc: &SceneDesc) -> Result<bool, ExportError> {
        let mut portals_written = desc.portals.is_empty();
        for (i, l) in desc.lights.iter().enumerate() {
            match l {
                LightDesc::Point {
                    position,
                    intensity,
                } => {
                    let _ = writeln!(
                        self.s,
                        "LightSource \"point\" \"point3 from\" [ {} ] \"rgb I\" [ {} ]",
                        v3(*position),
                        rgb(*intensity)
                    );
                }
                LightDesc::Spot {
                    position,
                    direction,
                    intensity,
                    cone_angle,
                    falloff_start,
                } => {
                    let _ = writeln!(self.s,
                        "LightSource \"spot\" \"point3 from\" [ {} ] \"point3 to\" [ {} ] \"rgb I\" [ {} ] \"float coneangle\" [ {} ] \"float conedeltaangle\" [ {} ]",
                        v3(*position),
                        v3(*position + *direction),
                        rgb(*intensity),
                        cone_angle,
                        cone_angle - falloff_start
                    );
                }
                LightDesc::Distant {
                    direction,
                    irradiance,
                } => {
                    let _ = writeln!(self.s,
                        "LightSource \"distant\" \"point3 from\" [ 0 0 0 ] \"point3 to\" [ {} ] \"rgb L\" [ {} ]",
                        v3(*direction),
                        rgb(*irradiance)
                    );
                }
                LightDesc::Environment(env) => {
                    // The scene's first portal goes with its first environment that takes one.
                    let mut portal = || {
                        if portals_written {
                            return String::new();
                        }
                        portals_written = true;
                        let c = facing(desc.portals[0], desc.camera.position);
                        format!(
                            " \"point3 portal\" [ {} {} {} {} ]",
                            v3(c[0]),
                            v3(c[1]),
                            v3(c[2]),
                            v3(c[3])
                        )
                    };
                    match env {
                        EnvironmentDesc::Constant(l) => {
                            let portal = portal();
                            let _ = writeln!(
                                self.s,
                                "LightSource \"infinite\" \"rgb L\" [ {} ]{portal}",
                                rgb(*l)
                            );
                        }
                        EnvironmentDesc::Image {
                            image,
                            scale,
                            to_world,
                        } => {
                            // pbrt-v4 reads square equal-area maps only: resampled (side = the
                            // map's height, so that reading it back gives the same size).
                            let mut baked = crate::equal_area::latlong_to_equal_area(image);
                            for c in &mut baked.pixels {
                                *c = Rgb::new(c.r * scale.r, c.g * scale.g, c.b * scale.b);
                            }
                            let file = self.data(format!("environment-{i}.exr"), |tmp| {
                                baked.write_exr(tmp, &Default::default())
                            })?;
                            let portal = portal();
                            let m = glam::Mat4::from_mat3(*to_world);
                            let _ = writeln!(self.s, "AttributeBegin");
                            let _ =
                                writeln!(self.s, "  Transform [ {} ]", join(&m.to_cols_array()));
                            let _ =
                                writeln!(self.s,
                                "  LightSource \"infinite\" \"string filename\" \"{file}\"{portal}"
                            );
                            let _ = writeln!(self.s, "AttributeEnd");
                        }
                        EnvironmentDesc::Sun {
                            direction,
                            radiance,
                            half_angle,
                        } => {
                            let cap = 1.0 - half_angle.cos();
                            let _ = writeln!(self.s,
                                "LightSource \"distant\" \"point3 from\" [ 0 0 0 ] \"point3 to\" [ {} ] \"rgb L\" [ {} ]  # the sun",
                                v3(-*direction),
                                rgb(*radiance * (2.0 * std::f32::consts::PI * cap))
                            );
                            self.approximations.push(format!(
                                "light {i}: the sun's disk ({:.3} degrees across) as a distant light of its irradiance (pbrt-v4 has no disk at infinity: sharp shadows, no sun in mirrors)",
                                2.0 * half_angle.to_degrees()
                            ));
                        }
                    }
                }
            }
        }
        Ok(portals_written)
    }

    /// Portals not attached to an infinite light (pbrt-v4 takes one per light): quads with
    /// the "interface" material, invisible to pbrt-v4 and read back as portals.
    fn portals(&mut self, desc: &SceneDesc, portals_written: bool) {
        let first = usize::from(!desc.portals.is_empty() && portals_written);
        for c in &desc.portals[first..] {
            let _ = writeln!(self.s,
                "\nAttributeBegin  # light portal\n  Material \"interface\"\n  Shape \"trianglemesh\" \"point3 P\" [ {} {} {} {} ] \"integer indices\" [ 0 1 2  0 2 3 ]\nAttributeEnd",
                v3(c[0]),
                v3(c[1]),
                v3(c[2]),
                v3(c[3])
            );
        }
    }

    /// A material of its own for each material and relief shapes share (pbrt-v4 gives bump
    /// and normal maps to materials, fenestra to shapes): "m{i}-relief{k}", m{i}'s parameters
    /// and the relief's, its image written as linear EXR. The shapes' material names, in
    /// shape order.
    fn reliefs(&mut self, desc: &SceneDesc) -> Result<Vec<String>, ExportError> {
        let mut seen: Vec<(usize, &Arc<Relief>)> = Vec::new();
        let mut names = Vec::with_capacity(desc.shapes.len());
        for shape in &desc.shapes {
            let Some(relief) = &shape.relief else {
                names.push(format!("m{}", shape.material));
                continue;
            };
            let key =
                |(m, r): &(usize, &Arc<Relief>)| *m == shape.material && Arc::ptr_eq(r, relief);
            let k = match seen.iter().position(key) {
                Some(k) => k,
                None => {
                    seen.push((shape.material, relief));
                    self.relief_material(seen.len() - 1, shape.material, relief, desc)?;
                    seen.len() - 1
                }
            };
            names.push(format!("m{}-relief{k}", shape.material));
        }
        Ok(names)
    }

    fn relief_material(
        &mut self,
        k: usize,
        i: usize,
        relief: &Relief,
        desc: &SceneDesc,
    ) -> Result<(), ExportError> {
        let (image, parameter) = match relief {
            Relief::Bump(b) => (
                &b.displacement,
                format!("\"texture displacement\" \"d{k}\""),
            ),
            Relief::Normals(n) => {
                if n.scale != 1.0 {
                    self.approximations.push(format!(
                        "m{i}: a normal map's scale {} (pbrt-v4's normal maps have none; written unscaled)",
                        n.scale
                    ));
                }
                (&n.texture, String::new())
            }
        };
        let file = self.data(format!("relief-{k}.exr"), |tmp| {
            image.image.write_exr(tmp, &Default::default())
        })?;
        let parameter = match relief {
            Relief::Bump(_) => {
                let _ = writeln!(self.s,
                    "Texture \"d{k}\" \"float\" \"imagemap\" \"string filename\" \"{file}\" \"float scale\" [ {} ] \"bool invert\" {} \"float uscale\" [ {} ] \"float vscale\" [ {} ] \"float udelta\" [ {} ] \"float vdelta\" [ {} ]",
                    image.scale, image.invert, image.uscale, image.vscale, image.udelta, image.vdelta
                );
                parameter
            }
            Relief::Normals(_) => format!("\"string normalmap\" \"{file}\""),
        };
        let mut text = String::new();
        material(&mut text, i, &desc.materials[i]);
        let text = text.replacen(&format!("\"m{i}\""), &format!("\"m{i}-relief{k}\""), 1);
        let _ = writeln!(self.s, "{} {parameter}", text.trim_end());
        Ok(())
    }

    /// Every shape, with its material (`materials`: each shape's name for it) and emission.
    fn shapes(&mut self, desc: &SceneDesc, materials: &[String]) -> Result<(), ExportError> {
        for (i, shape) in desc.shapes.iter().enumerate() {
            let _ = writeln!(self.s, "\nAttributeBegin");
            let _ = writeln!(self.s, "  NamedMaterial \"{}\"", materials[i]);
            if let Some(e) = &shape.emission {
                let _ = writeln!(
                    self.s,
                    "  AreaLightSource \"diffuse\" \"rgb L\" [ {} ] \"bool twosided\" {}",
                    rgb(e.radiance),
                    e.two_sided
                );
            }
            match &shape.kind {
                ShapeKind::Mesh(mesh) => {
                    let mut mesh = std::borrow::Cow::Borrowed(mesh);
                    if shape.flip_normals {
                        match mesh.to_mut().normals.as_mut() {
                            // With vertex normals pbrt-v4 ignores ReverseOrientation: flip them.
                            Some(n) => n.iter_mut().for_each(|v| *v = -*v),
                            None => self.s.push_str("  ReverseOrientation\n"),
                        }
                    }
                    if mesh.indices.len() > INLINE_TRIANGLES {
                        let file = self.data(format!("shape-{i}.ply"), |tmp| {
                            let mut w = std::io::BufWriter::new(std::fs::File::create(tmp)?);
                            fenestra_scene::mesh::ply::write(&mesh, &mut w)?;
                            std::io::Write::flush(&mut w)
                        })?;
                        let _ =
                            writeln!(self.s, "  Shape \"plymesh\" \"string filename\" \"{file}\"");
                    } else {
                        inline_mesh(&mut self.s, &mesh);
                    }
                }
                ShapeKind::Sphere { center, radius } => {
                    // A mirroring turn flips the sphere in pbrt-v4 as it did when read.
                    let mirrored = shape.orientation.is_some_and(|o| o.determinant() < 0.0);
                    if shape.flip_normals != mirrored {
                        self.s.push_str("  ReverseOrientation\n");
                    }
                    match shape.orientation {
                        Some(o) => {
                            let m = glam::Mat4::from_cols(
                                o.x_axis.extend(0.0),
                                o.y_axis.extend(0.0),
                                o.z_axis.extend(0.0),
                                center.extend(1.0),
                            );
                            let _ =
                                writeln!(self.s, "  Transform [ {} ]", join(&m.to_cols_array()));
                        }
                        None => {
                            let _ = writeln!(self.s, "  Translate {}", v3(*center));
                        }
                    }
                    let _ = writeln!(self.s, "  Shape \"sphere\" \"float radius\" [ {radius} ]");
                }
                ShapeKind::Disk {
                    center,
                    normal,
                    radius,
                } => {
                    if shape.flip_normals {
                        self.s.push_str("  ReverseOrientation\n");
                    }
                    // A right-handed frame with z along the normal (no mirroring, no flip).
                    let f = fenestra_core::Frame::from_normal(*normal);
                    let t = normal.cross(f.s);
                    let m = glam::Mat4::from_cols(
                        f.s.extend(0.0),
                        t.extend(0.0),
                        normal.extend(0.0),
                        center.extend(1.0),
                    );
                    let _ = writeln!(self.s, "  Transform [ {} ]", join(&m.to_cols_array()));
                    let _ = writeln!(self.s, "  Shape \"disk\" \"float radius\" [ {radius} ]");
                }
            }
            let _ = writeln!(self.s, "AttributeEnd");
        }
        Ok(())
    }
}

/// The quad `c` wound so that its normal (right-handed, corners in order) points to `inside`:
/// pbrt-v4 takes light through a portal from the side its normal faces away from, and renders
/// black through a portal wound the other way.
fn facing(c: [Vec3; 4], inside: Vec3) -> [Vec3; 4] {
    let n = (c[1] - c[0]).cross(c[2] - c[0]);
    if n.dot(inside - c[0]) >= 0.0 {
        c
    } else {
        [c[0], c[3], c[2], c[1]]
    }
}

fn join(v: &[f32]) -> String {
    v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

fn v3(v: Vec3) -> String {
    join(&v.to_array())
}

fn rgb(c: Rgb) -> String {
    join(&c.to_array())
}

/// The camera's pixel filter, always written: pbrt-v4's default (a gaussian) is not
/// fenestra's (the pixel's box).
fn pixel_filter(s: &mut String, f: &PixelFilter) {
    let (name, extra) = match *f.shape() {
        FilterShape::Box => ("box", String::new()),
        FilterShape::Triangle => ("triangle", String::new()),
        FilterShape::Gaussian { sigma } => ("gaussian", format!(" \"float sigma\" [ {sigma} ]")),
        FilterShape::Mitchell { b, c } => (
            "mitchell",
            format!(" \"float B\" [ {b} ] \"float C\" [ {c} ]"),
        ),
        FilterShape::Sinc { tau } => ("sinc", format!(" \"float tau\" [ {tau} ]")),
    };
    let _ = writeln!(
        s,
        "PixelFilter \"{name}\" \"float xradius\" [ {} ] \"float yradius\" [ {} ]{extra}",
        f.radius().x,
        f.radius().y
    );
}

fn camera(s: &mut String, c: &Camera, width: u32, height: u32) {
    let (forward, right, up) = c.basis();
    let orthonormal_rh = (forward.length() - 1.0).abs() < 1e-5
        && (right.length() - 1.0).abs() < 1e-5
        && (up.length() - 1.0).abs() < 1e-5
        && forward.cross(up).dot(right) > 0.9999;
    if orthonormal_rh {
        // pbrt's camera space is left-handed: mirror x so that the picture is not mirrored.
        let _ = writeln!(s, "Scale -1 1 1");
        let _ = writeln!(
            s,
            "LookAt {}  {}  {}",
            v3(c.position),
            v3(c.position + forward),
            v3(up)
        );
    } else {
        let world_from_camera = glam::DMat4::from_cols(
            right.as_dvec3().extend(0.0),
            up.as_dvec3().extend(0.0),
            forward.as_dvec3().extend(0.0),
            c.position.as_dvec3().extend(1.0),
        );
        let m = world_from_camera.inverse().as_mat4();
        let _ = writeln!(s, "Transform [ {} ]", join(&m.to_cols_array()));
    }
    let (FieldOfView::Vertical(fov) | FieldOfView::ShorterAxis(fov)) = c.fov;
    // pbrt's fov spans the shorter axis: a portrait image with a vertical fov, or any
    // explicit window, is written as a screen window.
    let window = match (c.fov, c.screen_window) {
        (_, Some(w)) => Some(w),
        (FieldOfView::Vertical(_), None) if width < height => {
            let a = width as f32 / height as f32;
            Some([-a, a, -1.0, 1.0])
        }
        _ => None,
    };
    pixel_filter(s, &c.filter);
    let _ = write!(s, "Camera \"perspective\" \"float fov\" [ {fov} ]");
    if let Some(w) = window {
        let _ = write!(s, " \"float screenwindow\" [ {} ]", join(&w));
    }
    s.push('\n');
}

fn inline_mesh(s: &mut String, m: &TriangleMesh) {
    let flat = |v: &[Vec3]| v.iter().map(|p| v3(*p)).collect::<Vec<_>>().join("  ");
    let _ = write!(
        s,
        "  Shape \"trianglemesh\"\n    \"point3 P\" [ {} ]\n    \"integer indices\" [ ",
        flat(&m.positions)
    );
    let idx: Vec<String> = m.indices.iter().flatten().map(|i| i.to_string()).collect();
    let _ = write!(s, "{} ]", idx.join(" "));
    if let Some(n) = &m.normals {
        let _ = write!(s, "\n    \"normal N\" [ {} ]", flat(n));
    }
    if let Some(uv) = &m.uvs {
        let t: Vec<String> = uv.iter().map(|p| format!("{} {}", p.x, p.y)).collect();
        let _ = write!(s, "\n    \"point2 uv\" [ {} ]", t.join("  "));
    }
    s.push('\n');
}

#[cfg(test)]
mod portal_winding_tests {
    use super::*;

    #[test]
    fn a_portal_is_wound_to_face_the_inside() {
        // box-hole's hole, wound counter-clockwise seen from above (normal up, to the sky):
        // pbrt-v4 rendered the sky through it black until it was turned to face the room.
        let up = [
            Vec3::new(-1.0, -1.0, 0.5),
            Vec3::new(1.0, -1.0, 0.5),
            Vec3::new(1.0, 1.0, 0.5),
            Vec3::new(-1.0, 1.0, 0.5),
        ];
        let normal = |c: [Vec3; 4]| (c[1] - c[0]).cross(c[2] - c[0]).normalize();
        let inside = Vec3::new(0.3, 0.2, 0.0);
        assert_eq!(normal(facing(up, inside)), -Vec3::Z);
        assert_eq!(facing(up, Vec3::new(0.0, 0.0, 2.0)), up);
        // The same four corners either way.
        let turned = facing(up, inside);
        assert!(up.iter().all(|p| turned.contains(p)));
    }
}
