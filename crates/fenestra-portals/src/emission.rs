//! Where on the portals light paths start (issue 66 item 4). Uniform over the portals' area
//! projected along the sun's direction, most lines land where the path tracer's next-event
//! samples already do well (a sunlit floor), and MIS gives their light back to it; the light
//! paths that pay are the few whose lines meet a glossy surface. Before rendering, a pilot of
//! light paths drawn uniformly records the light each brought to the camera after its MIS
//! weights, summed per cell of its portal's unit square; the render's light paths then start
//! from the mixture of [`UNIFORM_SHARE`] of the uniform density and the rest by that
//! histogram (a portal by its share of the pilot's light, a cell by its share of the
//! portal's, a point uniformly in it), so that no point of a portal loses more than that share
//! of its density: the worst a poor pilot can do is 1 / [`UNIFORM_SHARE`] times the variance.

use crate::portal::Portal;
use fenestra_core::distribution::{Distribution1D, Distribution2D};
use fenestra_core::Vec2;

/// The uniform density's share of the mixture.
pub const UNIFORM_SHARE: f32 = 0.25;

/// Cells of a portal's histogram (about; a quad's are about square).
const CELLS: usize = 256;

/// One sun's learned density over its portals' unit squares.
#[derive(Clone, Debug)]
pub struct Emission {
    /// Picks a portal by its share of the pilot's light.
    pick: Distribution1D,
    /// Each portal's density over its unit square.
    cells: Vec<Distribution2D>,
}

impl Emission {
    /// The learned density's pick of a portal and a point of its unit square from `u_pick`
    /// and `u`: (portal, point).
    pub fn sample(&self, u_pick: f32, u: Vec2) -> (usize, Vec2) {
        let (portal, _, _) = self.pick.sample_discrete(u_pick);
        (portal, self.cells[portal].sample(u).0)
    }

    /// The learned density of `portal`'s point `unit` of its unit square (per unit of that
    /// square, times the portal's pick probability).
    pub fn density(&self, portal: usize, unit: Vec2) -> f32 {
        self.pick.discrete_pmf(portal) * self.cells[portal].pdf(unit)
    }
}

/// One portal's histogram: its grid and its cells' sums.
#[derive(Clone, Debug)]
struct Cells {
    /// Columns, rows.
    grid: (usize, usize),
    /// The cells' sums, row-major.
    sums: Vec<f64>,
}

/// The pilot's light, summed per sun, portal and cell.
#[derive(Clone, Debug)]
pub struct Tally {
    /// Per sun, per portal.
    suns: Vec<Vec<Cells>>,
    /// Light paths that brought any light.
    pub contributing: u64,
}

impl Tally {
    /// Empty sums for suns whose portals are `portals` (per sun).
    pub fn new<'a>(portals: impl Iterator<Item = &'a [Portal]>) -> Self {
        let suns = portals
            .map(|ps| {
                (ps.iter())
                    .map(|p| {
                        let grid = grid(p);
                        let sums = vec![0.0; grid.0 * grid.1];
                        Cells { grid, sums }
                    })
                    .collect()
            })
            .collect();
        Tally {
            suns,
            contributing: 0,
        }
    }

    /// Adds `light` brought by a light path of sun `sun` that started at `unit` of `portal`.
    pub fn add(&mut self, sun: usize, portal: usize, unit: Vec2, light: f64) {
        if !(light > 0.0) || !light.is_finite() {
            return;
        }
        let cells = &mut self.suns[sun][portal];
        let (w, h) = cells.grid;
        let x = ((unit.x * w as f32) as usize).min(w - 1);
        let y = ((unit.y * h as f32) as usize).min(h - 1);
        cells.sums[y * w + x] += light;
        self.contributing += 1;
    }

    /// Each sun's learned density: `None` for a sun none of whose pilot paths brought light
    /// (it keeps the uniform density).
    pub fn emissions(&self) -> Vec<Option<Emission>> {
        (self.suns.iter())
            .map(|portals| {
                let totals: Vec<f32> = (portals.iter())
                    .map(|c| c.sums.iter().sum::<f64>() as f32)
                    .collect();
                (totals.iter().any(|&t| t > 0.0)).then(|| Emission {
                    pick: Distribution1D::new(&totals),
                    cells: (portals.iter())
                        .map(|c| {
                            let f: Vec<f32> = c.sums.iter().map(|&s| s as f32).collect();
                            Distribution2D::new(&f, c.grid.0, c.grid.1)
                        })
                        .collect(),
                })
            })
            .collect()
    }
}

/// A portal's histogram grid (columns along its unit square's x, rows along y): about
/// [`CELLS`] cells, about square on a quad.
fn grid(portal: &Portal) -> (usize, usize) {
    let side = (CELLS as f32).sqrt();
    match portal {
        Portal::Quad { e1, e2, .. } => {
            let ratio = (e1.length() / e2.length()).clamp(1.0 / CELLS as f32, CELLS as f32);
            let w = (side * ratio.sqrt()).round().clamp(1.0, CELLS as f32) as usize;
            (w, (CELLS / w).max(1))
        }
        _ => (side as usize, side as usize),
    }
}
