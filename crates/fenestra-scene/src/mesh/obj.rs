//! Wavefront OBJ with MTL materials through tobj. MTL maps onto fenestra materials as:
//! Ke > 0 -> diffuse area emission; d < 1 or illum 4/6/7/9 -> smooth dielectric of index Ni
//! (1.5 if absent); Ks > 0 -> normalised Phong (Kd, Ks, Ns); map_Kd -> textured diffuse;
//! otherwise Lambertian Kd (0.5 when absent).

use super::MeshError;
use crate::material;
use crate::texture::ImageTexture;
use crate::{Material, TriangleMesh};
use fenestra_core::image::Image;
use fenestra_core::{Rgb, Vec2, Vec3};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// An OBJ file's meshes, each with an index into `materials`.
pub struct ObjModel {
    /// The meshes, each with its material's index.
    pub meshes: Vec<(TriangleMesh, usize)>,
    /// Materials with their emitted radiance (Ke), if any; the last is the default material
    /// of faces without one.
    pub materials: Vec<(Material, Option<Rgb>)>,
    /// Problems that did not stop loading (a missing MTL file, an unreadable texture).
    pub warnings: Vec<String>,
    /// The MTL files it names (`mtllib`), read or not: inputs no output may replace.
    pub material_files: Vec<PathBuf>,
}

/// Reads an OBJ file and its MTL materials.
pub fn read(path: &Path) -> Result<ObjModel, MeshError> {
    let err = |reason: String| MeshError {
        path: path.to_path_buf(),
        reason,
    };
    let text = std::fs::read(path).map_err(|e| err(e.to_string()))?;
    check_indices(&text).map_err(|e| err(e.to_string()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let material_files = std::cell::RefCell::new(Vec::new());
    let (models, mtl) = tobj::load_obj_buf(
        &mut std::io::Cursor::new(&text),
        &tobj::GPU_LOAD_OPTIONS,
        |mtl| {
            material_files.borrow_mut().push(dir.join(mtl));
            tobj::load_mtl(dir.join(mtl))
        },
    )
    .map_err(|e| err(e.to_string()))?;
    let mut warnings = Vec::new();
    let mtl = mtl.unwrap_or_else(|e| {
        warnings.push(format!("{}: materials not loaded ({e})", path.display()));
        Vec::new()
    });
    let mut materials: Vec<(Material, Option<Rgb>)> =
        mtl.iter().map(|m| convert(m, dir, &mut warnings)).collect();
    let default = materials.len();
    materials.push((Material::diffuse(0.5), None));
    let mut meshes = Vec::new();
    for m in &models {
        let mesh = &m.mesh;
        let n = mesh.positions.len() / 3;
        let vec3s = |v: &[f32]| -> Vec<Vec3> {
            v.chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2]))
                .collect()
        };
        let normals = (mesh.normals.len() == 3 * n && n > 0).then(|| vec3s(&mesh.normals));
        let uvs = (mesh.texcoords.len() == 2 * n && n > 0).then(|| {
            mesh.texcoords
                .chunks_exact(2)
                .map(|c| Vec2::new(c[0], c[1]))
                .collect()
        });
        let indices: Vec<[u32; 3]> = mesh
            .indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        if let Some(bad) = indices.iter().flatten().find(|&&i| i as usize >= n) {
            return Err(err(format!("object '{}' uses vertex {bad} of {n}", m.name)));
        }
        if indices.is_empty() {
            continue;
        }
        let material = mesh.material_id.filter(|&i| i < default).unwrap_or(default);
        meshes.push((
            TriangleMesh {
                positions: vec3s(&mesh.positions),
                normals,
                uvs,
                indices,
            },
            material,
        ));
    }
    if meshes.is_empty() {
        return Err(err("no triangles".into()));
    }
    Ok(ObjModel {
        meshes,
        materials,
        warnings,
        material_files: material_files.into_inner(),
    })
}

/// A face or line index that names nothing.
#[derive(Debug)]
struct BadIndex {
    line: usize,
    index: i64,
    kind: &'static str,
    /// How many the file defines (in all, or before the line).
    defined: i64,
    /// Whether the index is past the file's last one (not only past those before it).
    later: bool,
}

impl std::fmt::Display for BadIndex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let BadIndex {
            line,
            index,
            kind,
            defined,
            later,
        } = self;
        write!(f, "line {line}: index {index} names no {kind} (")?;
        if *later {
            write!(f, "the file has {defined})")
        } else {
            write!(f, "{defined} defined before it)")
        }
    }
}

/// Every face or line index must name a vertex, texture coordinate or normal, said with its
/// line: tobj multiplies indices unchecked, which overflows for one far out of range (a
/// relative index before the first vertex, found by cargo fuzz), and names no line for an
/// index past the file's last vertex.
fn check_indices(text: &[u8]) -> Result<(), BadIndex> {
    const KINDS: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    let mut defined = [0i64; 3];
    // Per kind, the largest absolute index and its line (the file may define it later).
    let mut largest = [(0i64, 0usize); 3];
    for (no, line) in text.split(|&b| b == b'\n').enumerate() {
        let Ok(line) = std::str::from_utf8(line) else {
            continue; // tobj refuses the file
        };
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => defined[0] += 1,
            Some("vt") => defined[1] += 1,
            Some("vn") => defined[2] += 1,
            Some("f" | "l") => {
                for word in words {
                    for (kind, index) in word.split('/').take(3).enumerate() {
                        let Ok(i) = index.parse::<i64>() else {
                            continue; // empty (v//vn) or not a number: tobj refuses it
                        };
                        // Relative indices count back from the last one defined so far.
                        if i > largest[kind].0 {
                            largest[kind] = (i, no + 1);
                        }
                        let names_one = if i < 0 {
                            i.checked_neg().is_some_and(|back| back <= defined[kind])
                        } else {
                            i <= i64::from(u32::MAX)
                        };
                        if !names_one {
                            return Err(BadIndex {
                                line: no + 1,
                                index: i,
                                kind: KINDS[kind],
                                defined: defined[kind],
                                later: false,
                            });
                        }
                    }
                }
            }
            _ => {}
        }
    }
    for (kind, &(i, line)) in largest.iter().enumerate() {
        if i > defined[kind] {
            return Err(BadIndex {
                line,
                index: i,
                kind: KINDS[kind],
                defined: defined[kind],
                later: true,
            });
        }
    }
    Ok(())
}

fn convert(m: &tobj::Material, dir: &Path, warnings: &mut Vec<String>) -> (Material, Option<Rgb>) {
    let rgb = |c: Option<[f32; 3]>| c.map(Rgb::from);
    let mut kd = rgb(m.diffuse).unwrap_or(Rgb::splat(0.5));
    if kd.max_component() > 1.0 {
        warnings.push(format!(
            "material '{}': Kd {:?} above 1, clamped to 1 (as pbrt-v4 clamps reflectances)",
            m.name,
            kd.to_array()
        ));
        kd = kd.map(|c| c.min(1.0));
    }
    let ks = rgb(m.specular).unwrap_or(Rgb::ZERO);
    let emission = rgb(m.emissive).filter(|e| e.max_component() > 0.0);
    let transparent =
        m.dissolve.is_some_and(|d| d < 1.0) || matches!(m.illumination_model, Some(4 | 6 | 7 | 9));
    let material = if transparent {
        Material::Dielectric(material::Dielectric {
            eta: m.optical_density.filter(|&n| n > 0.0).unwrap_or(1.5),
        })
    } else if let Some(tex) = &m.diffuse_texture {
        let p = dir.join(tex.replace('\\', "/"));
        match Image::read(&p) {
            Ok(img) => Material::TexturedDiffuse(material::TexturedDiffuse {
                texture: Arc::new(ImageTexture::new(Arc::new(img), p)),
            }),
            Err(e) => {
                warnings.push(format!(
                    "material '{}': texture not loaded ({e}); using Kd",
                    m.name
                ));
                Material::Diffuse(material::Diffuse { reflectance: kd })
            }
        }
    } else if ks.max_component() > 0.0 {
        Material::Phong(material::Phong {
            diffuse: kd,
            specular: ks,
            exponent: m.shininess.unwrap_or(10.0).max(0.0),
        })
    } else {
        Material::Diffuse(material::Diffuse { reflectance: kd })
    };
    (material, emission)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_mtl_materials() {
        let dir = std::env::temp_dir().join(format!("fenestra-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        std::fs::write(
            dir.join("m.mtl"),
            "newmtl lamp\nKd 0 0 0\nKe 5 5 4\nnewmtl glass\nNi 1.33\nd 0.2\n\
             newmtl shiny\nKd 0.2 0.3 0.4\nKs 0.5 0.5 0.5\nNs 80\n",
        )
        .expect("mtl");
        std::fs::write(
            dir.join("m.obj"),
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n\
             usemtl glass\nf 1 3 4\no other\nusemtl shiny\nf 1 2 3 4\n",
        )
        .expect("obj");
        let m = read(&dir.join("m.obj")).expect("read");
        let tris: usize = m.meshes.iter().map(|(t, _)| t.indices.len()).sum();
        assert_eq!(tris, 4);
        assert_eq!(m.materials[0].1, Some(Rgb::new(5.0, 5.0, 4.0)));
        assert!(
            matches!(m.materials[1].0, Material::Dielectric(material::Dielectric { eta }) if (eta - 1.33).abs() < 1e-6)
        );
        assert!(
            matches!(m.materials[2].0, Material::Phong(material::Phong { exponent, .. }) if exponent == 80.0)
        );
        // Reflectance above 1 is clamped, as pbrt-v4 clamps it, and said.
        std::fs::write(dir.join("hot.mtl"), "newmtl hot\nKd 50 0.5 0.5\n").expect("mtl");
        std::fs::write(
            dir.join("hot.obj"),
            "mtllib hot.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nusemtl hot\nf 1 2 3\n",
        )
        .expect("obj");
        let hot = read(&dir.join("hot.obj")).expect("read");
        assert!(
            hot.warnings.iter().any(|w| w.contains("clamped")),
            "{:?}",
            hot.warnings
        );
        assert!(matches!(
            hot.materials[0].0,
            Material::Diffuse(material::Diffuse { reflectance }) if reflectance == Rgb::new(1.0, 0.5, 0.5)
        ));
        std::fs::write(dir.join("bad.obj"), "v 0 0 0\nf 1 2 3\n").expect("obj");
        assert!(read(&dir.join("bad.obj")).is_err());
        // Relative indices count back from the last vertex; one before the first is refused
        // with its line (tobj's arithmetic overflowed on it).
        let tri = "v 0 0 0\nv 1 0 0\nv 1 1 0\nvn 0 0 1\n";
        std::fs::write(dir.join("rel.obj"), format!("{tri}f -3//1 -2//1 -1//-1\n")).expect("obj");
        assert_eq!(read(&dir.join("rel.obj")).expect("read").meshes.len(), 1);
        for (face, says) in [
            (
                "f 1//-800001 2//1 3//1",
                "line 5: index -800001 names no normal (1 defined",
            ),
            ("f -4 -2 -1", "line 5: index -4 names no vertex (3 defined"),
            (
                "f 1/9223372036854775807 2 3",
                "index 9223372036854775807 names no texture",
            ),
            // Past the file's last vertex (tobj said "face vertex index out of bounds").
            (
                "f 1 2 7",
                "line 5: index 7 names no vertex (the file has 3)",
            ),
            // A later vertex may be named before it is defined.
            (
                "f 1 2 4
v 0 0 1
f 1 2 7",
                "line 7: index 7 names no vertex (the file has 4)",
            ),
        ] {
            std::fs::write(dir.join("far.obj"), format!("{tri}{face}\n")).expect("obj");
            let e = read(&dir.join("far.obj"))
                .err()
                .expect("refused")
                .to_string();
            assert!(e.contains(says), "{face}: {e}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
