//! The promises of seed 003 ch. 3: SortCluster-LPCA gives exactly LPCA's assignments,
//! SortMeans exactly Lloyd's, SortMeans++ exactly k-means++'s seeding, each with fewer
//! distance evaluations; and the approximation error falls as the subspaces grow.

use fenestra_lpca::init::{seed, Init};
use fenestra_lpca::synthetic::{btf_like, subspace_mixture};
use fenestra_lpca::{run, Algorithm, Dataset, Options, Schedule};

fn options(k: usize, schedule: &str, algorithm: Algorithm, init: Init) -> Options {
    Options {
        clusters: k,
        schedule: Schedule::parse(schedule).expect("schedule"),
        algorithm,
        init,
        seed: 42,
    }
}

fn assert_same(data: &Dataset, k: usize, schedule: &str, init: Init) {
    let a = run(data, &options(k, schedule, Algorithm::Lpca, init)).expect("lpca");
    let b = run(data, &options(k, schedule, Algorithm::ScLpca, init)).expect("sc-lpca");
    assert_eq!(
        a.assignments, b.assignments,
        "{schedule} {init:?}: assignments differ"
    );
    assert_eq!(a.models, b.models, "{schedule} {init:?}: models differ");
    assert_eq!(a.phi, b.phi);
    for (x, y) in a.iterations.iter().zip(&b.iterations) {
        assert_eq!(x.phi, y.phi, "iteration by iteration");
    }
    assert!(
        b.distance_evals < a.distance_evals,
        "{schedule} {init:?}: SC-LPCA evaluated {} distances, LPCA {}",
        b.distance_evals,
        a.distance_evals
    );
}

#[test]
fn sc_lpca_gives_exactly_the_lpca_assignments() {
    let mixture = subspace_mixture(1200, 24, 10, 3, 0.05, 1);
    for init in [
        Init::Random,
        Init::DistanceSum,
        Init::KmeansPlusPlus,
        Init::SortMeansPlusPlus,
    ] {
        assert_same(&mixture, 10, "0:4,1:3,2:3,4:2", init);
    }
    let btf = btf_like(24, 8, 8, 6, 4, 0.01, 2);
    assert_same(&btf, 12, "0:5,2:3,4:3,8:2", Init::SortMeansPlusPlus);
    assert_same(&btf, 3, "(0:3),(8:4)", Init::Random);
}

#[test]
fn sortmeans_gives_exactly_lloyds_clustering() {
    let data = subspace_mixture(2000, 16, 20, 0, 0.3, 3);
    assert_same(&data, 20, "0:15", Init::Random);
    assert_same(&data, 7, "0:10", Init::KmeansPlusPlus);
}

#[test]
fn sortmeans_plus_plus_seeds_exactly_like_kmeans_plus_plus() {
    let data = subspace_mixture(3000, 12, 30, 1, 0.1, 4);
    for s in 0..3 {
        let a = seed(&data, 30, Init::KmeansPlusPlus, s);
        let b = seed(&data, 30, Init::SortMeansPlusPlus, s);
        assert_eq!(a.centroids, b.centroids);
        let (aa, ad) = a.assignment.expect("k-means++ assigns");
        let (ba, bd) = b.assignment.expect("SortMeans++ assigns");
        assert_eq!((aa, ad), (ba, bd));
        assert!(
            b.distance_evals < a.distance_evals,
            "{} vs {}",
            b.distance_evals,
            a.distance_evals
        );
    }
}

#[test]
fn error_falls_as_the_subspaces_grow() {
    let data = btf_like(20, 8, 8, 4, 6, 0.005, 5);
    let errors: Vec<f64> = [0usize, 1, 2, 4, 6]
        .iter()
        .map(|&l| {
            let schedule = if l == 0 {
                "0:8".to_string()
            } else {
                format!("0:8,{l}:4")
            };
            run(
                &data,
                &options(4, &schedule, Algorithm::ScLpca, Init::SortMeansPlusPlus),
            )
            .expect("run")
            .relative_squared_error
        })
        .collect();
    assert!(errors.windows(2).all(|w| w[1] < w[0]), "{errors:?}");
    // With the generating dimension the residual is the noise alone.
    assert!(errors[4] < 1e-3, "{errors:?}");
}

#[test]
fn bad_options_are_refused() {
    let data = subspace_mixture(50, 4, 2, 1, 0.1, 6);
    assert!(run(&data, &options(0, "0:2", Algorithm::Lpca, Init::Random)).is_err());
    assert!(run(&data, &options(51, "0:2", Algorithm::Lpca, Init::Random)).is_err());
    let e = run(&data, &options(2, "0:2,4:1", Algorithm::Lpca, Init::Random)).unwrap_err();
    assert!(e.to_string().contains("below the data dimension 4"), "{e}");
}

#[test]
fn npy_round_trip_and_bad_files() {
    let dir = std::env::temp_dir().join(format!("fenestra-lpca-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let data = subspace_mixture(40, 5, 2, 1, 0.1, 7);
    let p = dir.join("x.npy");
    fenestra_lpca::io::write_npy(&p, &[40, 5], data.values.iter().copied()).expect("write");
    let back = fenestra_lpca::io::read_matrix(&p).expect("read");
    assert_eq!((back.n, back.d), (40, 5));
    assert_eq!(back.values, data.values);
    let p64 = dir.join("x64.npy");
    fenestra_lpca::io::write_npy(&p64, &[40, 5], data.values.iter().map(|&v| v as f64))
        .expect("write");
    assert_eq!(
        fenestra_lpca::io::read_matrix(&p64).expect("f64").values,
        data.values
    );
    let p1 = dir.join("one.npy");
    fenestra_lpca::io::write_npy(&p1, &[5], [1.0f32; 5]).expect("write");
    assert!(fenestra_lpca::io::read_matrix(&p1)
        .unwrap_err()
        .to_string()
        .contains("expected a 2D matrix"));
    let pi = dir.join("int.npy");
    fenestra_lpca::io::write_npy(&pi, &[2, 2], [1i32; 4]).expect("write");
    assert!(fenestra_lpca::io::read_matrix(&pi)
        .unwrap_err()
        .to_string()
        .contains("unsupported element type"));
    // A header claiming more values than the file holds (its product overflows usize).
    let dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (4611686018427387904, 4), }";
    let mut header = dict.to_string();
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend((header.len() as u16).to_le_bytes());
    bytes.extend(header.as_bytes());
    bytes.extend([0u8; 64]);
    std::fs::write(dir.join("huge.npy"), &bytes).expect("write");
    let e = fenestra_lpca::io::read_matrix(&dir.join("huge.npy"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("the header claims"), "{e}");
    std::fs::write(dir.join("junk.npy"), b"not numpy").expect("write");
    assert!(fenestra_lpca::io::read_matrix(&dir.join("junk.npy"))
        .unwrap_err()
        .to_string()
        .contains("not a NumPy"));
}
