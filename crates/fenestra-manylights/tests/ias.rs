//! `ias` against af_hf: the same image (direct light) within the standard errors both report,
//! with the shared-weight combination; the same pixels on one thread as on two.

mod common;

use common::{bvh_af_hf, many_lights, render};
use fenestra_manylights::ias::Combine;
use fenestra_manylights::{Ias, IasOptions};
use fenestra_render::integrator::PathOptions;

fn ias(combine: Combine) -> Ias {
    Ias::new(IasOptions {
        combine,
        ..Default::default()
    })
    .expect("options")
}

#[test]
fn ias_renders_the_direct_light_af_hf_renders() {
    let direct = PathOptions {
        max_depth: 2,
        ..Default::default()
    };
    let reference = render(many_lights(), &mut bvh_af_hf(direct), 1024, 2);
    let adaptive = render(many_lights(), &mut ias(Combine::Samples), 1, 2);
    let t = fenestra_eval::agreement(&reference.estimate(), &adaptive.estimate(), 0.01, 8)
        .expect("sizes");
    assert!(t.passed(), "{t:?}");
}

#[test]
fn the_seeds_reference_renders_the_same_direct_light() {
    let direct = PathOptions {
        max_depth: 2,
        ..Default::default()
    };
    let reference = render(many_lights(), &mut bvh_af_hf(direct), 1024, 2);
    let mut seeds = Ias::new(IasOptions::reference(1e-3)).expect("options");
    let image = render(many_lights(), &mut seeds, 1, 2);
    let t =
        fenestra_eval::agreement(&reference.estimate(), &image.estimate(), 0.01, 8).expect("sizes");
    assert!(t.passed(), "{t:?}");
    let again = render(many_lights(), &mut seeds, 1, 1);
    assert_eq!(image.estimate().mean.pixels, again.estimate().mean.pixels);
}

#[test]
fn ias_gives_the_same_pixels_on_one_thread_as_on_two() {
    for combine in [Combine::Samples, Combine::InverseVariance] {
        let one = render(many_lights(), &mut ias(combine), 1, 1);
        let two = render(many_lights(), &mut ias(combine), 1, 2);
        assert_eq!(one.estimate().mean.pixels, two.estimate().mean.pixels);
        assert_eq!(
            one.estimate().variance.pixels,
            two.estimate().variance.pixels
        );
    }
}
