//! Shapes placed by affine transforms, as scene files place them.

use crate::mesh::grid;
use crate::{Shape, ShapeKind, TriangleMesh};
use fenestra_core::{Vec3, PI};
use glam::{DMat3, DMat4, DVec3};

/// A transform that cannot place a shape: singular, or with a coordinate that is not finite.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("transform is singular or not finite")]
pub struct SingularTransform;

/// `shape` moved by `m`. A transform that mirrors flips the orientation of meshes without
/// vertex normals and of spheres and disks (as pbrt-v4 does). Spheres and disks stay analytic
/// under similarity transforms and are tessellated otherwise.
pub fn transformed(shape: &Shape, m: &DMat4) -> Result<Shape, SingularTransform> {
    let linear = DMat3::from_mat4(*m);
    let det = linear.determinant();
    if !(det.is_finite() && det.abs() > 1e-300 && m.is_finite()) {
        return Err(SingularTransform);
    }
    let normal_m = linear.inverse().transpose();
    let pt = |p: Vec3| m.transform_point3(p.as_dvec3()).as_vec3();
    let nrm = |n: Vec3| (normal_m * n.as_dvec3()).normalize_or_zero().as_vec3();
    let mirrored = det < 0.0;
    let mut out = shape.clone();
    out.kind = match &shape.kind {
        ShapeKind::Mesh(mesh) => {
            if mirrored && mesh.normals.is_none() {
                out.flip_normals = !out.flip_normals;
            }
            ShapeKind::Mesh(TriangleMesh {
                positions: mesh.positions.iter().map(|&p| pt(p)).collect(),
                normals: mesh
                    .normals
                    .as_ref()
                    .map(|n| n.iter().map(|&v| nrm(v)).collect()),
                uvs: mesh.uvs.clone(),
                indices: mesh.indices.clone(),
            })
        }
        quadric => {
            let scale = similarity_scale(&linear);
            if mirrored {
                out.flip_normals = !out.flip_normals;
            }
            match (quadric, scale) {
                (ShapeKind::Sphere { center, radius }, Some(s)) => {
                    // The sphere's uv turns with it (spheres are parametrised in object space).
                    let turn = (linear / s).as_mat3();
                    let turn = shape.orientation.map_or(turn, |o| turn * o);
                    out.orientation =
                        (!turn.abs_diff_eq(glam::Mat3::IDENTITY, 1e-6)).then_some(turn);
                    ShapeKind::Sphere {
                        center: pt(*center),
                        radius: radius * s as f32,
                    }
                }
                (
                    ShapeKind::Disk {
                        center,
                        normal,
                        radius,
                    },
                    Some(s),
                ) => ShapeKind::Disk {
                    center: pt(*center),
                    normal: nrm(*normal),
                    radius: radius * s as f32,
                },
                (q, _) => {
                    // Outward vertex normals give the side; flip_normals still applies.
                    let mut mesh = tessellate(q);
                    mesh.positions.iter_mut().for_each(|p| *p = pt(*p));
                    if let Some(n) = mesh.normals.as_mut() {
                        n.iter_mut().for_each(|v| *v = nrm(*v));
                    }
                    ShapeKind::Mesh(mesh)
                }
            }
        }
    };
    Ok(out)
}

/// The uniform scale factor of `l` if it is a rotation times a uniform scale (possibly
/// mirrored), `None` otherwise.
fn similarity_scale(l: &DMat3) -> Option<f64> {
    let cols = [l.x_axis, l.y_axis, l.z_axis];
    let s = cols[0].length();
    let tol = 1e-5 * s;
    let ortho = |a: DVec3, b: DVec3| a.dot(b).abs() <= tol * s;
    let same = cols.iter().all(|c| (c.length() - s).abs() <= tol);
    (same && ortho(cols[0], cols[1]) && ortho(cols[0], cols[2]) && ortho(cols[1], cols[2]))
        .then_some(s)
}

/// A sphere or disk as a triangle mesh with outward normals, for non-uniform transforms.
fn tessellate(kind: &ShapeKind) -> TriangleMesh {
    let (segments, rings) = (96, 48);
    let (mut mesh, normal): (TriangleMesh, Box<dyn Fn(Vec3) -> Vec3>) = match *kind {
        ShapeKind::Sphere { center, radius } => (
            grid(segments, rings, true, |s, t| {
                let (phi, theta) = (2.0 * PI * s, PI * t);
                center
                    + Vec3::new(
                        theta.sin() * phi.cos(),
                        theta.sin() * phi.sin(),
                        theta.cos(),
                    ) * radius
            }),
            Box::new(move |p: Vec3| (p - center).normalize_or(Vec3::Z)),
        ),
        ShapeKind::Disk {
            center,
            normal,
            radius,
        } => {
            let f = fenestra_core::Frame::from_normal(normal);
            (
                grid(segments, rings, true, |s, t| {
                    let phi = 2.0 * PI * s;
                    center + (f.s * phi.cos() + f.t * phi.sin()) * ((1.0 - t) * radius)
                }),
                Box::new(move |_| normal),
            )
        }
        ShapeKind::Mesh(ref m) => return m.clone(),
    };
    mesh.normals = Some(mesh.positions.iter().map(|&p| normal(p)).collect());
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn similarity_keeps_spheres_analytic_and_stretch_tessellates() {
        let s = Shape::new(
            ShapeKind::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
            0,
        );
        let m = DMat4::from_translation(DVec3::new(1.0, 2.0, 3.0))
            * DMat4::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 0.7)
            * DMat4::from_scale(DVec3::splat(2.0));
        let t = transformed(&s, &m).expect("transform");
        assert!(
            matches!(t.kind, ShapeKind::Sphere { radius, center } if (radius - 2.0).abs() < 1e-5 && (center - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-5)
        );
        let stretched =
            transformed(&s, &DMat4::from_scale(DVec3::new(1.0, 1.0, 3.0))).expect("transform");
        let ShapeKind::Mesh(mesh) = &stretched.kind else {
            panic!("tessellated")
        };
        let top = mesh.positions.iter().map(|p| p.z).fold(f32::MIN, f32::max);
        assert!((top - 3.0).abs() < 1e-4);
        assert!(transformed(&s, &DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0))).is_err());
    }
}
