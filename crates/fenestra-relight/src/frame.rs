//! One frame precomputed and relit (the still-frame core of seed 003 ch. 4): view samples
//! through pixel centres; transfer vectors by the N-body traversal at the view samples the
//! exploration (Alg. 3) picks; their Haar images kept sparse and compressed by Wavelet-LPCA;
//! every other view sample's transfer reconstructed from its nearest explored ones at a few
//! elements (eq. 4.5) and assigned to its nearest cluster. Relighting then costs, per cluster,
//! (1 + l) dot products of the gather samples' radiosity with the mean and basis (in the
//! wavelet domain: <x, B> = <Wx, WB>), and per pixel l multiply-adds. Beyond the seed, the
//! few pixels the scene's own light shows to be reconstructed badly ([`LightCheck`]) are
//! evaluated after all and kept uncompressed.

use crate::explore::{explore, ExploreOptions, ViewSample};
use crate::gather::Gather;
use crate::haar;
use crate::light_check::LightCheck;
use crate::neighbours::PointTree;
use crate::reconstruct::{reconstruct, Signals};
use crate::sparse::{Packed, SparseVec};
use crate::transfer::{elements, monte_carlo, transfer, ViewPoint};
use crate::wlpca::{wlpca, WlpcaOptions};
use fenestra_core::{Rgb, Sampler, Vec2, Vec3};
use fenestra_lpca::{Schedule, Subspace};
use fenestra_render::bsdf::Bsdf;
use fenestra_render::RenderScene;
use fenestra_scene::SurfaceInteraction;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// Pixels are reconstructed in tiles of this many pixels square.
const TILE: usize = 16;
/// Signals a worker keeps: a 16 x 16 tile's pixels have about 60 explored samples among
/// their neighbours at 10% explored (measured: 39,000 inverse transforms a 512 x 512 frame,
/// against 219,000 in scanline order with 32 kept).
const SIGNALS: usize = 64;
/// A reconstructed pixel's neighbours are chosen among this many times as many nearest
/// explored samples.
const CANDIDATES: usize = 2;

/// How a frame is precomputed.
#[derive(Clone, Debug)]
pub struct FrameOptions {
    /// The N-body traversal's solid-angle threshold.
    pub threshold: f32,
    /// Transfer vectors by this many Monte Carlo rays instead of the N-body traversal (0:
    /// N-body).
    pub mc_rays: u32,
    /// Share of the view samples whose transfer is evaluated, in `batches` batches.
    pub explored: f32,
    pub batches: usize,
    /// Wavelet coefficients kept per transfer vector.
    pub keep: usize,
    /// Clusters and the subspace schedule of Wavelet-LPCA.
    pub clusters: usize,
    pub schedule: Schedule,
    /// Explored neighbours and evaluated elements per reconstructed view sample.
    pub neighbours: usize,
    pub elements: usize,
    /// The reconstruction's pull towards the neighbours' average ([`reconstruct`]).
    pub ridge: f64,
    /// Share of the view samples evaluated after reconstruction and kept uncompressed: those
    /// whose reconstructed light departs most from their neighbours'
    /// ([`LightCheck::departure`]).
    pub refined: f32,
    /// Seed of every random choice.
    pub seed: u64,
}

/// A pixel's transfer, and the colour its BSDF gives reflected light.
#[derive(Clone, Debug, PartialEq)]
pub struct Pixel {
    pub transfer: Transfer,
    pub colour: Rgb,
}

/// A pixel's transfer as it is stored.
#[derive(Clone, Debug, PartialEq)]
pub enum Transfer {
    /// Its cluster and its coordinates in the cluster's subspace (nearly every pixel).
    Compressed {
        cluster: u32,
        coefficients: Vec<f32>,
    },
    /// Its sparse wavelet image itself (wavelet indices, ascending, and values): a pixel its
    /// cluster would relight badly.
    Kept { indices: Vec<u32>, values: Vec<f32> },
}

/// A precomputed frame.
#[derive(Clone, Debug)]
pub struct FrameTransfer {
    pub width: u32,
    pub height: u32,
    /// Gather samples its transfer vectors run over.
    pub gather: usize,
    /// The clusters' affine subspaces (wavelet domain, padded length).
    pub clusters: Vec<Subspace>,
    /// Every pixel's transfer (none: background, emitters, nothing to gather from).
    pub pixels: Vec<Option<Pixel>>,
    /// View samples whose transfer was evaluated, and the visibility rays the frame took.
    pub explored: usize,
    pub rays: u64,
}

/// The point a pixel's centre sees (none: background or an emitter).
pub struct View {
    pub si: SurfaceInteraction,
    pub bsdf: Bsdf,
    pub wo: Vec3,
}

impl View {
    fn point(&self) -> ViewPoint<'_> {
        ViewPoint {
            si: &self.si,
            bsdf: &self.bsdf,
            wo: self.wo,
        }
    }
}

/// The view samples of `scene`'s camera at `width` x `height`, row-major.
pub fn views(scene: &RenderScene, width: u32, height: u32) -> Vec<Option<View>> {
    (0..width * height)
        .into_par_iter()
        .map(|i| view(scene, i, width, height))
        .collect()
}

/// The view sample of pixel `i` (row-major) of `scene`'s camera at `width` x `height`.
pub fn view(scene: &RenderScene, i: u32, width: u32, height: u32) -> Option<View> {
    let c = Vec2::new((i % width) as f32 + 0.5, (i / width) as f32 + 0.5);
    let ray = scene.scene.camera.generate_ray(c, width, height);
    let hit = scene.scene.intersect(&ray, f32::INFINITY)?;
    if scene.scene.shapes[hit.shape as usize].emission.is_some() {
        return None;
    }
    let si = scene.scene.interaction(&ray, &hit);
    let bsdf = scene.bsdf_at(&si).into_owned();
    Some(View {
        si,
        bsdf,
        wo: -ray.d,
    })
}

impl FrameTransfer {
    /// Precomputes the frame of `scene`'s camera at `width` x `height` over `gather` (made or
    /// posed on this scene), in parallel; the result does not depend on the thread count.
    pub fn precompute(
        scene: &RenderScene,
        gather: &Gather,
        width: u32,
        height: u32,
        o: &FrameOptions,
    ) -> Self {
        let n = haar::padded_len(gather.samples.len());
        let views = views(scene, width, height);
        let mut frame = FrameTransfer {
            width,
            height,
            gather: gather.samples.len(),
            clusters: Vec::new(),
            pixels: vec![None; views.len()],
            explored: 0,
            rays: 0,
        };
        // Without gather samples (no non-emitting mesh) there is no transfer to compute.
        let seen: Vec<usize> = (0..views.len())
            .filter(|&i| views[i].is_some() && !gather.samples.is_empty())
            .collect();
        if seen.is_empty() {
            return frame;
        }
        let view = |i: usize| views[seen[i]].as_ref().expect("seen");
        let samples: Vec<ViewSample> = (0..seen.len())
            .map(|i| ViewSample {
                p: view(i).si.p,
                frame: 0,
            })
            .collect();
        let radius = scene.scene.bounding_sphere().1;
        let explore_options = ExploreOptions {
            batches: o.batches.max(1),
            per_batch: ((o.explored * seen.len() as f32) as usize / o.batches.max(1)).max(1),
            neighbours: 8,
            rank_tolerance: 1e-3,
            w_space: 1.0 / (2.0 * radius),
            w_time: 1.0,
            seed: o.seed,
        };
        let rays = AtomicU64::new(0);
        let near = (o.mc_rays > 0).then(|| gather.points());
        // A view sample's transfer vector (eq. 4.1 by the N-body traversal, or Monte Carlo),
        // wavelet-transformed and kept sparse.
        let evaluate = |i: usize| {
            let (mut w, r) = match &near {
                None => transfer(scene, gather, &view(i).point(), o.threshold),
                Some(near) => {
                    let mut sampler = Sampler::new(o.seed ^ 0x3c, seen[i] as u64, 0);
                    let x = monte_carlo(
                        scene,
                        gather,
                        near,
                        &view(i).point(),
                        o.mc_rays,
                        &mut sampler,
                    );
                    (x, o.mc_rays as u64)
                }
            };
            rays.fetch_add(r, Ordering::Relaxed);
            w.resize(n, 0.0);
            haar::forward(&mut w, &mut vec![0.0; n]);
            SparseVec::largest(&w, o.keep)
        };
        // The explored view samples and their transfer (the rows of Wavelet-LPCA).
        let (explored, rows): (Vec<usize>, Vec<SparseVec>) =
            explore(&samples, &explore_options, evaluate)
                .into_iter()
                .unzip();
        let k = o.clusters.min(explored.len()).max(1);
        let centroids: Vec<usize> = (0..k).map(|c| c * rows.len() / k).collect();
        let model = wlpca(
            &rows,
            &centroids,
            &WlpcaOptions {
                schedule: o.schedule.clone(),
                // Warm-started from the previous iteration's directions, EM moves little
                // after the first fits: a few iterations per fit (measured: docs/relight.md).
                em_iterations: 10,
                em_tolerance: 1e-4,
            },
        );
        let packed: Vec<Packed> = model.models.iter().map(Packed::new).collect();
        let check = LightCheck::new(scene, gather, &rows, &model.models, o.seed);
        let mut row_of = vec![usize::MAX; samples.len()];
        for (r, i) in explored.iter().enumerate() {
            row_of[*i] = r;
        }
        let at: Vec<_> = (explored.iter())
            .map(|&i| samples[i].point(explore_options.w_space, 1.0))
            .collect();
        let tree = PointTree::new(&at);
        // Pixels in tiles of 16 x 16, so that a worker's kept signals (below) serve a tile's
        // pixels, which share their neighbours, instead of being replaced along a scanline.
        let mut order: Vec<usize> = (0..seen.len()).collect();
        order.sort_by_key(|&i| {
            let (x, y) = (seen[i] % width as usize, seen[i] / width as usize);
            (y / TILE, x / TILE, y, x)
        });
        // Every pixel's transfer, with how far a reconstructed one's light departs from its
        // neighbours' (0 for explored ones).
        let mut pixels: Vec<(usize, Option<Pixel>, f64)> = order
            .into_par_iter()
            .map_init(
                || {
                    let signals = Signals::new(SIGNALS.max(4 * o.neighbours), gather.samples.len());
                    (Vec::new(), Vec::new(), signals)
                },
                |(near, products, signals), i| {
                    let v = view(i).point();
                    let pixel = seen[i];
                    near.clear();
                    let c = if row_of[i] != usize::MAX {
                        let r = row_of[i];
                        let c = model.assignments[r];
                        packed[c as usize].products(&rows[r], products);
                        c
                    } else {
                        // Eq. 4.5 from the nearest explored samples, fitted at a few elements.
                        tree.nearest(
                            &samples[i].point(explore_options.w_space, 1.0),
                            CANDIDATES * o.neighbours,
                            near,
                        );
                        // Those that face its way first (stable: nearest first within each): a
                        // pixel beside a corner otherwise takes half its neighbours from the
                        // other wall, whose transfer is nothing like its own.
                        let n = v.si.ng;
                        near.sort_by_key(|&(_, r)| {
                            view(explored[r as usize]).si.ng.dot(n).abs() <= 0.7
                        });
                        near.truncate(o.neighbours);
                        let slots: Vec<usize> =
                            near.iter().map(|&(_, r)| signals.load(&rows, r)).collect();
                        let dense: Vec<&[f64]> = slots.iter().map(|&s| signals.signal(s)).collect();
                        // The elements to fit at, drawn where the neighbours' transfer is (by its
                        // magnitude): uniform indices mostly land on gather samples the point
                        // cannot see, where every neighbour is zero too.
                        let mut sampler = Sampler::new(o.seed ^ 0x7e1, pixel as u64, 0);
                        let indices: Vec<usize> = (0..o.elements.max(near.len()))
                            .map(|_| signals.pick(&slots, sampler.next_1d() as f64))
                            .collect();
                        let shading = v.si.shading_frame();
                        // Each element evaluated once (the draws repeat the largest).
                        let mut unique = indices.clone();
                        unique.sort_unstable();
                        unique.dedup();
                        let mut r = 0;
                        let samples = unique.iter().map(|&j| &gather.samples[j]);
                        let evaluated = elements(scene, &v, &shading, samples, &mut r);
                        let values: Vec<f64> = (indices.iter())
                            .map(|j| evaluated[unique.binary_search(j).expect("drawn")])
                            .collect();
                        rays.fetch_add(r, Ordering::Relaxed);
                        let Some(weights) = reconstruct(&dense, &indices, &values, o.ridge) else {
                            return (i, None, 0.0);
                        };
                        // The cluster among its neighbours' (Alg. 4 over all clusters would cost
                        // a distance per cluster per pixel; neighbours lie in one or two), by
                        // the distance less |x|^2, which is the same for all.
                        let mut candidates: Vec<u32> = near
                            .iter()
                            .map(|&(_, r)| model.assignments[r as usize])
                            .collect();
                        candidates.sort_unstable();
                        candidates.dedup();
                        let mut best = (f64::INFINITY, candidates[0]);
                        for &c in &candidates {
                            let a = &packed[c as usize];
                            signals.products(&rows, &slots, &weights, c, a, products);
                            let excess = a.excess(products);
                            if excess < best.0 {
                                best = (excess, c);
                            }
                        }
                        let (a, c) = (&packed[best.1 as usize], best.1);
                        signals.products(&rows, &slots, &weights, c, a, products);
                        c
                    };
                    let coefficients = packed[c as usize].coordinates(products);
                    let departure = match near.is_empty() {
                        true => 0.0,
                        false => check.departure(c, &coefficients, near.iter().map(|&(_, r)| r)),
                    };
                    let transfer = Transfer::Compressed {
                        cluster: c,
                        coefficients,
                    };
                    let colour = v.colour();
                    (i, Some(Pixel { transfer, colour }), departure)
                },
            )
            .collect();
        // The reconstructions departing most from their neighbours are evaluated after all
        // and kept uncompressed: their clusters, fitted to the common transfer, would give
        // them their neighbours' light again.
        let mut worst: Vec<usize> = (0..pixels.len()).filter(|&k| pixels[k].2 > 0.0).collect();
        worst.sort_by(|&a, &b| pixels[b].2.total_cmp(&pixels[a].2).then(a.cmp(&b)));
        worst.truncate((o.refined * seen.len() as f32) as usize);
        let refined: Vec<SparseVec> = worst.par_iter().map(|&k| evaluate(pixels[k].0)).collect();
        for (&k, x) in worst.iter().zip(refined) {
            if let Some(p) = pixels[k].1.as_mut() {
                p.transfer = Transfer::Kept {
                    indices: x.indices,
                    values: x.values.iter().map(|&v| v as f32).collect(),
                };
            }
        }
        for (i, p, _) in pixels {
            frame.pixels[seen[i]] = p;
        }
        frame.clusters = model.models;
        frame.explored = explored.len() + worst.len();
        frame.rays = rays.into_inner();
        frame
    }

    /// Bytes it holds in memory (about).
    pub fn bytes(&self) -> usize {
        let vectors: usize = self.clusters.iter().map(|c| 1 + c.basis.len()).sum();
        let pixels: usize = (self.pixels.iter().flatten())
            .map(|p| match &p.transfer {
                Transfer::Compressed { coefficients, .. } => 40 + 4 * coefficients.len(),
                Transfer::Kept { indices, .. } => 64 + 8 * indices.len(),
            })
            .sum();
        vectors * haar::padded_len(self.gather) * 8 + pixels + self.pixels.len() * 8
    }

    /// The one-bounce indirect image for the gather samples' radiosity `b` (row-major).
    pub fn relight(&self, b: &[Rgb]) -> Vec<Rgb> {
        let n = haar::padded_len(self.gather);
        let mut scratch = vec![0.0; n];
        let channel = |f: fn(&Rgb) -> f32, scratch: &mut [f64]| {
            let mut w: Vec<f64> = b.iter().map(|c| f(c) as f64).collect();
            w.resize(n, 0.0);
            haar::forward(&mut w, scratch);
            w
        };
        let wb = [
            channel(|c| c.r, &mut scratch),
            channel(|c| c.g, &mut scratch),
            channel(|c| c.b, &mut scratch),
        ];
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
        // Per cluster: the mean's and each direction's light, per channel.
        let lights: Vec<(Rgb, Vec<Rgb>)> = (self.clusters.iter())
            .map(|s| {
                let rgb = |v: &[f64]| {
                    Rgb::new(
                        dot(v, &wb[0]) as f32,
                        dot(v, &wb[1]) as f32,
                        dot(v, &wb[2]) as f32,
                    )
                };
                (rgb(&s.mean), s.basis.iter().map(|e| rgb(e)).collect())
            })
            .collect();
        (self.pixels.iter())
            .map(|p| match p {
                None => Rgb::ZERO,
                Some(p) => {
                    let l = match &p.transfer {
                        Transfer::Compressed {
                            cluster,
                            coefficients,
                        } => {
                            let (mean, basis) = &lights[*cluster as usize];
                            (coefficients.iter().zip(basis))
                                .fold(*mean, |acc, (&w, e)| acc + *e * w)
                        }
                        Transfer::Kept { indices, values } => {
                            let at = |i: u32| {
                                let i = i as usize;
                                Rgb::new(wb[0][i] as f32, wb[1][i] as f32, wb[2][i] as f32)
                            };
                            (indices.iter().zip(values))
                                .fold(Rgb::ZERO, |acc, (&i, &v)| acc + at(i) * v)
                        }
                    };
                    // Light is not negative: a subspace that fits a pixel's transfer poorly
                    // can give it negative coordinates' worth of light (a pixel at -0.6 where
                    // the truth is 0.06).
                    p.colour * l.map(|c| c.max(0.0))
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transfer::{radiosity, relit};
    use fenestra_scene::{Backend, Scene};

    /// The relative RMS difference between `frame`'s relit image and the one every pixel's
    /// full N-body transfer gives, for the same radiosity.
    fn error_against_full_transfer(
        scene: &RenderScene,
        gather: &Gather,
        frame: &FrameTransfer,
        threshold: f32,
    ) -> f64 {
        error_at(scene, gather, frame, threshold, |_| true)
    }

    /// The same over the pixels `at` picks.
    fn error_at(
        scene: &RenderScene,
        gather: &Gather,
        frame: &FrameTransfer,
        threshold: f32,
        at: impl Fn(&Pixel) -> bool,
    ) -> f64 {
        let b = radiosity(scene, gather, 8, 2);
        let image = frame.relight(&b);
        let (w, h) = (frame.width, frame.height);
        let (mut err2, mut ref2) = (0.0f64, 0.0f64);
        for (i, got) in image.iter().enumerate() {
            if !frame.pixels[i].as_ref().is_some_and(&at) {
                continue;
            }
            let c = Vec2::new((i as u32 % w) as f32 + 0.5, (i as u32 / w) as f32 + 0.5);
            let ray = scene.scene.camera.generate_ray(c, w, h);
            let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
                continue;
            };
            if scene.scene.shapes[hit.shape as usize].emission.is_some() {
                continue;
            }
            let si = scene.scene.interaction(&ray, &hit);
            let bsdf = scene.bsdf_at(&si);
            let v = ViewPoint {
                si: &si,
                bsdf: &bsdf,
                wo: -ray.d,
            };
            let (x, _) = transfer(scene, gather, &v, threshold);
            let want = relit(v.colour(), &x, &b).luminance() as f64;
            err2 += (got.luminance() as f64 - want).powi(2);
            ref2 += want * want;
        }
        (err2 / ref2).sqrt()
    }

    #[test]
    fn a_scene_without_surfaces_to_gather_from_relights_black() {
        // The Cornell box's walls made emitters: nothing left to gather light.
        let mut desc = fenestra_builtin::load("cornell-box").expect("scene");
        for shape in &mut desc.shapes {
            shape
                .emission
                .get_or_insert(fenestra_scene::light::Emission::radiance(Rgb::ONE));
        }
        let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("build"));
        let options = FrameOptions {
            threshold: 0.02,
            mc_rays: 0,
            explored: 0.5,
            batches: 2,
            keep: 64,
            clusters: 2,
            schedule: Schedule::parse("0:1").expect("schedule"),
            neighbours: 2,
            elements: 4,
            ridge: 0.1,
            refined: 0.0,
            seed: 1,
        };
        let gather = Gather::new(&scene, 64, 1);
        let frame = FrameTransfer::precompute(&scene, &gather, 8, 8, &options);
        assert_eq!(frame.explored, 0);
        assert!(frame.relight(&[]).iter().all(|&l| l == Rgb::ZERO));
    }

    #[test]
    fn relit_light_is_never_negative() {
        // Two gather samples (padded length 2); one cluster whose direction, at the pixels'
        // coordinates, outweighs its mean at the second sample.
        let pixel = |c: f32| {
            Some(Pixel {
                transfer: Transfer::Compressed {
                    cluster: 0,
                    coefficients: vec![c],
                },
                colour: Rgb::splat(1.0),
            })
        };
        let frame = FrameTransfer {
            width: 2,
            height: 1,
            gather: 2,
            // Haar domain: (x0 + x1) / sqrt 2 and (x0 - x1) / sqrt 2.
            clusters: vec![Subspace {
                mean: vec![std::f64::consts::SQRT_2, 0.0],
                basis: vec![vec![0.0, 1.0]],
            }],
            pixels: vec![pixel(0.5), pixel(-3.0)],
            explored: 0,
            rays: 0,
        };
        // Element vectors (1.35, 0.65) and (-1.12, 3.12): the first relit as is, the second's
        // negative light at red clamped.
        let image = frame.relight(&[Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 1.0, 0.0)]);
        let x = 0.5 * std::f32::consts::FRAC_1_SQRT_2;
        assert!((image[0].r - (1.0 + x)).abs() < 1e-5 && (image[0].g - (1.0 - x)).abs() < 1e-5);
        assert_eq!(image[1].r, 0.0);
        assert!((image[1].g - (1.0 + 3.0 * std::f32::consts::FRAC_1_SQRT_2)).abs() < 1e-5);
    }

    #[test]
    fn a_compressed_frame_relights_like_its_full_transfer() {
        let desc = fenestra_builtin::load("cornell-box").expect("scene");
        let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("build"));
        let gather = Gather::new(&scene, 2048, 1);
        let base = FrameOptions {
            threshold: 0.02,
            mc_rays: 0,
            explored: 1.0,
            batches: 3,
            keep: 2048,
            clusters: 64,
            schedule: Schedule::parse("0:2,24:3").expect("schedule"),
            neighbours: 6,
            elements: 32,
            ridge: 0.1,
            refined: 0.0,
            seed: 1,
        };
        // Every view sample explored: the compression alone, nearly exact at this size.
        let all = FrameTransfer::precompute(&scene, &gather, 24, 24, &base);
        let e = error_against_full_transfer(&scene, &gather, &all, base.threshold);
        assert!(e < 0.03, "everything explored: relative RMS error {e}");
        // A tenth explored, the rest by eq. 4.5, in a room with furniture: the fitted
        // combination beats the neighbours' plain average (a ridge so strong that the fit is
        // ignored). In the box with half explored the average does as well: neighbours that
        // close and facing the same way leave the fit nothing to correct.
        let desc = fenestra_builtin::load("relight-room").expect("scene");
        let scene = RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("build"));
        let gather = Gather::new(&scene, 2048, 1);
        let tenth = FrameOptions {
            explored: 0.1,
            ..base.clone()
        };
        let fitted = FrameTransfer::precompute(&scene, &gather, 48, 36, &tenth);
        assert!(fitted.explored <= 48 * 36 / 10);
        let e_fit = error_against_full_transfer(&scene, &gather, &fitted, base.threshold);
        let average = FrameTransfer::precompute(
            &scene,
            &gather,
            48,
            36,
            &FrameOptions {
                ridge: 1e6,
                ..tenth.clone()
            },
        );
        let e_avg = error_against_full_transfer(&scene, &gather, &average, base.threshold);
        assert!(
            e_fit < 0.25 && e_fit < e_avg,
            "a tenth explored: fitted {e_fit}, averaged {e_avg}"
        );
        // The 5% of pixels departing most from their neighbours evaluated and kept: each as
        // its full transfer relights it (nothing truncated at this size), the frame nearer
        // the full transfer than the reconstruction alone.
        let refined = FrameTransfer::precompute(
            &scene,
            &gather,
            48,
            36,
            &FrameOptions {
                refined: 0.05,
                ..tenth
            },
        );
        let kept = |p: &Pixel| matches!(p.transfer, Transfer::Kept { .. });
        let seen = fitted.pixels.iter().flatten().count();
        assert_eq!(
            refined.pixels.iter().flatten().filter(|p| kept(p)).count(),
            seen / 20
        );
        assert_eq!(refined.explored, fitted.explored + seen / 20);
        let e_kept = error_at(&scene, &gather, &refined, base.threshold, kept);
        assert!(e_kept < 1e-5, "kept pixels: relative RMS error {e_kept}");
        let e_refined = error_against_full_transfer(&scene, &gather, &refined, base.threshold);
        assert!(
            e_refined < 0.9 * e_fit,
            "a tenth explored: refined {e_refined}, reconstructed {e_fit}"
        );
    }
}
