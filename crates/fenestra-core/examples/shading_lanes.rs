//! What SIMD shading could buy the path loop: two of af_hf's shading kernels (a diffuse
//! BSDF sample in world space; a point, direction and density on a triangle light) timed
//! three ways over the same inputs:
//!
//! - chained: each sample waits for the one before, as one path's vertices wait for each
//!   other in the renderer (the latency of the kernel's dependent divisions and roots);
//! - independent: the same scalar code over independent samples, which the CPU overlaps
//!   (what interleaving the lanes of a wave would give without SIMD);
//! - eight lanes: the kernel over eight samples at a time in a form the compiler
//!   vectorises, built for the portable target and for AVX2 (chosen at run time).
//!
//! cargo run --release -p fenestra-core --example shading_lanes

use fenestra_core::trig::sin_cos_quarter;
use fenestra_core::{warp, Frame};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, FRAC_PI_4};
use std::hint::black_box;
use std::time::Instant;

/// Samples per timed run.
const N: usize = 1 << 20;
/// Runs per variant; the fastest counts.
const RUNS: usize = 15;
const LANES: usize = 8;
/// Three and two coordinates of eight lanes.
type Lanes3 = [[f32; LANES]; 3];
type Lanes2 = [[f32; LANES]; 2];

/// Unit normals (or points) and 2D sample values, as structure of arrays.
struct Inputs {
    n: [Vec<f32>; 3],
    u: [Vec<f32>; 2],
}

impl Inputs {
    fn new() -> Self {
        let mut rng = fenestra_core::Rng::new(1);
        let mut inputs = Inputs {
            n: [vec![], vec![], vec![]],
            u: [vec![], vec![]],
        };
        for _ in 0..N {
            let n = warp::square_to_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            for (c, v) in inputs.n.iter_mut().zip(n.to_array()) {
                c.push(v);
            }
            for c in &mut inputs.u {
                c.push(rng.next_f32());
            }
        }
        inputs
    }

    fn normal(&self, i: usize) -> Vec3 {
        Vec3::new(self.n[0][i], self.n[1][i], self.n[2][i])
    }

    fn u(&self, i: usize) -> Vec2 {
        Vec2::new(self.u[0][i], self.u[1][i])
    }

    /// Lanes `base..base + 8` of each array.
    fn lanes(&self, base: usize) -> (Lanes3, Lanes2) {
        let at = |v: &Vec<f32>| -> [f32; LANES] {
            v[base..base + LANES].try_into().expect("eight lanes")
        };
        (self.n.each_ref().map(at), self.u.each_ref().map(at))
    }
}

/// A diffuse sample as the renderer takes it: frame, cosine hemisphere, to world, density.
fn diffuse(n: Vec3, u: Vec2) -> f32 {
    let w = warp::square_to_cosine_hemisphere(u);
    let wi = Frame::from_normal(n).to_world(w);
    wi.element_sum() + warp::cosine_hemisphere_pdf(w)
}

/// The triangle light (a corner, two edges, facing down) the light kernel samples.
const LIGHT: (Vec3, Vec3, Vec3) = (
    Vec3::new(-0.5, -0.5, 2.0),
    Vec3::new(1.0, 0.0, 0.0),
    Vec3::new(0.0, 1.0, 0.0),
);

/// A light sample as the renderer takes it: a point, the direction and distance to it, and
/// its solid-angle density.
fn light(x: Vec3, u: Vec2) -> f32 {
    let (corner, e1, e2) = LIGHT;
    let b = warp::square_to_triangle(u);
    let d = corner + e1 * b.x + e2 * b.y - x;
    let d2 = d.length_squared();
    let dist = d2.sqrt();
    let wi = d / dist;
    let cos = wi.z;
    let pdf = if cos > 0.0 { d2 / (0.5 * cos) } else { 0.0 };
    wi.element_sum() + pdf + dist
}

/// [`diffuse`] of eight lanes, written lane by lane without branches.
#[inline(always)]
fn diffuse_lanes(n: Lanes3, u: Lanes2) -> [f32; LANES] {
    let mut out = [0.0; LANES];
    for (k, out) in out.iter_mut().enumerate() {
        let (nx, ny, nz) = (n[0][k], n[1][k], n[2][k]);
        let sign = if nz < 0.0 { -1.0 } else { 1.0 };
        let a = -1.0 / (sign + nz);
        let b = nx * ny * a;
        let s = [1.0 + sign * nx * nx * a, sign * b, -sign * nx];
        let t = [b, sign + ny * ny * a, -ny];
        let (ox, oy) = (2.0 * u[0][k] - 1.0, 2.0 * u[1][k] - 1.0);
        let x_major = ox.abs() > oy.abs();
        let (minor, major) = if x_major { (oy, ox) } else { (ox, oy) };
        let ratio = minor / if major == 0.0 { 1.0 } else { major };
        let (sin, cos) = sin_cos_quarter(FRAC_PI_4 * ratio);
        let (dx, dy) = if x_major { (cos, sin) } else { (sin, cos) };
        let (dx, dy) = (major * dx, major * dy);
        let z = (1.0 - dx * dx - dy * dy).max(0.0).sqrt();
        let wx = s[0] * dx + t[0] * dy + nx * z;
        let wy = s[1] * dx + t[1] * dy + ny * z;
        let wz = s[2] * dx + t[2] * dy + nz * z;
        let pdf = if z > 0.0 { z * FRAC_1_PI } else { 0.0 };
        *out = wx + wy + wz + pdf;
    }
    out
}

/// [`light`] of eight lanes, written lane by lane without branches.
#[inline(always)]
fn light_lanes(x: Lanes3, u: Lanes2) -> [f32; LANES] {
    let (corner, e1, e2) = LIGHT;
    let mut out = [0.0; LANES];
    for (k, out) in out.iter_mut().enumerate() {
        let (u0, u1) = (u[0][k], u[1][k]);
        let first = u0 < u1;
        let b0 = if first { u0 / 2.0 } else { u0 - u1 / 2.0 };
        let b1 = if first { u1 - u0 / 2.0 } else { u1 / 2.0 };
        // max and min, not clamp: clamp's check of its bounds keeps the loop scalar.
        #[allow(clippy::manual_clamp)]
        let b0 = b0.max(0.0).min(1.0);
        let b1 = b1.max(0.0).min(1.0 - b0);
        let p = corner + e1 * b0 + e2 * b1;
        let d = [p.x - x[0][k], p.y - x[1][k], p.z - x[2][k]];
        let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let dist = d2.sqrt();
        let inv = 1.0 / dist;
        let cos = d[2] * inv;
        let pdf = if cos > 0.0 { d2 / (0.5 * cos) } else { 0.0 };
        *out = (d[0] + d[1] + d[2]) * inv + pdf + dist;
    }
    out
}

fn chained(f: impl Fn(Vec3, Vec2) -> f32, inputs: &Inputs, out: &mut [f32]) {
    let mut last = 0.0;
    for (i, o) in out.iter_mut().enumerate() {
        // A negligible dependence on the previous sample's result.
        let n = inputs.normal(i) + Vec3::X * (last * 1e-30);
        last = f(n, inputs.u(i));
        *o = last;
    }
}

fn independent(f: impl Fn(Vec3, Vec2) -> f32, inputs: &Inputs, out: &mut [f32]) {
    for (i, o) in out.iter_mut().enumerate() {
        *o = f(inputs.normal(i), inputs.u(i));
    }
}

#[inline(always)]
fn in_lanes(f: impl Fn(Lanes3, Lanes2) -> [f32; LANES], inputs: &Inputs, out: &mut [f32]) {
    for (base, o) in (0..N).step_by(LANES).zip(out.chunks_exact_mut(LANES)) {
        let (n, u) = inputs.lanes(base);
        o.copy_from_slice(&f(n, u));
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn in_lanes_avx2(f: impl Fn(Lanes3, Lanes2) -> [f32; LANES], inputs: &Inputs, out: &mut [f32]) {
    in_lanes(f, inputs, out)
}

/// [`in_lanes`] built for AVX2, timed, where the CPU has it.
fn time_avx2(f: impl Fn(Lanes3, Lanes2) -> [f32; LANES] + Copy, inputs: &Inputs) -> Option<f64> {
    #[cfg(target_arch = "x86_64")]
    if is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX2 and FMA (checked here).
        return Some(time(&|i, o| unsafe { in_lanes_avx2(f, i, o) }, inputs).0);
    }
    let _ = (f, inputs);
    None
}

/// Nanoseconds per sample of the fastest of [`RUNS`] runs, and the results' sum.
fn time(run: &dyn Fn(&Inputs, &mut [f32]), inputs: &Inputs) -> (f64, f64) {
    let mut out = vec![0.0; N];
    let mut best = f64::INFINITY;
    for _ in 0..RUNS {
        let t = Instant::now();
        run(black_box(inputs), black_box(&mut out));
        best = best.min(t.elapsed().as_secs_f64());
    }
    let sum = out.iter().map(|&v| v as f64).sum();
    (best * 1e9 / N as f64, sum)
}

fn main() {
    let inputs = Inputs::new();
    println!("| kernel | chained ns | independent ns | 8 lanes ns | 8 lanes, AVX2 ns |");
    println!("|---|---|---|---|---|");
    report("diffuse sample", diffuse, diffuse_lanes, &inputs);
    report("triangle light sample", light, light_lanes, &inputs);
}

/// One row of the table: `scalar` chained and independent, `lanes` portable and for AVX2.
fn report(
    name: &str,
    scalar: impl Fn(Vec3, Vec2) -> f32 + Copy,
    lanes: impl Fn(Lanes3, Lanes2) -> [f32; LANES] + Copy,
    inputs: &Inputs,
) {
    let (c, sum) = time(&|i, o| chained(scalar, i, o), inputs);
    let (s, _) = time(&|i, o| independent(scalar, i, o), inputs);
    let (l, lane_sum) = time(&|i, o| in_lanes(lanes, i, o), inputs);
    let relative = ((lane_sum - sum) / sum).abs();
    assert!(
        relative < 1e-4,
        "{name}: lanes disagree with scalar ({relative})"
    );
    let wide = time_avx2(lanes, inputs).map_or("-".into(), |w| format!("{w:.2}"));
    println!("| {name} | {c:.2} | {s:.2} | {l:.2} | {wide} |");
}
