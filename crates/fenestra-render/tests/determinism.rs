//! An image does not depend on the number of threads: same seed, same pixels, bit for bit.

mod common;

use common::integrator;
use fenestra_builtin as builtin;
use fenestra_render::integrator::PathOptions;

fn sums_with_threads(threads: usize, name: &str) -> Vec<[i128; 3]> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| {
        let (film, _) = common::render(
            builtin::load("box-4holes").expect("builtin"),
            integrator(name, PathOptions::default()).as_mut(),
            // Not a multiple of the 8-pixel blocks: partial blocks at the edges.
            20,
            16,
            5,
        );
        film.pixels.iter().map(|p| p.sum).collect()
    })
}

#[test]
fn one_and_two_threads_give_identical_pixels() {
    for name in ["hf", "af_hf"] {
        let one = sums_with_threads(1, name);
        let two = sums_with_threads(2, name);
        assert!(one == two, "{name}");
        assert!(
            one.iter().any(|p| p[0] > 0),
            "{name}: the image is not black"
        );
    }
}

#[test]
fn another_seed_gives_another_image() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("pool");
    let render = |seed| {
        pool.install(|| {
            common::render(
                builtin::load("box-hole").expect("builtin"),
                integrator("af_hf", PathOptions::default()).as_mut(),
                8,
                4,
                seed,
            )
            .0
            .image()
        })
    };
    assert_ne!(render(1), render(2));
}
