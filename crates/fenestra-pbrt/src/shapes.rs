//! pbrt-v4 shapes: trianglemesh, plymesh, bilinearmesh, loopsubdiv, sphere and disk, built in object space
//! and moved to the world by the current transform.

use crate::builder::{place, Builder};
use crate::parser::Directive;
use crate::{Loc, PbrtError, Topic};
use fenestra_core::{Vec2, Vec3};
use fenestra_scene::light::Emission;
use fenestra_scene::mesh::grid;
use fenestra_scene::{Shape, ShapeKind, TriangleMesh};
use std::path::Path;

/// Bilinear patches that are not planar are split into this many quads per side.
const BILINEAR_SPLITS: usize = 8;

/// The most levels of Loop subdivision a scene may ask for.
const MAX_SUBDIVISION_LEVELS: i64 = 8;

/// The most triangles one subdivision surface may become (about 3 GB of mesh).
const MAX_SUBDIVIDED_TRIANGLES: u64 = 1 << 27;

impl Builder {
    pub(super) fn shape(&mut self, d: &Directive, dir: &Path) -> Result<(), PbrtError> {
        let p = &d.params;
        if self.gs.material == crate::materials::INTERFACE {
            // Invisible to light in pbrt-v4 as well: nothing to render. A four-vertex
            // trianglemesh forming a parallelogram marks a light portal (what
            // `fenestra portals --export F.pbrt` writes for rectangles).
            if d.str(0) == "trianglemesh" && self.object.is_none() {
                let mesh = triangle_mesh(d)?;
                let shape = place(&Shape::new(ShapeKind::Mesh(mesh), 0), &self.gs.ctm, &d.loc)?;
                if let ShapeKind::Mesh(m) = &shape.kind {
                    if let [a, b, c, e] = m.positions[..] {
                        let size = (b - a).length() + (e - a).length();
                        if (a + c - b - e).length() <= 1e-4 * size && size > 0.0 {
                            self.portals.push([a, b, c, e]);
                        }
                    }
                }
            }
            p.use_all();
            return Ok(());
        }
        let reverse = self.gs.reverse;
        let kind = match d.str(0) {
            "trianglemesh" => {
                let mesh = triangle_mesh(d)?;
                ShapeKind::Mesh(mesh)
            }
            "plymesh" => {
                let Some(file) = p.string("filename")? else {
                    return Err(PbrtError::at(&d.loc, "plymesh needs \"string filename\""));
                };
                if p.has("displacement") {
                    self.warn(Topic::Geometry, "plymesh displacement", &d.loc);
                    p.use_all();
                }
                let path = dir.join(&file);
                let mesh = fenestra_scene::mesh::ply::read(&path)
                    .map_err(|e| PbrtError::at(&d.loc, e.to_string()))?;
                self.files.push(path);
                ShapeKind::Mesh(mesh)
            }
            "bilinearmesh" => ShapeKind::Mesh(bilinear_mesh(d)?),
            "loopsubdiv" => {
                self.note(
                    Topic::Geometry,
                    "loopsubdiv shading normals from the limit mesh's faces (pbrt-v4 uses the limit surface's tangents)",
                    &d.loc,
                );
                ShapeKind::Mesh(loop_subdivision(d)?)
            }
            "sphere" => {
                let radius = p.float("radius", 1.0)?;
                let (zmin, zmax, phimax) = (
                    p.float("zmin", -radius)?,
                    p.float("zmax", radius)?,
                    p.float("phimax", 360.0)?,
                );
                if zmin > -radius || zmax < radius || phimax < 360.0 {
                    self.warn(
                        Topic::Geometry,
                        "partial sphere (zmin, zmax, phimax; the full sphere is used)",
                        &d.loc,
                    );
                }
                positive_size(radius, "sphere radius", &d.loc)?;
                ShapeKind::Sphere {
                    center: Vec3::ZERO,
                    radius,
                }
            }
            "disk" => {
                let radius = p.float("radius", 1.0)?;
                positive_size(radius, "disk radius", &d.loc)?;
                if p.float("innerradius", 0.0)? > 0.0 || p.float("phimax", 360.0)? < 360.0 {
                    self.warn(
                        Topic::Geometry,
                        "partial disk (innerradius, phimax; the full disk is used)",
                        &d.loc,
                    );
                }
                ShapeKind::Disk {
                    center: Vec3::new(0.0, 0.0, p.float("height", 0.0)?),
                    normal: Vec3::Z,
                    radius,
                }
            }
            other => {
                self.warn(
                    Topic::Geometry,
                    format!("Shape \"{other}\" (skipped)"),
                    &d.loc,
                );
                p.use_all();
                return Ok(());
            }
        };
        // pbrt-v4: a mesh with vertex normals takes its orientation from them alone.
        let has_normals = matches!(&kind, ShapeKind::Mesh(m) if m.normals.is_some());
        let mut shape = Shape::new(kind, self.gs.material);
        shape.flip_normals = reverse && !has_normals;
        shape.relief = self.reliefs.get(&self.gs.material).cloned();
        let mut shape = place(&shape, &self.gs.ctm, &d.loc)?;
        if let Some(area) = self.gs.area.clone() {
            if self.object.is_some() {
                self.warn(
                    Topic::Lights,
                    "area lights inside object instances (emission dropped)",
                    &d.loc,
                );
            } else {
                let a = shape.area();
                if !(a > 0.0) {
                    return Err(PbrtError::at(&d.loc, "an area light shape has zero area"));
                }
                let Some(power) = area.power else {
                    shape.emission = Some(Emission {
                        radiance: area.radiance,
                        two_sided: area.two_sided,
                    });
                    return self.add_shape(shape, &d.loc);
                };
                if !(area.radiance.luminance() > 0.0) {
                    return Err(PbrtError::at(
                        &d.loc,
                        "area light \"power\" needs a radiance with positive luminance",
                    ));
                }
                // pbrt-v4 makes each triangle of a mesh a light of its own and gives each the
                // whole power (its "power" is per shape, and a triangle is a shape there).
                for (mut part, a) in per_triangle(shape) {
                    part.emission = Some(Emission::from_power(
                        area.radiance * power,
                        a,
                        area.two_sided,
                    ));
                    self.add_shape(part, &d.loc)?;
                }
                return Ok(());
            }
        }
        self.add_shape(shape, &d.loc)
    }
}

fn positive_size(v: f32, what: &str, loc: &Loc) -> Result<(), PbrtError> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(PbrtError::at(
            loc,
            format!("{what} must be positive, found {v}"),
        ))
    }
}

/// Checks indices against the vertex count and groups them by `n`.
fn indices<const N: usize>(
    d: &Directive,
    vertices: usize,
    what: &str,
) -> Result<Vec<[u32; N]>, PbrtError> {
    let (idx, loc) = match d.params.ints("indices")? {
        Some(i) => i,
        None if vertices == N => ((0..N as i64).collect(), d.loc.clone()),
        None => {
            return Err(PbrtError::at(
                &d.loc,
                format!("{what} needs \"integer indices\" (it has {vertices} vertices)"),
            ))
        }
    };
    if idx.len() % N != 0 {
        return Err(PbrtError::at(
            &loc,
            format!(
                "{what} indices: {} values is not a multiple of {N}",
                idx.len()
            ),
        ));
    }
    if let Some(bad) = idx.iter().find(|&&i| i < 0 || i as usize >= vertices) {
        return Err(PbrtError::at(
            &loc,
            format!("{what} index {bad} is out of range ({vertices} vertices)"),
        ));
    }
    Ok(idx
        .chunks_exact(N)
        .map(|c| std::array::from_fn(|k| c[k] as u32))
        .collect())
}

/// Vertex attributes P, N and uv, with their counts checked against P.
fn attributes(
    d: &Directive,
    what: &str,
) -> Result<(Vec<Vec3>, Option<Vec<Vec3>>, Option<Vec<Vec2>>), PbrtError> {
    let p = &d.params;
    let Some(positions) = p.point3s("P")? else {
        return Err(PbrtError::at(&d.loc, format!("{what} needs \"point3 P\"")));
    };
    let n = positions.len();
    let normals = p.normals("N")?;
    let uvs = p.point2s("uv")?;
    let check = |len: Option<usize>, name: &str| match len {
        Some(l) if l != n => Err(PbrtError::at(
            &d.loc,
            format!("{what}: {l} values of \"{name}\" for {n} vertices"),
        )),
        _ => Ok(()),
    };
    check(normals.as_ref().map(Vec::len), "N")?;
    check(uvs.as_ref().map(Vec::len), "uv")?;
    Ok((positions, normals, uvs))
}

fn triangle_mesh(d: &Directive) -> Result<TriangleMesh, PbrtError> {
    let (positions, normals, uvs) = attributes(d, "trianglemesh")?;
    let indices = indices::<3>(d, positions.len(), "trianglemesh")?;
    Ok(TriangleMesh {
        positions,
        normals,
        uvs,
        indices,
    })
}

/// pbrt-v4's "loopsubdiv": P and indices subdivided "levels" times (default 3, at most
/// [`MAX_SUBDIVISION_LEVELS`]) and moved to the limit surface.
fn loop_subdivision(d: &Directive) -> Result<TriangleMesh, PbrtError> {
    let p = &d.params;
    let Some(positions) = p.point3s("P")? else {
        return Err(PbrtError::at(&d.loc, "loopsubdiv needs \"point3 P\""));
    };
    let indices = indices::<3>(d, positions.len(), "loopsubdiv")?;
    let levels = p.int("levels", 3)?;
    // Each level quadruples the triangles: 4^8 = 65,536 per control triangle.
    if !(0..=MAX_SUBDIVISION_LEVELS).contains(&levels) {
        return Err(PbrtError::at(
            &d.loc,
            format!("loopsubdiv \"levels\" must be 0 to {MAX_SUBDIVISION_LEVELS}, found {levels}"),
        ));
    }
    let triangles = (indices.len() as u64) << (2 * levels);
    if triangles > MAX_SUBDIVIDED_TRIANGLES {
        return Err(PbrtError::at(
            &d.loc,
            format!("loopsubdiv would make {triangles} triangles (at most {MAX_SUBDIVIDED_TRIANGLES}): use fewer levels"),
        ));
    }
    Ok(fenestra_scene::mesh::subdivide::loop_subdivide(
        &positions,
        &indices,
        levels as u32,
    ))
}

/// Bilinear patches (p00, p10, p01, p11) as triangles: two per planar patch, a grid of
/// bilinearly interpolated points otherwise.
fn bilinear_mesh(d: &Directive) -> Result<TriangleMesh, PbrtError> {
    let (positions, normals, uvs) = attributes(d, "bilinearmesh")?;
    let patches = indices::<4>(d, positions.len(), "bilinearmesh")?;
    let mut mesh = TriangleMesh {
        normals: normals.as_ref().map(|_| Vec::new()),
        uvs: Some(Vec::new()),
        ..TriangleMesh::default()
    };
    for q in patches {
        let [a, b, c, e] = q.map(|i| i as usize);
        let planar = {
            let n = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
            let scale =
                (positions[b] - positions[a]).length() + (positions[c] - positions[a]).length();
            (positions[e] - positions[a])
                .dot(n.normalize_or_zero())
                .abs()
                <= 1e-6 * scale
        };
        let k = if planar { 1 } else { BILINEAR_SPLITS };
        let weights = |u: f32, v: f32| [(1.0 - u) * (1.0 - v), u * (1.0 - v), (1.0 - u) * v, u * v];
        let mix3 = |x: &[Vec3], w: [f32; 4]| x[a] * w[0] + x[b] * w[1] + x[c] * w[2] + x[e] * w[3];
        // The grid's uv are the patch parameters (u, v); the patch's own attributes follow.
        let mut patch = grid(k, k, false, |u, v| mix3(&positions, weights(u, v)));
        let params = patch.uvs.take().unwrap_or_default();
        patch.normals = normals.as_ref().map(|n| {
            params
                .iter()
                .map(|p| mix3(n, weights(p.x, p.y)).normalize_or_zero())
                .collect()
        });
        patch.uvs = Some(match &uvs {
            Some(t) => params
                .iter()
                .map(|p| {
                    let w = weights(p.x, p.y);
                    t[a] * w[0] + t[b] * w[1] + t[c] * w[2] + t[e] * w[3]
                })
                .collect(),
            None => params,
        });
        mesh.append(&patch);
    }
    Ok(mesh)
}

/// The shapes pbrt-v4 makes emitters of, each with the area its power is spread over: a
/// mesh's triangles (kept as one shape when they all have the same area, so that one radiance
/// serves them all; degenerate ones dropped), any other shape as it is. The mesh has a
/// positive area (checked before).
fn per_triangle(shape: Shape) -> Vec<(Shape, f32)> {
    let ShapeKind::Mesh(m) = &shape.kind else {
        let a = shape.area();
        return vec![(shape, a)];
    };
    let first = m.triangle_area(0);
    if (1..m.indices.len()).all(|i| (m.triangle_area(i) - first).abs() <= 1e-4 * first) {
        return vec![(shape, first)];
    }
    // Degenerate triangles emit nothing (their radiance would be infinite).
    (0..m.indices.len())
        .filter(|&i| m.triangle_area(i) > 0.0)
        .map(|i| {
            let part = Shape {
                kind: ShapeKind::Mesh(m.triangle_mesh(i)),
                ..shape.clone()
            };
            (part, m.triangle_area(i))
        })
        .collect()
}
