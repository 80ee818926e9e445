//! PLY meshes, ASCII and binary, with optional normals and texture coordinates, through
//! ply-rs-bw; polygons are fan-triangulated.

use super::{fan, MeshError};
use crate::TriangleMesh;
use fenestra_core::{Vec2, Vec3};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{
    Addable, ElementDef, Encoding, Header, PropertyAccess, PropertyAccessResult, PropertyDef,
    PropertyType, ScalarType,
};
use ply_rs_bw::writer::Writer;
use std::io::Write;
use std::path::Path;

#[derive(Default)]
struct Vertex {
    p: [f32; 3],
    n: [f32; 3],
    uv: [f32; 2],
}

impl Vertex {
    fn set(&mut self, name: &str, v: f32) -> PropertyAccessResult {
        let slot = match name {
            "x" => &mut self.p[0],
            "y" => &mut self.p[1],
            "z" => &mut self.p[2],
            "nx" => &mut self.n[0],
            "ny" => &mut self.n[1],
            "nz" => &mut self.n[2],
            "u" | "s" | "texture_u" | "texture_s" => &mut self.uv[0],
            "v" | "t" | "texture_v" | "texture_t" => &mut self.uv[1],
            _ => return PropertyAccessResult::Ignored,
        };
        *slot = v;
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Vertex::default()
    }
    fn set_float(&mut self, name: &str, v: f32) -> PropertyAccessResult {
        self.set(name, v)
    }
    fn set_double(&mut self, name: &str, v: f64) -> PropertyAccessResult {
        self.set(name, v as f32)
    }
    fn get_float(&self, name: &str) -> Option<f32> {
        Some(match name {
            "x" => self.p[0],
            "y" => self.p[1],
            "z" => self.p[2],
            "nx" => self.n[0],
            "ny" => self.n[1],
            "nz" => self.n[2],
            "u" => self.uv[0],
            "v" => self.uv[1],
            _ => return None,
        })
    }
}

#[derive(Default)]
struct Face {
    indices: Vec<i64>,
}

impl Face {
    fn set<T: Into<i64> + Copy>(&mut self, name: &str, v: &[T]) -> PropertyAccessResult {
        if name == "vertex_indices" || name == "vertex_index" {
            self.indices = v.iter().map(|&i| i.into()).collect();
            PropertyAccessResult::Set
        } else {
            PropertyAccessResult::Ignored
        }
    }
}

impl PropertyAccess for Face {
    fn new() -> Self {
        Face::default()
    }
    fn set_list_char(&mut self, n: &str, v: Vec<i8>) -> PropertyAccessResult {
        self.set(n, &v)
    }
    fn set_list_uchar(&mut self, n: &str, v: Vec<u8>) -> PropertyAccessResult {
        self.set(n, &v)
    }
    fn set_list_short(&mut self, n: &str, v: Vec<i16>) -> PropertyAccessResult {
        self.set(n, &v)
    }
    fn set_list_ushort(&mut self, n: &str, v: Vec<u16>) -> PropertyAccessResult {
        self.set(n, &v)
    }
    fn set_list_int(&mut self, n: &str, v: Vec<i32>) -> PropertyAccessResult {
        self.set(n, &v)
    }
    fn set_list_uint(&mut self, n: &str, v: Vec<u32>) -> PropertyAccessResult {
        self.set(n, &v)
    }
}

/// For writing: a triangle as a `vertex_indices` list of three.
struct WriteFace([i32; 3]);

impl PropertyAccess for WriteFace {
    fn new() -> Self {
        WriteFace([0; 3])
    }
    fn get_list_int(&self, name: &str) -> Option<&[i32]> {
        (name == "vertex_indices").then_some(&self.0[..])
    }
}

/// Reads a PLY triangle (or polygon) mesh.
pub fn read(path: &Path) -> Result<TriangleMesh, MeshError> {
    let err = |reason: String| MeshError {
        path: path.to_path_buf(),
        reason,
    };
    let file = crate::compressed::Source::open(path).map_err(|e| err(e.to_string()))?;
    let most_bytes = file.most_bytes();
    let mut reader = ply_rs_bw::parser::Reader::new(file);
    let vparser = Parser::<Vertex>::new();
    let fparser = Parser::<Face>::new();
    let header = vparser
        .read_header(&mut reader)
        .map_err(|e| err(format!("bad PLY header: {e}")))?;
    // A header may claim any count; the reader would grow its arrays until memory ran out
    // on elements that take no bytes (found by cargo fuzz).
    for (name, def) in &header.elements {
        let least = least_bytes(def, header.encoding);
        if (def.count as u64).saturating_mul(least) > most_bytes {
            return Err(err(format!(
                "element '{name}' claims {} entries of at least {least} bytes, more than the file holds",
                def.count
            )));
        }
    }
    let mut vertices = None;
    let mut faces = None;
    let mut has = (false, false);
    for (name, def) in &header.elements {
        let ctx = |e: ply_rs_bw::parser::ParseError| err(format!("element '{name}': {e}"));
        match name.as_str() {
            "vertex" => {
                has = (
                    def.properties.contains_key("nx"),
                    ["u", "s", "texture_u", "texture_s"]
                        .iter()
                        .any(|k| def.properties.contains_key(*k)),
                );
                vertices = Some(
                    vparser
                        .read_payload_for_element(&mut reader, def, &header)
                        .map_err(ctx)?,
                );
            }
            "face" => {
                faces = Some(
                    fparser
                        .read_payload_for_element(&mut reader, def, &header)
                        .map_err(ctx)?,
                )
            }
            // Other elements (edges, materials) are read past and ignored.
            _ => {
                Parser::<ply_rs_bw::ply::DefaultElement>::new()
                    .read_payload_for_element(&mut reader, def, &header)
                    .map_err(ctx)?;
            }
        }
    }
    let vertices = vertices.ok_or_else(|| err("no 'vertex' element".into()))?;
    let faces = faces.ok_or_else(|| err("no 'face' element".into()))?;
    let n = vertices.len();
    let finite = |v: &[f32]| v.iter().all(|c| c.is_finite());
    if let Some((i, v)) = vertices
        .iter()
        .enumerate()
        .find(|(_, v)| !finite(&v.p) || (has.0 && !finite(&v.n)))
    {
        let [x, y, z] = if finite(&v.p) { v.n } else { v.p };
        let what = if finite(&v.p) { "normal" } else { "position" };
        return Err(err(format!(
            "vertex {i} of {n}: its {what} ({x}, {y}, {z}) is not finite"
        )));
    }
    let mut indices = Vec::with_capacity(faces.len());
    let mut poly = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        poly.clear();
        for &i in &face.indices {
            if i < 0 || i as usize >= n {
                return Err(err(format!(
                    "face {f} uses vertex {i} but the file has {n} vertices"
                )));
            }
            poly.push(i as u32);
        }
        if poly.len() < 3 {
            return Err(err(format!("face {f} has {} vertices", poly.len())));
        }
        fan(&poly, &mut indices);
    }
    Ok(TriangleMesh {
        positions: vertices.iter().map(|v| Vec3::from(v.p)).collect(),
        normals: has
            .0
            .then(|| vertices.iter().map(|v| Vec3::from(v.n)).collect()),
        uvs: has
            .1
            .then(|| vertices.iter().map(|v| Vec2::from(v.uv)).collect()),
        indices,
    })
}

/// The fewest bytes one element of `def` takes: its scalars and list lengths (one byte each
/// in ASCII), at least one.
fn least_bytes(def: &ElementDef, encoding: Encoding) -> u64 {
    let size = |t: &ScalarType| match (encoding, t) {
        (Encoding::Ascii, _) | (_, ScalarType::Char | ScalarType::UChar) => 1,
        (_, ScalarType::Short | ScalarType::UShort) => 2,
        (_, ScalarType::Int | ScalarType::UInt | ScalarType::Float) => 4,
        (_, ScalarType::Double) => 8,
    };
    let bytes: u64 = def
        .properties
        .values()
        .map(|p| match &p.data_type {
            PropertyType::Scalar(t) | PropertyType::List(t, _) => size(t),
        })
        .sum();
    bytes.max(1)
}

/// Writes `mesh` as binary little-endian PLY (positions, normals and uv when present).
pub fn write(mesh: &TriangleMesh, out: &mut impl Write) -> std::io::Result<()> {
    let float = PropertyType::Scalar(ScalarType::Float);
    let mut vdef = ElementDef::new("vertex".into());
    let mut names = vec!["x", "y", "z"];
    if mesh.normals.is_some() {
        names.extend(["nx", "ny", "nz"]);
    }
    if mesh.uvs.is_some() {
        names.extend(["u", "v"]);
    }
    for n in names {
        vdef.properties
            .add(PropertyDef::new(n.into(), float.clone()));
    }
    vdef.count = mesh.positions.len();
    let mut fdef = ElementDef::new("face".into());
    fdef.properties.add(PropertyDef::new(
        "vertex_indices".into(),
        PropertyType::List(ScalarType::UChar, ScalarType::Int),
    ));
    fdef.count = mesh.indices.len();
    let mut header = Header::new();
    header.encoding = Encoding::BinaryLittleEndian;
    header.elements.add(vdef.clone());
    header.elements.add(fdef.clone());
    let vertices: Vec<Vertex> = (0..mesh.positions.len())
        .map(|i| Vertex {
            p: mesh.positions[i].into(),
            n: mesh.normals.as_ref().map_or([0.0; 3], |n| n[i].into()),
            uv: mesh.uvs.as_ref().map_or([0.0; 2], |t| t[i].into()),
        })
        .collect();
    let faces: Vec<WriteFace> = mesh
        .indices
        .iter()
        .map(|t| WriteFace(t.map(|i| i as i32)))
        .collect();
    let vw = Writer::<Vertex>::new();
    vw.write_header(out, &header)?;
    vw.write_payload_of_element(out, &vertices, &vdef, &header)?;
    Writer::<WriteFace>::new().write_payload_of_element(out, &faces, &fdef, &header)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_quads_are_triangulated_and_binary_round_trips() {
        let dir = std::env::temp_dir().join(format!("fenestra-ply-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let ascii = dir.join("quad.ply");
        std::fs::write(
            &ascii,
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
             property float z\nproperty float u\nproperty float v\nelement face 1\n\
             property list uchar int vertex_indices\nend_header\n\
             0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n",
        )
        .expect("write");
        let m = read(&ascii).expect("read");
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert!(m.normals.is_none());
        assert_eq!(m.uvs.as_ref().map(|u| u[2]), Some(Vec2::new(1.0, 1.0)));

        let bin = dir.join("quad-bin.ply");
        let mut f = std::fs::File::create(&bin).expect("create");
        write(&m, &mut f).expect("write");
        drop(f);
        let back = read(&bin).expect("read binary");
        assert_eq!(back.positions, m.positions);
        assert_eq!(back.indices, m.indices);
        assert_eq!(back.uvs, m.uvs);
        // A coordinate that is not a number is refused with its file and vertex (the scene
        // said only "shape 0: a vertex position is not finite").
        let mut nan = m.clone();
        nan.positions[2].y = f32::NAN;
        let mut f = std::fs::File::create(&bin).expect("create");
        write(&nan, &mut f).expect("write");
        drop(f);
        let e = read(&bin).expect_err("NaN").to_string();
        assert!(
            e.contains("quad-bin.ply: vertex 2 of 4: its position (1, NaN, 0) is not finite"),
            "{e}"
        );
        write(&m, &mut std::fs::File::create(&bin).expect("create")).expect("write");

        // gzip-compressed, whatever the name; a damaged one says it is gzip.
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(&std::fs::read(&bin).expect("bin"))
            .expect("gzip");
        let gz = gz.finish().expect("gzip");
        let packed = dir.join("quad.ply.gz");
        std::fs::write(&packed, &gz).expect("write");
        assert_eq!(read(&packed).expect("read gzip").positions, m.positions);
        std::fs::write(&packed, &gz[..gz.len() / 2]).expect("write");
        let e = read(&packed).expect_err("truncated").to_string();
        assert!(e.contains("gzip-compressed, but"), "{e}");

        std::fs::write(
            &ascii,
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
             property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
             end_header\n0 0 0\n3 0 1 5\n",
        )
        .expect("write");
        let e = read(&ascii).expect_err("index out of range").to_string();
        assert!(
            e.contains("face 0 uses vertex 1 but the file has 1 vertices"),
            "{e}"
        );
        // Counts the file cannot hold are refused before reading (an element without
        // properties took no bytes and grew without end).
        for (element, says) in [
            (
                "element junk 1000000000000\n",
                "element 'junk' claims 1000000000000 entries of at least 1 bytes",
            ),
            (
                "element vertex 100000\nproperty double x\n",
                "element 'vertex' claims 100000 entries of at least 8 bytes",
            ),
        ] {
            std::fs::write(
                &ascii,
                format!("ply\nformat binary_little_endian 1.0\n{element}end_header\n"),
            )
            .expect("write");
            let e = read(&ascii).expect_err(says).to_string();
            assert!(e.contains(says), "{e}");
        }
        std::fs::write(&ascii, b"\x00\xffgarbage").expect("write");
        assert!(read(&ascii).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
