//! The learned sampler's cells, groups and picks.

use super::cells::{grid_for, halves, Sum};
use super::groups::pick_within;
use super::*;
use fenestra_render::options::Options;

/// Sums of `groups(cell)` groups in each of `cells`, group g weighing 1 + g, with
/// `samples` samples each.
fn sums_of(cells: &[u64], groups: impl Fn(u64) -> u32, samples: u32) -> Vec<Sum> {
    let mut sums: Vec<Sum> = cells
        .iter()
        .flat_map(|&key| {
            (0..groups(key)).map(move |group| Sum {
                key,
                group,
                weight: 1.0 + group as f64,
                samples,
            })
        })
        .collect();
    sums.sort_by_key(|s| (s.key, s.group));
    sums
}

#[test]
fn tables_find_every_cell_they_learned_and_no_other() {
    let cells: Vec<u64> = (0..300u64).map(|c| c * 7919).collect();
    let groups = |key: u64| ((key / 7919) % 5) as u32;
    let table = Table::new(Grid::default(), &sums_of(&cells, groups, 1), 1);
    for &key in &cells {
        let found = table.cell(key);
        let groups = groups(key);
        if groups == 0 {
            assert!(found.is_none());
            continue;
        }
        let entries = found.expect("a learned cell");
        let total: f64 = (0..groups).map(|g| 1.0 + g as f64).sum();
        for g in 0..groups {
            let p = groups_pmf(entries, (g, g + 1));
            assert!((f64::from(p) - (1.0 + g as f64) / total).abs() < 1e-6);
            // Picking at the middle of its interval gives the group back.
            let mid = entries[g as usize].1 - p / 2.0;
            assert_eq!(pick_within(entries, 0.0, mid).0, g);
        }
        assert_eq!(groups_pmf(entries, (groups, groups + 1)), 0.0);
    }
    assert!(table.cell(12345).is_none());
}

#[test]
fn points_take_the_finest_cell_that_learned_enough() {
    let grid = Grid {
        lo: Vec3::ZERO,
        inv_size: 1.0,
    };
    // Two points in one box of the grid, in different half boxes.
    let (a, b) = (Vec3::splat(0.25), Vec3::splat(0.75));
    let coarse = grid.key(a, Vec3::Z, 0);
    assert_eq!(coarse, grid.key(b, Vec3::Z, 0));
    let (fine_a, fine_b) = (grid.key(a, Vec3::Z, 1), grid.key(b, Vec3::Z, 1));
    assert_ne!(fine_a, fine_b);
    // The box learned group 0 from 19 samples, a's half box group 1 from 5, b's group 2
    // from 3.
    let mut sums = sums_of(&[coarse], |_| 1, 19);
    sums.extend(sums_of(&[fine_a], |_| 2, 5).into_iter().skip(1));
    sums.extend(sums_of(&[fine_b], |_| 3, 3).into_iter().skip(2));
    sums.sort_by_key(|s| (s.key, s.group));
    let table = Table::new(grid, &sums, 4);
    let groups = |p: Vec3| table.at(p, Vec3::Z).expect("learned").iter().map(|e| e.0);
    assert!(groups(a).eq([1]), "a's half box has 5 samples of 4 needed");
    assert!(groups(b).eq([0]), "b's has 3, so b takes the box");
    assert!(groups(Vec3::new(0.75, 0.25, 0.25)).eq([0]));
}

#[test]
fn a_box_has_the_half_boxes_of_its_points() {
    let grid = Grid {
        lo: Vec3::new(-3.0, -1.0, 2.0),
        inv_size: 0.7,
    };
    let mut rng = fenestra_core::Rng::new(7);
    for _ in 0..2000 {
        let p = grid.lo + Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 40.0;
        let n = fenestra_core::warp::square_to_uniform_sphere(rng.next_2d());
        let halves = halves(grid.key(p, n, 0));
        assert!(halves.contains(&grid.key(p, n, 1)), "{p} {n}");
        // ... and no other box's, nor another normal direction's.
        assert!(!halves.contains(&grid.key(p + Vec3::X / grid.inv_size, n, 1)));
        assert!(!halves.contains(&grid.key(p, -n, 1)));
    }
}

#[test]
fn cells_tell_normals_and_boxes_apart() {
    let grid = Grid {
        lo: Vec3::ZERO,
        inv_size: 2.0,
    };
    let p = Vec3::new(0.3, 0.3, 0.3);
    let key = |p, n| grid.key(p, n, 0);
    assert_ne!(key(p, Vec3::Z), key(p, -Vec3::Z));
    assert_ne!(key(p, Vec3::Z), key(p, Vec3::X));
    assert_eq!(key(p, Vec3::Z), key(p + Vec3::splat(0.1), Vec3::Z));
    assert_ne!(key(p, Vec3::Z), key(p + Vec3::splat(0.3), Vec3::Z));
    // The next level halves the boxes (0.2 and 0.3 share a box of 1/2, not of 1/4),
    // and its cells are its own.
    let q = p - Vec3::splat(0.1);
    assert_eq!(key(p, Vec3::Z), key(q, Vec3::Z));
    assert_ne!(grid.key(p, Vec3::Z, 1), grid.key(q, Vec3::Z, 1));
    assert_ne!(grid.key(p, Vec3::Z, 1), key(p, Vec3::Z));
}

#[test]
fn cells_are_as_fine_as_the_records_allow() {
    // 4,096 points on a floor of side 1 facing up: 2^k cells a side hold 4096 / 4^k.
    let points: Vec<(Vec3, Vec3)> = (0..4096)
        .map(|i| {
            let (x, y) = ((i % 64) as f32 + 0.5, (i / 64) as f32 + 0.5);
            (Vec3::new(x / 64.0, y / 64.0, 0.0), Vec3::Z)
        })
        .collect();
    let side = |g: Grid| g.inv_size.recip();
    // Diagonal 1: boxes of 1/2^k. 16 a cell: 256 cells, 1/16 a side.
    let g = grid_for(&points, Vec3::ZERO, 1.0, 16);
    assert_eq!(side(g), 1.0 / 16.0);
    let g = grid_for(&points, Vec3::ZERO, 1.0, 64);
    assert_eq!(side(g), 1.0 / 8.0);
    // Fewer points than one cell wants (the first ten, x up to 0.15): the finest grid
    // that keeps them in one cell.
    let g = grid_for(&points[..10], Vec3::ZERO, 1.0, 64);
    assert_eq!(side(g), 0.25);
}

#[test]
fn options_that_could_bias_or_mean_nothing_are_refused() {
    let ok = LearnedOptions::default();
    assert!(ok.check().is_ok());
    let e = LearnedOptions { mix: 1.0, ..ok }
        .check()
        .expect_err("a mix of 1 leaves no light tree");
    assert!(e.to_string().starts_with("learned.mix must be"), "{e}");
    assert!(LearnedOptions {
        cell_records: 0,
        ..ok
    }
    .check()
    .is_err());
    assert!(LearnedOptions { groups: 0, ..ok }.check().is_err());
    assert!(LearnedOptions {
        passes: u32::MAX,
        ..ok
    }
    .check()
    .is_err());
}
