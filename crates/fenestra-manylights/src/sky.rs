//! Environment lights as regions of directions (seed 004 §3.4.2, §3.5.1): each environment is
//! cut into regions that join every point's cut as clusters, after the structured importance
//! sampling the seed uses (Agarwal et al. 2003) in a simpler form: the sphere (polar angle
//! from +z, azimuth) is split, always at the region holding the most pre-integrated power,
//! in half along its longer angular side, until there are as many regions as asked (the
//! seed's 300). Bright parts of the sky get small regions. A region is sampled uniformly in
//! solid angle (jittered within it); regions wholly below a point's horizon are pruned.

use fenestra_core::{Vec2, Vec3, PI};
use fenestra_render::light::{LightHit, Lights};
use fenestra_render::options::OptionError;

/// The seed's number of environment regions.
pub const SKY_REGIONS: usize = 300;

/// Most regions of an environment (each is a cluster of every cut of ias, a group of the
/// learned sampler).
const MAX_SKY_REGIONS: usize = 4096;

/// `sky_regions` of an options group: at most [`MAX_SKY_REGIONS`].
pub fn check_sky_regions(regions: usize) -> Result<(), OptionError> {
    if regions > MAX_SKY_REGIONS {
        return Err(OptionError::new(
            "sky_regions",
            format!("is at most {MAX_SKY_REGIONS}, got {regions}"),
        ));
    }
    Ok(())
}

/// Directions per side of the grid the regions' power is integrated on (2:1 in azimuth).
const GRID: usize = 128;

/// A rectangle of directions: polar angles theta0..theta1 from +z, azimuths phi0..phi1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyRegion {
    /// The environment light (index into the scene's lights).
    pub light: usize,
    /// Polar angle range (radians).
    pub theta: [f32; 2],
    /// Azimuth range (radians).
    pub phi: [f32; 2],
    /// Its pre-integrated power (luminance x solid angle, on the grid).
    pub power: f32,
    /// Unit direction at its centre and the largest angle from it to the region's edge.
    pub axis: Vec3,
    /// See `axis`.
    pub half_angle: f32,
}

/// The direction of polar angle `theta` and azimuth `phi`.
fn direction(theta: f32, phi: f32) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    Vec3::new(st * phi.cos(), st * phi.sin(), ct)
}

impl SkyRegion {
    fn new(light: usize, theta: [f32; 2], phi: [f32; 2], power: f32) -> Self {
        let axis = direction(0.5 * (theta[0] + theta[1]), 0.5 * (phi[0] + phi[1]));
        // The farthest of the corners and edge midpoints, and a margin for the curved edges.
        let mut half: f32 = 0.0;
        for t in [theta[0], 0.5 * (theta[0] + theta[1]), theta[1]] {
            for p in [phi[0], 0.5 * (phi[0] + phi[1]), phi[1]] {
                half = half.max(axis.angle_between(direction(t, p)));
            }
        }
        let margin = 0.25 * (theta[1] - theta[0]).max((phi[1] - phi[0]) * 0.5);
        SkyRegion {
            light,
            theta,
            phi,
            power,
            axis,
            half_angle: (half + margin).min(PI),
        }
    }

    /// Its solid angle.
    pub fn solid_angle(&self) -> f32 {
        (self.phi[1] - self.phi[0]) * (self.theta[0].cos() - self.theta[1].cos())
    }

    /// A direction uniform in solid angle over the region.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let (c0, c1) = (self.theta[0].cos(), self.theta[1].cos());
        let cos_t = c0 + (c1 - c0) * u.x;
        let phi = self.phi[0] + (self.phi[1] - self.phi[0]) * u.y;
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
    }

    /// Whether the direction of polar angles `[theta, phi]` (from [`polar`]) lies in the
    /// region (regions tile the sphere: each direction lies in one of an environment's
    /// regions).
    pub fn holds(&self, [theta, phi]: [f32; 2]) -> bool {
        let inside = |v: f32, [lo, hi]: [f32; 2], end: f32| v >= lo && (v < hi || hi >= end);
        inside(theta, self.theta, PI) && inside(phi, self.phi, 2.0 * PI)
    }

    /// Whether some direction of the region lies above the plane of normal `n` (always, for
    /// a zero normal).
    pub fn above(&self, n: Vec3) -> bool {
        n == Vec3::ZERO || self.axis.angle_between(n) - self.half_angle < 0.5 * PI
    }
}

/// The polar angle from +z and the azimuth in [0, 2 pi) of unit direction `d`.
pub fn polar(d: Vec3) -> [f32; 2] {
    let phi = d.y.atan2(d.x);
    let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
    [d.z.clamp(-1.0, 1.0).acos(), phi]
}

/// The regions of every environment light of `lights`, `count` for each.
pub fn regions(lights: &Lights, count: usize) -> Vec<SkyRegion> {
    // The sun's disk, narrower than a grid cell, is sampled whole (as a distant light is).
    lights
        .environments
        .iter()
        .filter(|&&e| !lights.lights[e].is_compact())
        .flat_map(|&e| SkyMap::new(lights, e, count).regions)
        .collect()
}

/// One environment light's regions, and which region each direction lies in.
#[derive(Clone, Debug)]
pub struct SkyMap {
    /// The regions, tiling the sphere.
    pub regions: Vec<SkyRegion>,
    /// Per cell of the grid the regions are made of (row by polar angle): its region.
    cells: Vec<u16>,
}

impl SkyMap {
    /// The regions of environment light `light` of `lights`: `count` at most (and at most
    /// one per grid cell).
    pub fn new(lights: &Lights, light: usize, count: usize) -> Self {
        let env = &lights.lights[light];
        // Luminance x solid angle of each grid cell.
        let (rows, cols) = (GRID, 2 * GRID);
        let (dt, dp) = (PI / rows as f32, 2.0 * PI / cols as f32);
        let cells: Vec<f32> = (0..rows * cols)
            .map(|k| {
                let (i, j) = (k / cols, k % cols);
                let t = (i as f32 + 0.5) * dt;
                let d = direction(t, (j as f32 + 0.5) * dp);
                env.le(LightHit::Escaped, d).luminance() * t.sin() * dt * dp
            })
            .collect();
        // Regions as cell rectangles [i0, i1) x [j0, j1), split at the most powerful.
        let power = |i0: usize, i1: usize, j0: usize, j1: usize| -> f32 {
            (i0..i1)
                .map(|i| cells[i * cols + j0..i * cols + j1].iter().sum::<f32>())
                .sum()
        };
        let count = count.clamp(1, MAX_SKY_REGIONS);
        let mut rects = vec![(0, rows, 0, cols, power(0, rows, 0, cols))];
        while rects.len() < count {
            // The most powerful region that can still be split (ties: the first).
            let Some(k) = (0..rects.len())
                .filter(|&k| rects[k].1 - rects[k].0 > 1 || rects[k].3 - rects[k].2 > 1)
                .max_by(|&a, &b| rects[a].4.total_cmp(&rects[b].4).then(b.cmp(&a)))
            else {
                break;
            };
            let (i0, i1, j0, j1, _) = rects[k];
            // Split its longer angular side in half (azimuth cells are twice as many).
            let (a, b) = if (i1 - i0) * 2 >= j1 - j0 && i1 - i0 > 1 {
                let m = (i0 + i1) / 2;
                ((i0, m, j0, j1), (m, i1, j0, j1))
            } else {
                let m = (j0 + j1) / 2;
                ((i0, i1, j0, m), (i0, i1, m, j1))
            };
            rects[k] = (a.0, a.1, a.2, a.3, power(a.0, a.1, a.2, a.3));
            rects.push((b.0, b.1, b.2, b.3, power(b.0, b.1, b.2, b.3)));
        }
        let mut region_of = vec![0u16; rows * cols];
        let regions = (rects.iter().enumerate())
            .map(|(r, &(i0, i1, j0, j1, p))| {
                for i in i0..i1 {
                    region_of[i * cols + j0..i * cols + j1].fill(r as u16);
                }
                SkyRegion::new(
                    light,
                    [i0 as f32 * dt, i1 as f32 * dt],
                    [j0 as f32 * dp, j1 as f32 * dp],
                    p,
                )
            })
            .collect();
        SkyMap {
            regions,
            cells: region_of,
        }
    }

    /// The region unit direction `d` lies in.
    pub fn region_of(&self, d: Vec3) -> usize {
        let [theta, phi] = polar(d);
        let (rows, cols) = (GRID, 2 * GRID);
        let i = ((theta * (rows as f32 / PI)) as usize).min(rows - 1);
        let j = ((phi * (cols as f32 / (2.0 * PI))) as usize).min(cols - 1);
        self.cells[i * cols + j] as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::Rng;

    #[test]
    fn regions_tile_the_sphere_and_bound_their_directions() {
        let mut regions = Vec::new();
        // A synthetic set: the split of an empty sky is by halves, as for any sky.
        let (dt, dp) = (PI / 4.0, PI / 4.0);
        for i in 0..4 {
            for j in 0..8 {
                regions.push(SkyRegion::new(
                    0,
                    [i as f32 * dt, (i + 1) as f32 * dt],
                    [j as f32 * dp, (j + 1) as f32 * dp],
                    1.0,
                ));
            }
        }
        let total: f32 = regions.iter().map(SkyRegion::solid_angle).sum();
        assert!((total - 4.0 * PI).abs() < 1e-4, "{total}");
        let mut rng = Rng::new(5);
        for r in &regions {
            for _ in 0..200 {
                let d = r.sample(rng.next_2d());
                assert!(r.axis.angle_between(d) <= r.half_angle + 1e-5);
                let holders: Vec<&SkyRegion> =
                    regions.iter().filter(|o| o.holds(polar(d))).collect();
                assert!(holders.len() == 1 && holders[0] == r, "{d} in {holders:?}");
                // A direction above a plane makes its region count as above it.
                let n = fenestra_core::warp::square_to_uniform_sphere(rng.next_2d());
                if d.dot(n) > 0.0 {
                    assert!(r.above(n), "{r:?} {d} {n}");
                }
            }
        }
    }
}
