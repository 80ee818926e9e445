//! BSDF samples (beyond the seed, which samples lights only and gives mirrors and glass
//! nothing but what they show emitted).
//!
//! Where a light of the cut is larger than the BSDF's lobe: on a narrow lobe (a polished
//! floor mirroring a window) a light sample rarely lands where the BSDF is large, however
//! well the pass's PDF picks clusters, and beside a large emitter its density varies a lot
//! across it; the pixel stays noisy. There each light sample comes with a BSDF sample, the
//! two weighed by the power heuristic (Veach 1997). The light technique's density of a direction is the pass's own: the
//! probability of the cluster of the cut the light lies in, times the light's share of that
//! cluster by power, times the light's density of the direction. Both techniques use the
//! same PDF throughout a pass, so each pass's estimate stays unbiased; the statistics still
//! learn from light samples only.
//!
//! At mirrors and glass: an eye ray follows one sampled bounce and adds the light it meets,
//! as a path tracer limited to direct light (path length 2) does.

use super::block::{BlockRender, Far};
use super::options::BsdfSamples;
use super::point::{Point, Shade};
use crate::forest::NO_PARENT;
use crate::sky::polar;
use fenestra_core::mis::MisHeuristic;
use fenestra_core::stats::RayCounters;
use fenestra_core::{Ray, Rgb, Sampler, Vec3};
use fenestra_render::bsdf::{reflect_z, Bsdf, BsdfSample};
use fenestra_render::integrator::Sides;
use fenestra_render::light::LightHit;
use fenestra_scene::SurfaceInteraction;

/// How the two techniques are weighed.
pub(super) const HEURISTIC: MisHeuristic = MisHeuristic::Power { beta: 2.0 };

impl BlockRender<'_> {
    /// Whether a point (`si`, `bsdf`, seen from direction `wo`) with `cut` takes BSDF
    /// samples besides light samples under `mode`. `Auto`: where a light of its cut subtends
    /// more than the BSDF's lobe, 1 / the lobe's peak density. There light samples
    /// alone do poorly: a light larger than a narrow lobe is rarely sampled where the BSDF
    /// is large (a polished floor mirroring a lamp), and a light wider than a Lambertian
    /// lobe (pi sr) has a density that varies a lot across it (a wall beside a large
    /// emitter). Lights smaller than the lobe are what light samples do best (Veach 1997).
    pub(super) fn takes_bsdf_samples(
        &self,
        (si, bsdf, wo): (&SurfaceInteraction, &Bsdf, Vec3),
        cut: &[u32],
        mode: BsdfSamples,
    ) -> bool {
        if bsdf.is_delta() {
            return false;
        }
        match mode {
            BsdfSamples::None => false,
            BsdfSamples::All => true,
            BsdfSamples::Auto => {
                let wo = si.shading_frame().to_local(wo);
                // The peak: towards the mirror direction (glossy lobes) or the normal
                // (Lambertian ones).
                let normal = Vec3::Z * wo.z.signum();
                let lobe = 1.0 / bsdf.pdf(wo, reflect_z(wo)).max(bsdf.pdf(wo, normal));
                let nodes = &self.forest.nodes;
                cut.iter()
                    .filter_map(|&c| nodes.get(c as usize))
                    .filter(|c| c.children.is_none())
                    .any(|c| c.sphere.solid_angle(si.p) > lobe)
            }
        }
    }
}

/// A light a ray met: an environment, or light `.0` on the surface at `.1`.
enum Source<'a> {
    Environment(usize),
    Surface(usize, &'a SurfaceInteraction),
}

/// A direction sampled from `bsdf` at `si` for light arriving along it (`wo` towards the
/// viewer, `n` the normal on the viewer's side); `None` where the BSDF gives none or the
/// shading normal would let light through the surface.
fn sample_direction(
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    (wo, n): (Vec3, Vec3),
    sides: Sides,
    sampler: &mut Sampler,
) -> Option<(BsdfSample, Vec3)> {
    let frame = si.shading_frame();
    let wo = frame.to_local(wo);
    let (uc, u) = (sampler.next_1d(), sampler.next_2d());
    let bs = bsdf.sample(wo, uc, u)?;
    let wi = frame.to_world(bs.wi);
    let leaks = sides == Sides::Both
        && !bsdf.is_transmissive()
        && (wi.dot(n) > 0.0) != (bs.wi.z * wo.z > 0.0);
    (!leaks).then_some((bs, wi))
}

/// The pass's cluster probabilities at a point (`pdf`, summing to `total`).
#[derive(Clone, Copy)]
pub(super) struct PassPdf<'a> {
    pub(super) pdf: &'a [f32],
    pub(super) total: f32,
}

impl PassPdf<'_> {
    /// The probability of cluster `node` of point `q`'s cut (`None`: not in the cut).
    fn of(&self, q: &Point, node: u32) -> Option<f32> {
        let k = q.lookup.binary_search_by_key(&node, |&(c, _)| c).ok()?;
        Some(self.pdf[q.lookup[k].1 as usize] / self.total)
    }
}

impl BlockRender<'_> {
    /// One BSDF sample at point `q`'s hit `at`: the light it finds over its density,
    /// weighed against the light technique of the pass (`pass`).
    pub(super) fn bsdf_sample(
        &self,
        q: &Point,
        at: &Shade,
        pass: PassPdf,
        sampler: &mut Sampler,
        rays: &mut RayCounters,
    ) -> Rgb {
        let Some((bs, wi)) = sample_direction(&at.si, &at.bsdf, (at.wo, q.n), self.sides, sampler)
        else {
            return Rgb::ZERO;
        };
        let found = self.light_along(&at.si, wi, rays, |source| {
            if bs.delta {
                return 1.0;
            }
            HEURISTIC.weight(bs.pdf, self.source_density((q, at.si.p), pass, wi, source))
        });
        bs.weight * found
    }

    /// What an eye ray that met the mirror or glass `bsdf` at `si` (`wo` towards the eye,
    /// `n` the normal on its side) sees emitted one sampled bounce on.
    pub(super) fn specular_emission(
        &self,
        si: &SurfaceInteraction,
        bsdf: &Bsdf,
        (wo, n): (Vec3, Vec3),
        sampler: &mut Sampler,
        rays: &mut RayCounters,
    ) -> Rgb {
        match sample_direction(si, bsdf, (wo, n), self.sides, sampler) {
            Some((bs, wi)) => bs.weight * self.light_along(si, wi, rays, |_| 1.0),
            None => Rgb::ZERO,
        }
    }

    /// The light a ray from `si` along `wi` meets (through thin panes, as the light samples'
    /// visibility rays go), each source's radiance times `weight` of it.
    fn light_along(
        &self,
        si: &SurfaceInteraction,
        wi: Vec3,
        rays: &mut RayCounters,
        weight: impl Fn(Source) -> f32,
    ) -> Rgb {
        let scene = self.scene;
        let lights = &scene.lights;
        rays.bounce += 1;
        let (tr, beyond) = scene.through_glass(Ray::new(si.spawn(wi), wi), f32::INFINITY);
        let found = match beyond {
            None => lights.environments.iter().fold(Rgb::ZERO, |acc, &e| {
                let le = lights.lights[e].le(LightHit::Escaped, wi);
                acc + le * weight(Source::Environment(e))
            }),
            Some(hit) => match lights.surface_emission(&hit, wi) {
                Some((light, le)) if !le.is_black() => le * weight(Source::Surface(light, &hit)),
                _ => Rgb::ZERO,
            },
        };
        tr * found
    }

    /// Solid-angle density with which a light sample of the pass at point `q`'s hit at `p`
    /// gives direction `wi` towards `source`.
    fn source_density(
        &self,
        (q, p): (&Point, Vec3),
        pass: PassPdf,
        wi: Vec3,
        source: Source,
    ) -> f32 {
        match source {
            Source::Environment(e) => self.environment_pdf((q, p), pass, e, wi),
            Source::Surface(light, si) => {
                let scene = self.scene;
                self.cluster_share(q, pass, self.forest.leaf_of[light])
                    * scene.lights.lights[light].pdf_li(&scene.scene, p, wi, LightHit::Surface(si))
            }
        }
    }

    /// The probability that a light sample of the pass at `q` picks the light at forest leaf
    /// `leaf`: its cluster's in the cut, times its share of the cluster by power.
    fn cluster_share(&self, q: &Point, pass: PassPdf, leaf: u32) -> f32 {
        if leaf == NO_PARENT {
            return 0.0;
        }
        let (mut node, mut share) = (leaf, 1.0);
        loop {
            if let Some(p) = pass.of(q, node) {
                return p * share;
            }
            let Some((parent, s)) = self.forest.up(node) else {
                return 0.0;
            };
            node = parent;
            share *= s;
        }
    }

    /// Solid-angle density with which a light sample of the pass at `q` gives direction `wi`
    /// of environment `light`: its region's probability over the region's solid angle, or
    /// the environment's own density where it is one cluster.
    fn environment_pdf(
        &self,
        (q, p): (&Point, Vec3),
        pass: PassPdf,
        light: usize,
        wi: Vec3,
    ) -> f32 {
        let first_far = self.forest.nodes.len() as u32;
        let angles = polar(wi);
        for (k, far) in self.far.iter().enumerate() {
            let node = first_far + k as u32;
            match far {
                Far::Region(r) if r.light == light && r.holds(angles) => {
                    return pass.of(q, node).unwrap_or(0.0) / r.solid_angle();
                }
                Far::Light(l) if *l == light => {
                    let scene = self.scene;
                    let p =
                        scene.lights.lights[light].pdf_li(&scene.scene, p, wi, LightHit::Escaped);
                    return pass.of(q, node).unwrap_or(0.0) * p;
                }
                _ => {}
            }
        }
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ias::{Ias, IasOptions};
    use fenestra_core::Rng;
    use fenestra_render::integrator::Integrator;
    use fenestra_render::{RenderControl, RenderScene};
    use fenestra_scene::light::{Emission, EnvironmentDesc};
    use fenestra_scene::{
        Backend, Camera, LightDesc, Material, RenderDefaults, Scene, SceneDesc, Shape, ShapeKind,
        TriangleMesh,
    };
    use std::cell::Cell;

    /// A floor under a sky, a panel of 8 x 6 emitting tiles and two spheres.
    fn scene() -> RenderScene {
        let floor = TriangleMesh::quad(Vec3::ZERO, Vec3::X * 4.0, Vec3::Y * 4.0);
        let mut shapes = vec![Shape::new(ShapeKind::Mesh(floor), 0)];
        for i in 0..8 {
            for k in 0..6 {
                let c = Vec3::new(0.125 * i as f32, 1.5, 0.1 + 0.125 * k as f32);
                let tile = TriangleMesh::quad(c, Vec3::X * 0.0625, Vec3::Z * 0.0625);
                let glow = Emission::radiance(Rgb::splat(1.0 + (i + k) as f32));
                shapes.push(Shape::new(ShapeKind::Mesh(tile), 0).emitting(glow));
            }
        }
        for (x, r) in [(-1.0, 0.2), (1.5, 0.1)] {
            let ball = ShapeKind::Sphere {
                center: Vec3::new(x, 0.5, 1.0),
                radius: r,
            };
            shapes.push(Shape::new(ball, 0).emitting(Emission::radiance(Rgb::splat(2.0))));
        }
        let desc = SceneDesc {
            name: "tiles".into(),
            shapes,
            materials: vec![Material::diffuse(0.5)],
            lights: vec![LightDesc::Environment(EnvironmentDesc::Constant(
                Rgb::splat(0.3),
            ))],
            camera: Camera::look_at(Vec3::new(0.0, -3.0, 2.0), Vec3::ZERO, Vec3::Z, 60.0)
                .expect("camera"),
            defaults: RenderDefaults::default(),
            portals: Vec::new(),
        };
        RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("scene"))
    }

    #[test]
    fn a_bsdf_sample_reads_the_density_the_light_sample_had() {
        // MIS is unbiased only if the density a BSDF-sampled direction is weighed with is
        // the one the light technique samples it with: through the cluster of the cut, the
        // light's share of it by power, the light's own density, or a sky region's.
        let scene = scene();
        let mut ias = Ias::new(IasOptions {
            bsdf_samples: BsdfSamples::All,
            ..Default::default()
        })
        .expect("options");
        ias.prepare(&scene, &RenderControl::unattended())
            .expect("prepare");
        let forest = ias.forest.as_ref().expect("prepared");
        let block = BlockRender {
            options: &ias.options,
            sides: ias.sides,
            forest,
            far: &ias.far,
            scene: &scene,
            seed: 3,
            width: 16,
            height: 16,
            threshold: 1e-3,
            trace: None,
        };
        let mut rays = RayCounters::default();
        let mut rng = Rng::new(11);
        let (mut checked, mut regions) = (0, 0);
        for (x, y) in [(8, 8), (3, 12), (12, 10), (8, 14)] {
            let pixel = block.pixel_points((x, y), 0, &mut rays);
            for q in &pixel.points {
                assert!(!q.lookup.is_empty(), "every point takes BSDF samples");
                let pdf: Vec<f32> = q.cut.iter().map(|_| 0.1 + rng.next_f32()).collect();
                let cdf: Vec<f32> = pdf
                    .iter()
                    .scan(0.0, |acc, &w| {
                        *acc += w;
                        Some(*acc)
                    })
                    .collect();
                let pass = PassPdf {
                    pdf: &pdf,
                    total: cdf[cdf.len() - 1],
                };
                for i in 0..400 {
                    let mut sampler = Sampler::new(3, u64::from(y * 16 + x), i);
                    let at = &q.hits[i as usize % q.hits.len()];
                    let s = block.sample(q, at, &pdf, &cdf, &mut sampler, &mut rays);
                    if !s.visible || s.density == 0.0 {
                        continue;
                    }
                    let (found, sky) = (Cell::new(None), Cell::new(false));
                    block.light_along(&at.si, s.wi, &mut rays, |source| {
                        sky.set(matches!(source, Source::Environment(_)));
                        found.set(Some(block.source_density((q, at.si.p), pass, s.wi, source)));
                        1.0
                    });
                    let found = found.get().expect("the visible light is met");
                    regions += usize::from(sky.get());
                    assert!(
                        (found - s.density).abs() <= 1e-3 * s.density,
                        "sampled with density {}, read back {found}",
                        s.density
                    );
                    checked += 1;
                }
            }
        }
        assert!(
            checked > 1000 && regions > 50,
            "{checked} samples, {regions} of the sky"
        );
    }
}
