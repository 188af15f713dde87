//! The rectangular contact grid (paper Fig. 2, docs/model.md §2): n × m cells over [−a, a] × [−b, b]; cells whose
//! centre lies inside the ellipse take part.

use super::hertz::HertzContact;

/// One active cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// Column index along x (0 at x = −a).
    pub i: usize,
    /// Row index along y (0 at y = −b).
    pub j: usize,
    /// Centre x [m].
    pub x: f64,
    /// Centre y [m].
    pub y: f64,
}

/// One strip of constant y: its cells in rolling order, from the leading edge x = +a(y) to the trailing edge.
#[derive(Debug, Clone, PartialEq)]
pub struct Strip {
    /// Row index.
    pub j: usize,
    /// Lateral position of the strip centre [m].
    pub y: f64,
    /// Half-length a(y) = a·sqrt(1 − y²/b²) of the strip inside the ellipse [m].
    pub half_length: f64,
    /// Range of indices into [`ContactGrid::cells`] (leading cell first).
    pub cells: std::ops::Range<usize>,
}

/// The grid of the contact ellipse.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactGrid {
    /// Semi-axis along x [m].
    pub a: f64,
    /// Semi-axis along y [m].
    pub b: f64,
    /// Number of columns along x.
    pub nx: usize,
    /// Number of rows along y.
    pub ny: usize,
    /// Cell length h_x = 2a/n [m].
    pub hx: f64,
    /// Cell width h_y = 2b/m [m].
    pub hy: f64,
    /// Active cells, strip by strip (j ascending), each strip from the leading edge backwards.
    pub cells: Vec<Cell>,
    /// Strips that contain at least one active cell.
    pub strips: Vec<Strip>,
    /// Map from (i, j) (index i + nx·j) to the active cell's index.
    index: Vec<Option<usize>>,
}

impl ContactGrid {
    /// Builds the grid over the ellipse with semi-axes `a`, `b` [m].
    pub fn new(a: f64, b: f64, nx: usize, ny: usize) -> Self {
        let hx = 2.0 * a / nx as f64;
        let hy = 2.0 * b / ny as f64;
        let mut cells = Vec::new();
        let mut strips = Vec::new();
        let mut index = vec![None; nx * ny];
        for j in 0..ny {
            let y = -b + (j as f64 + 0.5) * hy;
            let start = cells.len();
            for i in (0..nx).rev() {
                let x = -a + (i as f64 + 0.5) * hx;
                if (x / a).powi(2) + (y / b).powi(2) < 1.0 {
                    index[i + nx * j] = Some(cells.len());
                    cells.push(Cell { i, j, x, y });
                }
            }
            if cells.len() > start {
                strips.push(Strip {
                    j,
                    y,
                    half_length: a * (1.0 - (y / b).powi(2)).max(0.0).sqrt(),
                    cells: start..cells.len(),
                });
            }
        }
        Self {
            a,
            b,
            nx,
            ny,
            hx,
            hy,
            cells,
            strips,
            index,
        }
    }

    /// Grid over a Hertz contact.
    pub fn for_contact(h: &HertzContact, nx: usize, ny: usize) -> Self {
        Self::new(h.a, h.b, nx, ny)
    }

    /// Number of active cells.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// True if no cell is active (never for nx, ny ≥ 1).
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// Area of one cell h_x·h_y [m²].
    pub fn cell_area(&self) -> f64 {
        self.hx * self.hy
    }

    /// Index of the active cell at column `i`, row `j`, if any (out-of-range indices give None).
    pub fn cell_at(&self, i: isize, j: isize) -> Option<usize> {
        if i < 0 || j < 0 || i as usize >= self.nx || j as usize >= self.ny {
            return None;
        }
        self.index[i as usize + self.nx * j as usize]
    }

    /// Sum of `values` over the cells times the cell area: the discrete ∫∫ value dA.
    pub fn integrate(&self, values: &[f64]) -> f64 {
        values.iter().sum::<f64>() * self.cell_area()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_lie_inside_and_strips_run_from_leading_edge() {
        let g = ContactGrid::new(6e-3, 10e-3, 20, 24);
        assert!(!g.is_empty());
        for s in &g.strips {
            let xs: Vec<f64> = g.cells[s.cells.clone()].iter().map(|c| c.x).collect();
            assert!(
                xs.windows(2).all(|w| w[0] > w[1]),
                "strip not leading-first"
            );
            assert!(xs[0] < s.half_length && *xs.last().unwrap() > -s.half_length);
        }
        for (k, c) in g.cells.iter().enumerate() {
            assert_eq!(g.cell_at(c.i as isize, c.j as isize), Some(k));
        }
        assert_eq!(g.cell_at(-1, 0), None);
    }

    #[test]
    fn active_area_converges_to_ellipse_area() {
        let (a, b) = (6e-3, 10e-3);
        let exact = std::f64::consts::PI * a * b;
        let err = |n: usize| {
            let g = ContactGrid::new(a, b, n, n);
            (g.len() as f64 * g.cell_area() - exact).abs() / exact
        };
        assert!(err(100) < 0.01);
        assert!(err(200) < err(20));
    }
}
