//! The photon map for the light beyond a record's rays (seed 003 §2.5: "the first bounce was
//! computed using the compared algorithms while photon mapping was used for the higher
//! recursion levels"; Jensen 2001's global photon map with final gathering): photons traced
//! from the lights by power and stored where they land on diffuse surfaces after at least one
//! bounce (direct light stays with next-event estimation); a record ray's hit on a diffuse
//! surface takes its indirect light from the k nearest photons (radiance estimate
//! rho / pi * sum power / (pi r^2)) instead of a path.
//!
//! Photons sit in a hashed grid of cells twice the largest gather radius wide, so a query
//! reads 8 cells; the k nearest are selected in a scratch buffer the caller keeps (no
//! allocation per query). Path lengths stay those of af_hf: a photon that took `m` segments
//! serves a point reached by `s` only if `s + m` is within the path-length limit.

use fenestra_core::distribution::Distribution1D;
use fenestra_core::ray::{offset_distance, offset_origin};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Ray, Rgb, Sampler, Vec3};
use fenestra_render::bsdf::Bsdf;
use fenestra_render::integrator::{Gather, Shading};
use fenestra_render::RenderScene;
use rayon::prelude::*;

/// Seed of the photons' sample streams (xor-ed with the render's seed).
const PHOTONS: u64 = 0x5d5c_0006;
/// Photons traced per parallel task.
const CHUNK: u32 = 4096;

/// A photon where it landed.
#[derive(Clone, Copy, Debug)]
struct Photon {
    p: Vec3,
    /// The surface's geometric normal on the side the photon arrived from.
    n: Vec3,
    /// Power (over the number of photons emitted).
    power: Rgb,
    /// Segments of its path from the light.
    segments: u32,
}

/// Photons in a hashed grid.
#[derive(Debug)]
pub struct PhotonMap {
    photons: Vec<Photon>,
    /// Photons of hash bucket b: `photons[start[b]..start[b + 1]]`.
    start: Vec<u32>,
    cell: f32,
    radius: f32,
    k: usize,
    max_depth: u32,
    /// Photons emitted.
    pub emitted: u64,
    /// Rays traced to emit and scatter them.
    pub rays: u64,
}

impl PhotonMap {
    /// Traces `count` photons from the lights of `scene` (picked by power) for paths of at
    /// most `max_depth` segments; lookups gather the `k` nearest within `radius`.
    pub fn trace(
        scene: &RenderScene,
        count: u32,
        k: usize,
        radius: f32,
        max_depth: u32,
        seed: u64,
    ) -> Self {
        let powers: Vec<f32> = (scene.lights.lights.iter())
            .map(|l| l.power(&scene.scene))
            .collect();
        let mut map = PhotonMap::from_photons(Vec::new(), k, radius, max_depth);
        map.emitted = count as u64;
        if powers.iter().sum::<f32>() <= 0.0 || count == 0 || max_depth < 3 {
            return map;
        }
        let pick = Distribution1D::new(&powers);
        let chunks: Vec<(Vec<Photon>, u64)> = (0..count.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut out = Vec::new();
                let mut rays = 0;
                for i in c * CHUNK..((c + 1) * CHUNK).min(count) {
                    rays += map.photon(scene, &pick, i, seed, &mut out);
                }
                (out, rays)
            })
            .collect();
        let mut photons = Vec::new();
        for (mut c, rays) in chunks {
            photons.append(&mut c);
            map.rays += rays;
        }
        let scale = 1.0 / count as f32;
        photons.iter_mut().for_each(|p| p.power *= scale);
        map.index(photons);
        map
    }

    /// A map of `photons` for lookups of the `k` nearest within `radius`.
    fn from_photons(photons: Vec<Photon>, k: usize, radius: f32, max_depth: u32) -> Self {
        let mut map = PhotonMap {
            photons: Vec::new(),
            start: vec![0, 0],
            cell: 2.0 * radius,
            radius,
            k: k.max(1),
            max_depth,
            emitted: photons.len() as u64,
            rays: 0,
        };
        map.index(photons);
        map
    }

    /// Traces photon `i`, appending where it lands; returns the rays traced.
    fn photon(
        &self,
        scene: &RenderScene,
        pick: &Distribution1D,
        i: u32,
        seed: u64,
        out: &mut Vec<Photon>,
    ) -> u64 {
        let mut sampler = Sampler::new(seed ^ PHOTONS, 0, i);
        let (light, pmf, _) = pick.sample_discrete(sampler.next_1d());
        let (u_pos, u_dir) = (sampler.next_2d(), sampler.next_2d());
        let Some(e) = scene.lights.lights[light].sample_ray(&scene.scene, u_pos, u_dir) else {
            return 0;
        };
        if pmf <= 0.0 {
            return 0;
        }
        let mut power = e.power * (1.0 / pmf);
        let off = offset_distance(e.origin.abs().max_element());
        let mut ray = Ray::new(offset_origin(e.origin, e.dir, e.dir, off), e.dir);
        let mut rays = 0;
        // A point reached by a record ray is at least 2 segments from the camera.
        for segments in 1..=self.max_depth - 2 {
            rays += 1;
            let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
                break;
            };
            let si = scene.scene.interaction(&ray, &hit);
            let bsdf = scene.bsdf_at(&si);
            let wo = -ray.d;
            if segments >= 2 && matches!(*bsdf, Bsdf::Diffuse(_)) {
                let n = if si.ng.dot(wo) < 0.0 { -si.ng } else { si.ng };
                out.push(Photon {
                    p: si.p,
                    n,
                    power,
                    segments,
                });
            }
            let frame = si.shading_frame();
            let uc = sampler.next_1d();
            let u = sampler.next_2d();
            let Some(bs) = bsdf.sample(frame.to_local(wo), uc, u) else {
                break;
            };
            // Russian roulette by the throughput's change.
            let survive = bs.weight.max_component().min(1.0);
            if survive <= 0.0 || sampler.next_1d() >= survive {
                break;
            }
            power *= bs.weight * (1.0 / survive);
            let wi = frame.to_world(bs.wi);
            ray = Ray::new(si.spawn(wi), wi);
        }
        rays
    }

    /// Sorts the photons into the grid's buckets (a counting sort by bucket).
    fn index(&mut self, photons: Vec<Photon>) {
        let buckets = photons.len().next_power_of_two();
        let bucket = |p: &Photon| bucket(cell(p.p, self.cell, 0.0), buckets);
        let mut start = vec![0u32; buckets + 1];
        for p in &photons {
            start[bucket(p) + 1] += 1;
        }
        for b in 0..buckets {
            start[b + 1] += start[b];
        }
        let mut next = start.clone();
        let mut sorted = photons.clone();
        for p in photons {
            let b = bucket(&p);
            sorted[next[b] as usize] = p;
            next[b] += 1;
        }
        self.photons = sorted;
        self.start = start;
    }

    /// Photons stored.
    pub fn len(&self) -> usize {
        self.photons.len()
    }

    /// Whether none was stored.
    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    /// Bytes the map takes.
    pub fn bytes(&self) -> usize {
        self.photons.len() * std::mem::size_of::<Photon>() + self.start.len() * 4
    }

    /// Irradiance from light of paths of at most `max_depth - segments` segments at `p`
    /// (surface normal `n` on the viewer's side): sum of the k nearest photons' power over
    /// pi r^2. `scratch` holds the candidates.
    pub fn irradiance(
        &self,
        p: Vec3,
        n: Vec3,
        segments: u32,
        scratch: &mut Vec<(f32, u32)>,
    ) -> Rgb {
        if self.photons.is_empty() {
            return Rgb::ZERO;
        }
        scratch.clear();
        let r2_max = self.radius * self.radius;
        let buckets = self.start.len() - 1;
        // The 2 x 2 x 2 cells from the one below p's nearest cell corner hold every point
        // within `radius` (half a cell) of p.
        let [x, y, z] = cell(p, self.cell, 0.5);
        let mut read = [usize::MAX; 8];
        for k in 0..8 {
            let c = [
                x + (k & 1) as i32,
                y + (k >> 1 & 1) as i32,
                z + (k >> 2) as i32,
            ];
            let b = bucket(c, buckets);
            // Cells may share a bucket: read each bucket once.
            if read.contains(&b) {
                continue;
            }
            read[k] = b;
            let range = self.start[b] as usize..self.start[b + 1] as usize;
            for (i, ph) in self.photons[range.clone()].iter().enumerate() {
                let d2 = (ph.p - p).length_squared();
                if d2 < r2_max && segments + ph.segments <= self.max_depth && ph.n.dot(n) > 0.9 {
                    scratch.push((d2, (range.start + i) as u32));
                }
            }
        }
        if scratch.is_empty() {
            return Rgb::ZERO;
        }
        let r2 = if scratch.len() > self.k {
            scratch.select_nth_unstable_by(self.k - 1, |a, b| a.0.total_cmp(&b.0));
            scratch.truncate(self.k);
            scratch.iter().map(|c| c.0).fold(0.0, f32::max)
        } else {
            r2_max
        };
        // Sum in photon order: the selection's order must not change the sum's rounding.
        scratch.sort_unstable_by_key(|c| c.1);
        let sum = scratch
            .iter()
            .fold(Rgb::ZERO, |acc, c| acc + self.photons[c.1 as usize].power);
        sum * (1.0 / (std::f32::consts::PI * r2.max(1e-12)))
    }
}

/// The grid cell holding `p / size - shift`.
fn cell(p: Vec3, size: f32, shift: f32) -> [i32; 3] {
    (p / size - shift).floor().to_array().map(|v| v as i32)
}

/// A cell's bucket among `buckets` (a power of two), by Teschner et al.'s spatial hash.
fn bucket(c: [i32; 3], buckets: usize) -> usize {
    let h = (c[0] as u32).wrapping_mul(73_856_093)
        ^ (c[1] as u32).wrapping_mul(19_349_663)
        ^ (c[2] as u32).wrapping_mul(83_492_791);
    h as usize & (buckets - 1)
}

/// The photon map answering for diffuse points a record ray's path reaches.
pub struct PhotonGather<'a> {
    /// The map.
    pub map: &'a PhotonMap,
    /// Candidates of the current lookup.
    pub scratch: &'a mut Vec<(f32, u32)>,
}

impl Gather for PhotonGather<'_> {
    fn indirect(
        &mut self,
        _: &RenderScene,
        s: &Shading,
        segments: u32,
        _: &mut RayCounters,
    ) -> Option<Rgb> {
        let Bsdf::Diffuse(d) = s.bsdf else {
            return None;
        };
        let n = if s.si.ng.dot(s.wo) < 0.0 {
            -s.si.ng
        } else {
            s.si.ng
        };
        let e = self.map.irradiance(s.si.p, n, segments, self.scratch);
        Some(d.reflectance * e * std::f32::consts::FRAC_1_PI)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookups_sum_the_k_nearest_photons_as_brute_force_does() {
        // Photons on two facing planes (z = 0 facing up, z = 0.01 facing down), of depths 2-3.
        let mut rng = Sampler::new(9, 0, 0);
        let photons: Vec<Photon> = (0..20_000u32)
            .map(|i| {
                let u = rng.next_2d();
                let up = i % 3 != 0;
                Photon {
                    p: Vec3::new(
                        u.x * 2.0 - 1.0,
                        u.y * 2.0 - 1.0,
                        if up { 0.0 } else { 0.01 },
                    ),
                    n: if up { Vec3::Z } else { -Vec3::Z },
                    power: Rgb::splat(1.0 + (i % 7) as f32),
                    segments: 2 + i % 2,
                }
            })
            .collect();
        let (k, radius, max_depth) = (30, 0.08, 5);
        let map = PhotonMap::from_photons(photons.clone(), k, radius, max_depth);
        let mut scratch = Vec::new();
        for q in 0..200u32 {
            let u = rng.next_2d();
            let p = Vec3::new(u.x * 2.4 - 1.2, u.y * 2.4 - 1.2, 0.0);
            let segments = 2 + q % 2;
            let got = map.irradiance(p, Vec3::Z, segments, &mut scratch);
            let mut near: Vec<(f32, &Photon)> = (photons.iter())
                .filter(|ph| ph.n.z > 0.0 && segments + ph.segments <= max_depth)
                .map(|ph| ((ph.p - p).length_squared(), ph))
                .filter(|(d2, _)| *d2 < radius * radius)
                .collect();
            near.sort_by(|a, b| a.0.total_cmp(&b.0));
            let r2 = if near.len() > k {
                near.truncate(k);
                near[k - 1].0
            } else {
                radius * radius
            };
            let sum: f32 = near.iter().map(|(_, ph)| ph.power.r).sum();
            let want = sum / (std::f32::consts::PI * r2);
            assert!(
                (got.r - want).abs() <= 1e-4 * want.max(1.0),
                "at {p:?}: {} vs {want}",
                got.r
            );
        }
    }
}
