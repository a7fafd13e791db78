//! A UV grid over a face's domain whose cells are classified inside the trim, outside it, or
//! near a loop: it answers most inside tests of a face without the polygon test (the distance
//! queries' cache holds one per face), and tells which cells of a coarser grid can hold a
//! point of the face.

use super::covered::covered_domain;
use super::loops::{contains, Trim};
use crate::model::Face;
use glam::DVec2;

/// A UV grid over a face's domain that classifies each cell as inside the trim, outside it,
/// or near a loop (see [`TrimGrid::contains`]).
#[derive(Clone, Debug)]
pub struct TrimGrid {
    nu: usize,
    nv: usize,
    u: (f64, f64),
    v: (f64, f64),
    du: f64,
    dv: f64,
    periods: (Option<f64>, Option<f64>),
    /// Per cell (row-major in v): [`CELL_IN`], [`CELL_OUT`] or [`CELL_MIXED`].
    state: Vec<u8>,
}

/// A cell of the grid inside the trim, outside it, near a loop (the exact test decides
/// there), and not classified yet (while the grid is built).
const CELL_IN: u8 = 1;
const CELL_OUT: u8 = 2;
const CELL_MIXED: u8 = 0;
const CELL_UNKNOWN: u8 = 3;

impl TrimGrid {
    /// Classifies the cells of an `nu × nv` grid over the face's domain. A cell is near a loop
    /// ([`CELL_MIXED`]) if a loop polygon passes through it or a neighbour (the polygon is
    /// walked in steps of a quarter cell, and the marks grown by one cell so that a segment
    /// clipping a corner between two steps is still caught). No loop crosses a connected
    /// region of the other cells, so one [`contains`] per region classifies it.
    pub fn new(face: &Face, nu: usize, nv: usize) -> Option<TrimGrid> {
        let d = &face.domain;
        let ((u0, u1), (v0, v1)) = covered_domain(face);
        if !(u0.is_finite() && u1.is_finite() && v0.is_finite() && v1.is_finite())
            || u1 <= u0
            || v1 <= v0
        {
            return None;
        }
        let (du, dv) = ((u1 - u0) / nu as f64, (v1 - v0) / nv as f64);
        let mut grid = TrimGrid {
            nu,
            nv,
            u: (u0, u1),
            v: (v0, v1),
            du,
            dv,
            periods: (d.u_period, d.v_period),
            state: vec![CELL_MIXED; nu * nv],
        };
        let mut near = vec![false; nu * nv];
        for l in face.loops.iter().filter(|l| l.vertex.is_none()) {
            let poly = l.outline();
            let n = poly.len();
            for k in 0..n {
                let a = poly[k];
                let mut b = poly[(k + 1) % n];
                if k + 1 == n {
                    // The closing step of a loop that wraps around a period is short on the
                    // surface: go to the copy of the first point next to the last.
                    let near_copy = |x: f64, r: f64, p: Option<f64>| match p {
                        Some(p) if (x - r).abs() > 0.5 * p => x + ((r - x) / p).round() * p,
                        _ => x,
                    };
                    b = DVec2::new(
                        near_copy(b.x, a.x, grid.periods.0),
                        near_copy(b.y, a.y, grid.periods.1),
                    );
                }
                let delta = b - a;
                let steps = (4.0 * (delta.x.abs() / du).max(delta.y.abs() / dv))
                    .ceil()
                    .min(1e6) as usize
                    + 1;
                for s in 0..=steps {
                    let (i, j) = grid.cell_of(a + delta * (s as f64 / steps as f64));
                    near[j * nu + i] = true;
                }
            }
        }
        for j in 0..nv {
            for i in 0..nu {
                let grown = (j.saturating_sub(1)..(j + 2).min(nv))
                    .any(|jj| (i.saturating_sub(1)..(i + 2).min(nu)).any(|ii| near[jj * nu + ii]));
                grid.state[j * nu + i] = if grown { CELL_MIXED } else { CELL_UNKNOWN };
            }
        }
        // No loop passes through a connected region of the other cells: one test decides it.
        let mut queue = Vec::new();
        for start in 0..nu * nv {
            if grid.state[start] != CELL_UNKNOWN {
                continue;
            }
            let (i, j) = (start % nu, start / nu);
            let centre = grid.node(i, j) + DVec2::new(0.5 * du, 0.5 * dv);
            let fill = if contains(face, centre) {
                CELL_IN
            } else {
                CELL_OUT
            };
            grid.state[start] = fill;
            queue.clear();
            queue.push(start);
            while let Some(c) = queue.pop() {
                let (i, j) = (c % nu, c / nu);
                let mut visit = |ii: usize, jj: usize| {
                    let k = jj * nu + ii;
                    if grid.state[k] == CELL_UNKNOWN {
                        grid.state[k] = fill;
                        queue.push(k);
                    }
                };
                if i > 0 {
                    visit(i - 1, j);
                }
                if i + 1 < nu {
                    visit(i + 1, j);
                }
                if j > 0 {
                    visit(i, j - 1);
                }
                if j + 1 < nv {
                    visit(i, j + 1);
                }
            }
        }
        Some(grid)
    }

    /// Cells along u and along v.
    pub fn counts(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }

    /// A cell's sides in u and v.
    pub fn cell_size(&self) -> (f64, f64) {
        (self.du, self.dv)
    }

    /// True when cell `(i, j)` is outside the trim (no point of the face is in it).
    #[inline]
    pub fn is_outside(&self, i: usize, j: usize) -> bool {
        self.state[j * self.nu + i] == CELL_OUT
    }

    /// The parameters of node `(i, j)` (the lower corner of cell `(i, j)`).
    #[inline]
    pub fn node(&self, i: usize, j: usize) -> DVec2 {
        DVec2::new(self.u.0 + self.du * i as f64, self.v.0 + self.dv * j as f64)
    }

    /// The cell containing `q` (periodic coordinates moved to the copy nearest the domain's
    /// middle, the rest clamped).
    #[inline]
    fn cell_of(&self, q: DVec2) -> (usize, usize) {
        let idx = |x: f64, r: (f64, f64), h: f64, n: usize, period: Option<f64>| {
            let mut x = x;
            if let Some(p) = period {
                let mid = 0.5 * (r.0 + r.1);
                x += ((mid - x) / p).round() * p;
            }
            (((x - r.0) / h).floor().max(0.0) as usize).min(n - 1)
        };
        (
            idx(q.x, self.u, self.du, self.nu, self.periods.0),
            idx(q.y, self.v, self.dv, self.nv, self.periods.1),
        )
    }

    /// [`contains`], answered from the grid where the cell is not near a loop, by
    /// `exact` (the same face's prepared loops) otherwise.
    #[inline]
    pub fn contains(&self, face: &Face, exact: &Trim, uv: DVec2) -> bool {
        let wrap = |x: f64, r: (f64, f64), p: Option<f64>| match p {
            Some(p) => r.0 + (x - r.0).rem_euclid(p),
            None => x,
        };
        let (u, v) = (
            wrap(uv.x, self.u, self.periods.0),
            wrap(uv.y, self.v, self.periods.1),
        );
        if u >= self.u.0 && u < self.u.1 && v >= self.v.0 && v < self.v.1 {
            let i = (((u - self.u.0) / self.du) as usize).min(self.nu - 1);
            let j = (((v - self.v.0) / self.dv) as usize).min(self.nv - 1);
            match self.state[j * self.nu + i] {
                CELL_IN => return true,
                CELL_OUT => return false,
                _ => {}
            }
        } else {
            // The loops lie in the domain (it is their bounding box, a whole period where
            // they wrap): clearly beyond it is outside; near its border, test exactly.
            let margin = |x: f64, r: (f64, f64), h: f64| x < r.0 - h || x > r.1 + h;
            if margin(u, self.u, self.du) || margin(v, self.v, self.dv) {
                return false;
            }
        }
        exact.contains(face, uv)
    }
}
