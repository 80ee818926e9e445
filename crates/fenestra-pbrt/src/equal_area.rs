//! pbrt-v4's environment map layout, Clarberg's equal-area octahedral mapping of the sphere
//! to a square, and resampling between it and fenestra's latitude-longitude layout (the
//! reader turns pbrt-v4's square maps into latitude-longitude, the exporter the other way).

use fenestra_core::image::Image;
use fenestra_core::Rgb;
use glam::DVec3;
use std::f64::consts::PI;

/// Clarberg's equal-area octahedral mapping of the unit sphere to [0,1]^2 (pbrt-v4's
/// environment map layout).
pub fn sphere_to_square(d: DVec3) -> (f64, f64) {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    let a = x.max(y);
    let b = if a == 0.0 { 0.0 } else { x.min(y) / a };
    let mut phi = b.atan() * 2.0 / std::f64::consts::PI;
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        std::mem::swap(&mut u, &mut v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    ((u.copysign(d.x) + 1.0) * 0.5, (v.copysign(d.y) + 1.0) * 0.5)
}

/// The unit direction at polar angle `theta` from +z and azimuth `phi` from +x.
pub(crate) fn spherical(theta: f64, phi: f64) -> DVec3 {
    DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// Resamples an equal-area square map (side N) to latitude-longitude (2N x N), bilinearly.
pub fn equal_area_to_latlong(sq: &Image) -> Image {
    let n = sq.width;
    let (w, h) = (2 * n, n);
    let mut out = Image::new(w, h);
    for row in 0..h {
        let theta = std::f64::consts::PI * (row as f64 + 0.5) / h as f64;
        for col in 0..w {
            let phi = 2.0 * std::f64::consts::PI * (col as f64 + 0.5) / w as f64;
            let (u, v) = sphere_to_square(spherical(theta, phi));
            let (x, y) = (u * n as f64 - 0.5, v * n as f64 - 0.5);
            let (x0, y0) = (x.floor(), y.floor());
            let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
            let at = |dx: f64, dy: f64| {
                let cx = (x0 + dx).clamp(0.0, (n - 1) as f64) as usize;
                let cy = (y0 + dy).clamp(0.0, (n - 1) as f64) as usize;
                sq.get(cx, cy)
            };
            let c = at(0.0, 0.0) * ((1.0 - fx) * (1.0 - fy))
                + at(1.0, 0.0) * (fx * (1.0 - fy))
                + at(0.0, 1.0) * ((1.0 - fx) * fy)
                + at(1.0, 1.0) * (fx * fy);
            out.set(col, row, c);
        }
    }
    out
}

/// The inverse of [`sphere_to_square`]: the unit direction at (u, v) in [0, 1]^2.
pub fn square_to_sphere(u: f64, v: f64) -> DVec3 {
    let (u, v) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    let (up, vp) = (u.abs(), v.abs());
    let signed = 1.0 - (up + vp);
    let r = 1.0 - signed.abs();
    let phi = if r == 0.0 { 1.0 } else { (vp - up) / r + 1.0 } * PI / 4.0;
    let z = (1.0 - r * r).copysign(signed);
    let s = r * (2.0 - r * r).max(0.0).sqrt();
    DVec3::new(phi.cos().copysign(u) * s, phi.sin().copysign(v) * s, z)
}

/// Resamples a latitude-longitude map (2N x N; column 0 at phi = 0, row 0 at +z) to an
/// equal-area square of side N, bilinearly (pbrt-v4 reads no other layout).
pub fn latlong_to_equal_area(ll: &Image) -> Image {
    let n = ll.height;
    let (w, h) = (ll.width as f64, ll.height as f64);
    let mut out = Image::new(n, n);
    for y in 0..n {
        for x in 0..n {
            let d = square_to_sphere((x as f64 + 0.5) / n as f64, (y as f64 + 0.5) / n as f64);
            let theta = d.z.clamp(-1.0, 1.0).acos();
            let phi = d.y.atan2(d.x).rem_euclid(2.0 * PI);
            let (s, t) = (phi / (2.0 * PI) * w - 0.5, theta / PI * h - 0.5);
            let (s0, t0) = (s.floor(), t.floor());
            let (fs, ft) = ((s - s0) as f32, (t - t0) as f32);
            let at = |ds: f64, dt: f64| {
                let cx = (s0 + ds).rem_euclid(w) as usize;
                let cy = (t0 + dt).clamp(0.0, h - 1.0) as usize;
                ll.get(cx.min(ll.width - 1), cy)
            };
            let c: Rgb = at(0.0, 0.0) * ((1.0 - fs) * (1.0 - ft))
                + at(1.0, 0.0) * (fs * (1.0 - ft))
                + at(0.0, 1.0) * ((1.0 - fs) * ft)
                + at(1.0, 1.0) * (fs * ft);
            out.set(x, y, c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_area_mapping_is_equal_area() {
        // Directions on a fine latitude-longitude grid, weighted by solid angle, must cover
        // the square's 4x4 cells evenly.
        let mut cells = [0.0f64; 16];
        let (nt, np) = (400, 800);
        for i in 0..nt {
            let theta = std::f64::consts::PI * (i as f64 + 0.5) / nt as f64;
            for j in 0..np {
                let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / np as f64;
                let (u, v) = sphere_to_square(spherical(theta, phi));
                assert!((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v));
                let c = ((u * 4.0).min(3.0) as usize) + 4 * ((v * 4.0).min(3.0) as usize);
                cells[c] += theta.sin();
            }
        }
        let total: f64 = cells.iter().sum();
        for c in cells {
            assert!((c / total - 1.0 / 16.0).abs() < 2e-3, "{cells:?}");
        }
        // +z maps to the centre, -z to the corners.
        let (u, v) = sphere_to_square(DVec3::Z);
        assert!((u - 0.5).abs() < 1e-12 && (v - 0.5).abs() < 1e-12);
    }

    #[test]
    fn square_to_sphere_inverts_sphere_to_square() {
        for i in 0..64 {
            for j in 0..64 {
                let (u, v) = ((i as f64 + 0.5) / 64.0, (j as f64 + 0.5) / 64.0);
                let d = square_to_sphere(u, v);
                assert!((d.length() - 1.0).abs() < 1e-9, "{d}");
                let (a, b) = sphere_to_square(d);
                assert!(
                    (a - u).abs() < 1e-9 && (b - v).abs() < 1e-9,
                    "({u}, {v}) -> {d} -> ({a}, {b})"
                );
            }
        }
    }

    #[test]
    fn a_smooth_map_survives_the_round_trip() {
        // A map varying smoothly with direction: to equal-area and back (bilinear resampling
        // twice), every texel stays within 2.5% (the worst near -z, where the square's corners
        // meet and lookups clamp) and the mean within 0.2%.
        let (w, h) = (128, 64);
        let mut ll = Image::new(w, h);
        for y in 0..h {
            let theta = PI * (y as f64 + 0.5) / h as f64;
            for x in 0..w {
                let phi = 2.0 * PI * (x as f64 + 0.5) / w as f64;
                let d = spherical(theta, phi);
                ll.set(
                    x,
                    y,
                    Rgb::new((2.0 + d.x) as f32, (2.0 + d.y) as f32, (2.0 + d.z) as f32),
                );
            }
        }
        let back = equal_area_to_latlong(&latlong_to_equal_area(&ll));
        assert_eq!((back.width, back.height), (w, h));
        for (a, b) in ll.pixels.iter().zip(&back.pixels) {
            let err = (*a - *b).max_component().max((*b - *a).max_component());
            assert!(err < 0.05, "{a:?} {b:?}");
        }
        let (m, n) = (ll.mean(), back.mean());
        assert!((m.b - n.b).abs() < 2e-3 * m.b, "{m:?} {n:?}");
    }
}
