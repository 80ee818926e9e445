//! A block's points (seed 004 Step 1, §3.6, §4.6.3): eye rays through each pixel, grouped
//! into sub-pixel regions of similar hits, each a point with its cut through the light
//! clusters; what the rays see emitted; and, beyond the seed, more eye rays where a pixel
//! sees the edge of a light or lies beside one that does.

use super::block::{BlockRender, Far};
use super::feedback::normal_class;
use super::options::{BsdfSamples, Pdf, MOST_RAYS_PER_SURFACE};
use super::pixel::PixelState;
use super::point::{cut_lookup, Point, Shade};
use fenestra_core::stats::RayCounters;
use fenestra_core::{Ray, Rgb, Sampler, Vec2, Vec3};
use fenestra_render::light::LightHit;

/// Eye rays per unique surface in a pixel by image size (§4.6.3): 25 up to 512x512, 20 up
/// to 1024x1024, 15 beyond.
fn rays_per_surface(width: u32, height: u32) -> u32 {
    match u64::from(width) * u64::from(height) {
        0..=262_144 => MOST_RAYS_PER_SURFACE,
        262_145..=1_048_576 => 20,
        _ => 15,
    }
}

/// A sub-pixel region (§3.6): its first hit and how many eye rays it gathered.
struct Region {
    shape: usize,
    material: usize,
    /// How far from its first hit a ray's hit may join it.
    radius: f32,
    rays: u32,
    point: Point,
}

/// Sums of what a pixel's eye rays see emitted, and of its squares, per channel and in
/// luminance.
#[derive(Default)]
struct Emitted {
    sum: Rgb,
    sq: [f64; 3],
    luminance: f64,
    luminance_sq: f64,
    /// The least and the most luminance a ray saw (`None` before the first ray).
    range: Option<[f64; 2]>,
}

impl Emitted {
    fn add(&mut self, le: Rgb) {
        self.sum += le;
        for (c, v) in le.to_array().into_iter().enumerate() {
            self.sq[c] += f64::from(v) * f64::from(v);
        }
        let l = f64::from(le.luminance());
        self.luminance += l;
        self.luminance_sq += l * l;
        self.range = Some(self.range.map_or([l, l], |[lo, hi]| [lo.min(l), hi.max(l)]));
    }

    /// Whether the rays saw the edge of a light: some saw it, others saw less than half as
    /// much (a smooth sky does not count).
    fn edge(&self) -> bool {
        self.range.is_some_and(|[lo, hi]| hi > 0.0 && lo < 0.5 * hi)
    }

    /// The mean over `n` rays and the variance of that mean, per channel.
    fn mean(&self, n: u32) -> (Rgb, [f64; 3]) {
        let sums = self.sum.to_array();
        let variance = std::array::from_fn(|c| variance_of_mean(f64::from(sums[c]), self.sq[c], n));
        (self.sum * (1.0 / n as f32), variance)
    }

    /// Whether the mean luminance over `n` rays is lit but its relative variance is at
    /// least `threshold`.
    fn uncertain(&self, n: u32, threshold: f32) -> bool {
        let m = self.luminance / f64::from(n);
        let variance = variance_of_mean(self.luminance, self.luminance_sq, n);
        m > 0.0 && variance >= f64::from(threshold) * m * m
    }
}

/// The variance of the mean of `n` values from their sum and the sum of their squares.
fn variance_of_mean(sum: f64, sq: f64, n: u32) -> f64 {
    let n = f64::from(n);
    let m = sum / n;
    ((sq / n - m * m) / (n - 1.0).max(1.0)).max(0.0)
}

impl BlockRender<'_> {
    /// Beyond the seed: a pixel none of whose eye rays saw the edge of a light that a
    /// neighbour's rays saw (some of them met it) may hold a sliver of that light that its
    /// own rays missed; it is traced again with `edge_rays` times the seed's eye rays (and
    /// more while they disagree, as any pixel). Neighbours outside the block (x0..x1,
    /// y0..y1) are probed with their first eye rays, so blocks stay independent.
    pub(super) fn beside_light_edges(
        &self,
        pixels: &mut [PixelState],
        (x0, y0, x1, y1): (u32, u32, u32, u32),
        rays: &mut RayCounters,
    ) {
        let options = &self.options;
        if options.emitted_rays == 0 || options.edge_rays == 0 {
            return;
        }
        let per_surface = rays_per_surface(self.width, self.height);
        let w = x1 - x0;
        let mut probed: Vec<(u32, u32, bool)> = Vec::new();
        let mut edge = |x: u32, y: u32, pixels: &[PixelState], rays: &mut RayCounters| {
            if (x0..x1).contains(&x) && (y0..y1).contains(&y) {
                return pixels[((y - y0) * w + (x - x0)) as usize].edge;
            }
            if let Some(&(_, _, e)) = probed.iter().find(|p| (p.0, p.1) == (x, y)) {
                return e;
            }
            let e = self.probe_edge((x, y), per_surface, rays);
            probed.push((x, y, e));
            e
        };
        let mut again = Vec::new();
        for (i, p) in pixels.iter().enumerate() {
            if p.edge {
                continue;
            }
            let near = (-1i64..=1).flat_map(|dy| (-1i64..=1).map(move |dx| (dx, dy)));
            let near = near.filter(|&d| d != (0, 0)).any(|(dx, dy)| {
                let (nx, ny) = (i64::from(p.x) + dx, i64::from(p.y) + dy);
                let inside = (0..i64::from(self.width)).contains(&nx)
                    && (0..i64::from(self.height)).contains(&ny);
                inside && edge(nx as u32, ny as u32, pixels, rays)
            });
            if near {
                again.push(i);
            }
        }
        for i in again {
            let (x, y) = (pixels[i].x, pixels[i].y);
            pixels[i] = self.pixel_points((x, y), options.edge_rays * per_surface, rays);
        }
    }

    /// Whether the first `n` eye rays of pixel (x, y), the ones its own render takes, see
    /// the edge of a light (what they see emitted directly; mirrors and glass not followed).
    fn probe_edge(&self, (x, y): (u32, u32), n: u32, rays: &mut RayCounters) -> bool {
        let scene = self.scene;
        let mut seen = Emitted::default();
        for i in 0..n {
            let (ray, _) = self.eye_ray((x, y), i, rays);
            seen.add(match scene.scene.intersect(&ray, f32::INFINITY) {
                None => self.sky_along(ray.d),
                Some(hit) => {
                    let si = scene.scene.interaction(&ray, &hit);
                    let le = scene.lights.surface_emission(&si, ray.d);
                    le.map_or(Rgb::ZERO, |(_, le)| le)
                }
            });
        }
        seen.edge()
    }

    /// Eye ray `i` of pixel (x, y), through a point drawn from the pixel filter as the path
    /// tracers take theirs, and the rest of its sample stream.
    fn eye_ray(&self, (x, y): (u32, u32), i: u32, rays: &mut RayCounters) -> (Ray, Sampler) {
        let pixel = u64::from(y) * u64::from(self.width) + u64::from(x);
        let mut sampler = Sampler::new(self.seed, pixel, i);
        let camera = &self.scene.scene.camera;
        let film = Vec2::new(x as f32, y as f32) + camera.filter.sample(sampler.next_2d());
        rays.camera += 1;
        (camera.generate_ray(film, self.width, self.height), sampler)
    }

    /// What the environments send along direction `d`.
    fn sky_along(&self, d: Vec3) -> Rgb {
        let lights = &self.scene.lights;
        let sky = lights.environments.iter();
        sky.fold(Rgb::ZERO, |acc, &e| {
            acc + lights.lights[e].le(LightHit::Escaped, d)
        })
    }

    /// Step 1 with the adaptive anti-aliasing of §3.6 and §4.6.3: eye rays through the
    /// pixel (25, 20 or 15 per unique surface by resolution, at most three surfaces' worth),
    /// grouped into sub-pixel regions: a hit joins a region of the same shape, material and
    /// plane within half the pixel's footprint radius of its first hit, else starts one.
    /// Each region is a point, its share of the rays its area, with a cut through the forest
    /// at its first hit; beyond the seed it keeps its hits (up to `region_hits`) for its
    /// light samples to take in turn. What the rays see emitted is averaged over all of them.
    pub(super) fn pixel_points(
        &self,
        (x, y): (u32, u32),
        least: u32,
        rays: &mut RayCounters,
    ) -> PixelState {
        let scene = self.scene;
        let camera = &scene.scene.camera;
        let per_surface = rays_per_surface(self.width, self.height);
        // The pixel's angular size, for its footprint at a hit.
        let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        let d0 = camera.generate_ray(centre, self.width, self.height).d;
        let d1 = camera
            .generate_ray(centre + Vec2::X, self.width, self.height)
            .d;
        let pixel_angle = d0.angle_between(d1);
        let mut regions: Vec<Region> = Vec::new();
        let mut seen = Emitted::default();
        let options = &self.options;
        let most = options.emitted_rays;
        let (mut traced, mut target, mut surfaces) = (0u32, per_surface.max(least), 0u32);
        loop {
            if traced >= target {
                // Beyond the seed: where what the rays see emitted differs from ray to ray
                // (the edge of a visible light), more rays, until its mean is within the
                // pixel threshold or the pixel has `emitted_rays`.
                if traced < most && seen.uncertain(traced, self.threshold) {
                    target = (traced + per_surface).min(most);
                } else {
                    break;
                }
            }
            let (ray, mut sampler) = self.eye_ray((x, y), traced, rays);
            traced += 1;
            let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
                seen.add(self.sky_along(ray.d));
                continue;
            };
            let si = scene.scene.interaction(&ray, &hit);
            let material = scene.scene.shapes[si.shape].material;
            let n = if si.ng.dot(ray.d) <= 0.0 {
                si.ng
            } else {
                -si.ng
            };
            let bsdf = scene.bsdf_at(&si);
            let mut le = scene
                .lights
                .surface_emission(&si, ray.d)
                .map_or(Rgb::ZERO, |(_, le)| le);
            if options.bsdf_samples != BsdfSamples::None && bsdf.is_delta() {
                // Beyond the seed: what a mirror or glass shows one bounce on.
                le += self.specular_emission(&si, &bsdf, (-ray.d, n), &mut sampler, rays);
            }
            seen.add(le);
            let same_surface = |r: &Region| {
                r.shape == si.shape
                    && r.material == material
                    && r.point.n.dot(n) > 0.999
                    && (si.p - r.point.hits[0].si.p).dot(r.point.n).abs() <= 1e-4 * (1.0 + hit.t)
            };
            if !regions.iter().any(same_surface) {
                surfaces += 1;
                target = target.max(per_surface * surfaces.min(3));
            }
            if let Some(r) = regions
                .iter_mut()
                .find(|r| same_surface(r) && (si.p - r.point.hits[0].si.p).length() <= r.radius)
            {
                r.rays += 1;
                // Beyond the seed: the region's light samples go to its hits in turn.
                if r.point.hits.len() < options.region_hits as usize {
                    r.point.hits.push(Shade {
                        si,
                        bsdf: bsdf.into_owned(),
                        wo: -ray.d,
                    });
                }
                continue;
            }
            let bsdf = bsdf.into_owned();
            let receiver = if bsdf.is_transmissive() {
                Vec3::ZERO
            } else {
                n
            };
            let mut cut = Vec::new();
            if !bsdf.is_delta() {
                self.forest
                    .cut(si.p, receiver, self.options.solid_angle, &mut cut);
                let first_far = self.forest.nodes.len() as u32;
                for (k, far) in self.far.iter().enumerate() {
                    if let Far::Region(r) = far {
                        if !r.above(receiver) {
                            continue;
                        }
                    }
                    cut.push(first_far + k as u32);
                }
            }
            let lookup =
                if self.takes_bsdf_samples((&si, &bsdf, -ray.d), &cut, options.bsdf_samples) {
                    cut_lookup(&cut)
                } else {
                    Vec::new()
                };
            regions.push(Region {
                shape: si.shape,
                material,
                radius: 0.5 * hit.t * pixel_angle,
                rays: 1,
                point: Point {
                    hits: vec![Shade {
                        si,
                        bsdf,
                        wo: -ray.d,
                    }],
                    n,
                    class: normal_class(n),
                    area: 0.0,
                    cut,
                    irradiance: Vec::new(),
                    lookup,
                },
            });
        }
        let share = 1.0 / traced as f32;
        let mut points: Vec<Point> = regions
            .into_iter()
            // Mirrors and glass get no light samples (the seed's scope): only what is seen
            // emitted there, and one bounce on (module `bsdf_samples`), counts.
            .filter(|r| !r.point.cut.is_empty())
            .map(|r| Point {
                area: r.rays as f32 * share,
                ..r.point
            })
            .collect();
        if options.pdf == Pdf::Irradiance {
            for q in &mut points {
                q.irradiance = self.irradiance_pdf(q);
            }
        }
        let traced_pdfs = self.trace == Some((x, y));
        PixelState::new((x, y), points, seen.mean(traced), seen.edge(), traced_pdfs)
    }
}
