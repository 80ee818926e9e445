//! Direct-to-indirect transfer (seed 003 §4.4.1-4.4.3) and relighting with it (§4.6).
//!
//! The transfer from gather sample g to a view point v is eq. 4.1, A(g) f_r(v -> g) G(v, g)
//! V(v, g) (G with the disk form factor's bounded 1 / (r^2 + A / pi), see [`elements`]), with
//! f_r's luminance (the point's colour, f_r(w_o, n) over its luminance, is
//! applied when relighting: exact for BRDFs whose colour does not change with direction).
//! [`transfer`] evaluates it by Hasan et al.'s N-body traversal of the gather tree: a subtree
//! that is small from v (its area over the squared distance to its bounds below a threshold)
//! takes one gather sample's value, with one visibility ray, for all its samples.
//!
//! Relighting: the gather samples' radiosity B = albedo / pi * E, E their direct irradiance
//! from the lights; a view point's one-bounce indirect radiance is colour * sum_j x_j B_j.

use crate::gather::{Gather, GatherSample};
use crate::neighbours::PointTree;
use fenestra_core::ray::{offset_distance, offset_origin};
use fenestra_core::{warp, Frame, Ray, Rgb, Sampler, Vec2, Vec3};
use fenestra_render::bsdf::Bsdf;
use fenestra_render::light::Light;
use fenestra_render::RenderScene;
use fenestra_scene::{SurfaceInteraction, PACKET};

/// A point seen by the camera, for its transfer.
pub struct ViewPoint<'a> {
    /// The surface point.
    pub si: &'a SurfaceInteraction,
    /// Its BSDF.
    pub bsdf: &'a Bsdf,
    /// Towards the camera (world, unit).
    pub wo: Vec3,
}

impl ViewPoint<'_> {
    /// The colour its BSDF gives reflected light: f_r(w_o, n) over its luminance.
    pub fn colour(&self) -> Rgb {
        let frame = self.si.shading_frame();
        let wo = frame.to_local(self.wo);
        let n = Vec3::new(0.0, 0.0, wo.z.signum());
        let f = self.bsdf.eval(wo, n);
        let y = f.luminance();
        if y > 0.0 {
            f * (1.0 / y)
        } else {
            Rgb::ZERO
        }
    }
}

/// What eq. 4.1 needs of a view point, made once for all its elements.
struct Receiver<'a> {
    v: &'a ViewPoint<'a>,
    frame: &'a Frame,
    /// w_o in the shading frame.
    wo: Vec3,
    /// The side of the geometric normal w_o is on (elements from the other side are zero).
    side: f32,
    /// Where visibility rays start: every ray that counts leaves on w_o's side, so from one
    /// offset origin.
    origin: Vec3,
}

impl Receiver<'_> {
    /// Eq. 4.1 from `g` but for the visibility term, with the visibility ray and its length;
    /// `None` where the element is zero whatever lies between.
    fn unoccluded(&self, g: &GatherSample) -> Option<(f64, Ray, f32)> {
        let d = g.p - self.v.si.p;
        let dist2 = d.length_squared();
        if dist2 <= 0.0 {
            return None;
        }
        let w = d / dist2.sqrt();
        let cos_g = w.dot(g.n).abs();
        let wi = self.frame.to_local(w);
        if cos_g <= 0.0 || wi.z * self.wo.z <= 0.0 || w.dot(self.v.si.ng) * self.side <= 0.0 {
            return None;
        }
        let f = self.v.bsdf.eval(self.wo, wi).luminance();
        if f <= 0.0 {
            return None;
        }
        let to = g.p - self.origin;
        let reach = to.length();
        // The form factor of a disk of the sample's area (Wallace et al. 1989), A cos cos /
        // (pi r^2 + A), in place of the point's A cos cos / (pi r^2): the same far away,
        // bounded by 1 near, where a gather sample beside the view point would otherwise make
        // a spike that no cluster's subspace represents (and that projects to negative light
        // elsewhere).
        let pi = std::f32::consts::PI;
        let value = (g.area * f * wi.z.abs() * cos_g * pi / (pi * dist2 + g.area)) as f64;
        Some((
            value,
            Ray::new(self.origin, to / reach),
            reach * (1.0 - 1e-3),
        ))
    }
}

/// Eq. 4.1 from each of `samples` to `v` (`frame` v's shading frame), their visibility rays
/// traced in packets of eight (one origin, so coherent: Embree's packet queries answer them
/// faster than one at a time); adds the rays traced to `rays`.
pub fn elements<'g>(
    scene: &RenderScene,
    v: &ViewPoint,
    frame: &Frame,
    samples: impl Iterator<Item = &'g GatherSample>,
    rays: &mut u64,
) -> Vec<f64> {
    let receiver = Receiver {
        v,
        frame,
        wo: frame.to_local(v.wo),
        side: v.wo.dot(v.si.ng),
        origin: v.si.spawn(v.wo),
    };
    let mut values = Vec::new();
    let mut pending: Vec<(usize, Ray, f32)> = Vec::new();
    for g in samples {
        if let Some((value, ray, reach)) = receiver.unoccluded(g) {
            pending.push((values.len(), ray, reach));
            values.push(value);
        } else {
            values.push(0.0);
        }
    }
    *rays += pending.len() as u64;
    for packet in pending.chunks(PACKET) {
        // A short last packet repeats its last ray.
        let lane = |i: usize| &packet[i.min(packet.len() - 1)];
        let blocked = (scene.scene).occluded8(
            &std::array::from_fn(|i| lane(i).1),
            std::array::from_fn(|i| lane(i).2),
        );
        for (&(at, _, _), blocked) in packet.iter().zip(blocked) {
            if blocked {
                values[at] = 0.0;
            }
        }
    }
    values
}

/// The transfer vector of `v` by the N-body traversal (subtrees whose area over the squared
/// distance to their bounds is below `threshold` take one sample's value), and the
/// visibility rays it took.
pub fn transfer(
    scene: &RenderScene,
    gather: &Gather,
    v: &ViewPoint,
    threshold: f32,
) -> (Vec<f64>, u64) {
    let mut x = vec![0.0; gather.samples.len()];
    let mut rays = 0;
    if gather.nodes.is_empty() {
        return (x, rays);
    }
    // The nodes where the traversal stops (their samples' range), then their
    // representatives' elements at once.
    let mut stops = Vec::new();
    let mut stack = vec![0u32];
    while let Some(n) = stack.pop() {
        let node = &gather.nodes[n as usize];
        let nearest = v.si.p.clamp(node.min, node.max);
        let dist2 = nearest.distance_squared(v.si.p);
        let small = dist2 > 0.0 && node.area / dist2 < threshold;
        if node.children == [0, 0] || small {
            stops.push((node.lo as usize, node.hi as usize));
        } else {
            stack.extend(node.children);
        }
    }
    let rep = |&(lo, hi): &(usize, usize)| &gather.samples[(lo + hi) / 2];
    let frame = v.si.shading_frame();
    let values = elements(scene, v, &frame, stops.iter().map(rep), &mut rays);
    // Most stops are hidden or face away: their samples stay zero.
    for (stop, value) in stops.iter().zip(values).filter(|(_, v)| *v != 0.0) {
        let (lo, hi) = *stop;
        let area = rep(stop).area;
        for (xj, g) in x[lo..hi].iter_mut().zip(&gather.samples[lo..hi]) {
            *xj = value * (g.area / area) as f64;
        }
    }
    (x, rays)
}

/// The transfer vector of `v` by Monte Carlo, the alternative to the N-body traversal the
/// issue compares against: `rays` cosine-weighted rays (stream `sampler`); each that hits a
/// surface credits the gather sample whose patch it lands in ([`Gather::owner`], `near` from
/// [`Gather::points`]) with f pi / rays, so that sum_j x_j B_j estimates the one-bounce light.
/// The near field is integrated by the rays, not by the gather samples' positions.
pub fn monte_carlo(
    scene: &RenderScene,
    gather: &Gather,
    near: &PointTree,
    v: &ViewPoint,
    rays: u32,
    sampler: &mut Sampler,
) -> Vec<f64> {
    let mut x = vec![0.0; gather.samples.len()];
    let frame = v.si.shading_frame();
    let wo = frame.to_local(v.wo);
    let side = if wo.z < 0.0 { -1.0 } else { 1.0 };
    let mut found = Vec::new();
    for _ in 0..rays {
        let local =
            warp::square_to_cosine_hemisphere(sampler.next_2d()) * Vec3::new(1.0, 1.0, side);
        let w = frame.to_world(local);
        if w.dot(v.si.ng) * v.wo.dot(v.si.ng) <= 0.0 {
            continue;
        }
        let ray = Ray::new(v.si.spawn(w), w);
        let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
            continue;
        };
        let h = scene.scene.interaction(&ray, &hit);
        if let Some(j) = gather.owner(near, h.p, h.ng, hit.shape, &mut found) {
            let f = v.bsdf.eval(wo, local).luminance();
            x[j as usize] += (f * std::f32::consts::PI / rays as f32) as f64;
        }
    }
    x
}

/// The transfer vector of `v` with every element evaluated (the reference for the N-body
/// traversal).
pub fn brute_force(scene: &RenderScene, gather: &Gather, v: &ViewPoint) -> Vec<f64> {
    let frame = v.si.shading_frame();
    elements(scene, v, &frame, gather.samples.iter(), &mut 0)
}

/// Direct irradiance at `p` on both sides of the surface of normal `n` (summed), from every
/// light with `samples` light samples
/// each (stream `sampler`).
pub fn irradiance(
    scene: &RenderScene,
    p: Vec3,
    n: Vec3,
    samples: u32,
    sampler: &mut Sampler,
) -> Rgb {
    direct(scene, p, n, samples, sampler, |wi| {
        let cos = wi.dot(n).abs();
        (cos > 0.0).then(|| Rgb::splat(cos))
    })
}

/// Direct light at `p` (geometric normal `ng`, for the shadow rays' offset): the sum over
/// every light, `samples` light samples each (one for Dirac lights, which is exact), of `weight(wi)` (the BSDF times the cosine, or
/// none where nothing is reflected) times the light's radiance over its density, unoccluded.
pub fn direct(
    scene: &RenderScene,
    p: Vec3,
    ng: Vec3,
    samples: u32,
    sampler: &mut Sampler,
    weight: impl Fn(Vec3) -> Option<Rgb>,
) -> Rgb {
    let mut e = Rgb::ZERO;
    let off = offset_distance(p.abs().max_element());
    for light in &scene.lights.lights {
        // Dirac lights ignore the sample point: no random numbers for them.
        let dirac = matches!(light, Light::Point(_) | Light::Spot(_) | Light::Distant(_));
        for _ in 0..samples {
            let u = if dirac {
                Vec2::splat(0.5)
            } else {
                sampler.next_2d()
            };
            let Some(ls) = light.sample_li(&scene.scene, p, u) else {
                continue;
            };
            // A Dirac light's one sample is exact: no more of it.
            let share = if ls.delta { 1.0 } else { 1.0 / samples as f32 };
            let usable = ls.pdf > 0.0;
            if let Some(w) = weight(ls.wi).filter(|_| usable) {
                let origin = offset_origin(p, ng, ls.wi, off);
                let reach = ls
                    .point
                    .map_or(f32::INFINITY, |q| (q - origin).length() * (1.0 - 1e-3));
                if !scene.scene.occluded(&Ray::new(origin, ls.wi), reach) {
                    e += w * ls.li * (share / ls.pdf);
                }
            }
            if ls.delta {
                break;
            }
        }
    }
    e
}

/// The gather samples' radiosity (albedo / pi * direct irradiance, `samples` light samples
/// per light).
pub fn radiosity(scene: &RenderScene, gather: &Gather, samples: u32, seed: u64) -> Vec<Rgb> {
    (gather.samples.iter().enumerate())
        .map(|(j, g)| {
            let mut sampler = Sampler::new(seed, j as u64, 0);
            g.albedo
                * irradiance(scene, g.p, g.n, samples, &mut sampler)
                * std::f32::consts::FRAC_1_PI
        })
        .collect()
}

/// One-bounce indirect radiance at a view point of colour `colour` and transfer `x`.
pub fn relit(colour: Rgb, x: &[f64], radiosity: &[Rgb]) -> Rgb {
    let (mut r, mut g, mut b) = (0.0f64, 0.0f64, 0.0f64);
    for (&w, l) in x.iter().zip(radiosity) {
        r += w * l.r as f64;
        g += w * l.g as f64;
        b += w * l.b as f64;
    }
    colour * Rgb::new(r as f32, g as f32, b as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::warp;
    use fenestra_scene::{Backend, Scene};

    fn cornell() -> RenderScene {
        let desc = fenestra_builtin::load("cornell-box").expect("scene");
        RenderScene::new(Scene::build(desc, Backend::Obvhs).expect("build"))
    }

    /// The surface a camera ray through pixel (x, y) of a `size`-square image finds.
    fn seen(scene: &RenderScene, x: f32, y: f32, size: u32) -> (SurfaceInteraction, Vec3) {
        let ray = scene
            .scene
            .camera
            .generate_ray(fenestra_core::Vec2::new(x, y), size, size);
        let hit = scene.scene.intersect(&ray, f32::INFINITY).expect("hit");
        (scene.scene.interaction(&ray, &hit), -ray.d)
    }

    #[test]
    fn relit_one_bounce_light_matches_a_monte_carlo_estimate() {
        let scene = cornell();
        let gather = Gather::new(&scene, 16_384, 1);
        let b = radiosity(&scene, &gather, 16, 2);
        for (px, py) in [(32.0, 52.0), (20.0, 30.0)] {
            let (si, wo) = seen(&scene, px, py, 64);
            let bsdf = scene.bsdf_at(&si);
            let v = ViewPoint {
                si: &si,
                bsdf: &bsdf,
                wo,
            };
            let (x, rays) = transfer(&scene, &gather, &v, 0.02);
            let exact = brute_force(&scene, &gather, &v);
            let (sx, se): (f64, f64) = (x.iter().sum(), exact.iter().sum());
            assert!(
                (sx - se).abs() < 0.03 * se,
                "N-body {sx} vs every sample {se}"
            );
            assert!(rays < gather.samples.len() as u64 / 4, "{rays} rays");
            let l = relit(v.colour(), &x, &b);
            let near = gather.points();
            let mc_x = monte_carlo(&scene, &gather, &near, &v, 4096, &mut Sampler::new(9, 0, 0));
            let l_mc = relit(v.colour(), &mc_x, &b);
            // Monte Carlo: cosine-weighted directions from v, the radiosity of what they hit.
            let frame = si.shading_frame();
            let up = if frame.to_local(wo).z < 0.0 {
                -1.0
            } else {
                1.0
            };
            let mut sampler = Sampler::new(5, 0, 0);
            let (mut sum, n) = (Rgb::ZERO, 4096u32);
            for k in 0..n {
                let mut s = Sampler::new(6, k as u64, 0);
                let local =
                    warp::square_to_cosine_hemisphere(s.next_2d()) * Vec3::new(1.0, 1.0, up);
                let w = frame.to_world(local);
                let ray = Ray::new(si.spawn(w), w);
                let Some(hit) = scene.scene.intersect(&ray, f32::INFINITY) else {
                    continue;
                };
                let h = scene.scene.interaction(&ray, &hit);
                if scene.scene.shapes[hit.shape as usize].emission.is_some() || h.ng.dot(w) >= 0.0 {
                    continue;
                }
                let albedo = match &*scene.bsdf_at(&h) {
                    Bsdf::Diffuse(d) => d.reflectance,
                    _ => Rgb::ZERO,
                };
                let e = irradiance(&scene, h.p, h.ng, 4, &mut sampler);
                let f_cos_pdf = bsdf.eval(frame.to_local(wo), local) * std::f32::consts::PI;
                sum += f_cos_pdf * albedo * e * std::f32::consts::FRAC_1_PI;
            }
            let mc = sum * (1.0 / n as f32);
            let (ly, my) = (l.luminance(), mc.luminance());
            assert!(
                (ly - my).abs() < 0.05 * my,
                "pixel ({px}, {py}): relit {ly} vs Monte Carlo {my}"
            );
            // The Monte Carlo transfer vector, relit, against the same estimate (its rays are
            // another stream; gather samples stand for what they hit).
            let ty = l_mc.luminance();
            assert!(
                (ty - my).abs() < 0.05 * my,
                "pixel ({px}, {py}): Monte Carlo transfer {ty} vs Monte Carlo {my}"
            );
        }
    }

    #[test]
    fn gather_samples_cover_the_surfaces_in_tree_order() {
        let scene = cornell();
        let gather = Gather::new(&scene, 1000, 3);
        assert_eq!(gather.samples.len(), 1000);
        let area: f32 = gather.samples.iter().map(|g| g.area).sum();
        let meshes: f32 = (scene.scene.shapes.iter())
            .filter(|s| s.emission.is_none())
            .map(|s| s.area())
            .sum();
        assert!((area - meshes).abs() < 1e-3 * meshes);
        // Every node's samples lie in its bounds and its children split its range.
        for node in &gather.nodes {
            for g in &gather.samples[node.lo as usize..node.hi as usize] {
                assert!(g.p.cmpge(node.min).all() && g.p.cmple(node.max).all());
            }
            if node.children != [0, 0] {
                let [l, r] = node.children.map(|c| gather.nodes[c as usize]);
                assert_eq!((l.lo, l.hi, r.lo, r.hi), (node.lo, r.lo, l.hi, node.hi));
            }
        }
    }
}
