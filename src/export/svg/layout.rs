//! Where everything goes on the page: the four views (FRONT, TOP, RIGHT in third-angle
//! projection, and the ISOMETRIC view), their panels, the legend column and the title block.
//!
//! The grid's columns and rows are sized to what the orthographic views need (at least
//! [`MIN_SPLIT`] each); the cells of a column share their x and those of a row their y, so
//! FRONT and TOP line up in x and FRONT and RIGHT in z. The orthographic views share one
//! scale; the isometric view is fitted to its cell at its own. A [`Panel`] maps model points
//! to page points (SVG's y axis points down, the view's `v` up).

use glam::{DVec2, DVec3};

/// Page width in SVG user units (px at 100 %).
pub const PAGE_WIDTH: f64 = 1400.0;
/// Page height in SVG user units.
pub const PAGE_HEIGHT: f64 = 1000.0;

const MARGIN: f64 = 12.0;
const LEGEND_WIDTH: f64 = 230.0;
const TITLE_HEIGHT: f64 = 92.0;
const LABEL_BAND: f64 = 24.0;
/// Smallest share of the grid's width or height a column or row of panels gets.
pub const MIN_SPLIT: f64 = 0.4;
const INSET: f64 = 16.0;
/// Smallest extent of the part taken in any direction (mm), so that a flat part still scales.
const MIN_EXTENT_MM: f64 = 1e-9;

/// A direction of view: the picture's right (`u`) and up (`v`) axes in model space, and the
/// direction toward the viewer.
#[derive(Clone, Copy, Debug)]
pub(super) struct View {
    pub(super) name: &'static str,
    /// What the view looks along, for the panel label.
    pub(super) note: &'static str,
    pub(super) u: DVec3,
    pub(super) v: DVec3,
    pub(super) toward: DVec3,
}

pub(super) const FRONT: View = View {
    name: "FRONT",
    note: "looking along +y",
    u: DVec3::X,
    v: DVec3::Z,
    toward: DVec3::NEG_Y,
};
pub(super) const TOP: View = View {
    name: "TOP",
    note: "looking along \u{2212}z",
    u: DVec3::X,
    v: DVec3::Y,
    toward: DVec3::Z,
};
pub(super) const RIGHT: View = View {
    name: "RIGHT",
    note: "looking along \u{2212}x",
    u: DVec3::Y,
    v: DVec3::Z,
    toward: DVec3::X,
};

pub(super) fn isometric() -> View {
    View {
        name: "ISOMETRIC",
        note: "from (1, \u{2212}1, 1)",
        u: DVec3::new(1.0, 1.0, 0.0).normalize(),
        v: DVec3::new(-1.0, 1.0, 2.0).normalize(),
        toward: DVec3::new(1.0, -1.0, 1.0).normalize(),
    }
}

/// A rectangle on the page.
#[derive(Clone, Copy, Debug)]
pub(super) struct Rect {
    pub(super) x: f64,
    pub(super) y: f64,
    pub(super) w: f64,
    pub(super) h: f64,
}

/// One view placed on the page: model point → page point.
#[derive(Clone, Copy, Debug)]
pub(super) struct Panel {
    pub(super) view: View,
    pub(super) cell: Rect,
    /// px per mm.
    pub(super) scale: f64,
    /// `(u, v)` of the model's bounding-box centre, drawn at `origin`.
    centre: DVec2,
    origin: DVec2,
    /// Depth (along `toward`) of the nearest and farthest bounding-box corner.
    depth_range: (f64, f64),
}

impl Panel {
    pub(super) fn page_point(&self, p: DVec3) -> DVec2 {
        let (u, v) = (p.dot(self.view.u), p.dot(self.view.v));
        DVec2::new(
            self.origin.x + (u - self.centre.x) * self.scale,
            self.origin.y - (v - self.centre.y) * self.scale,
        )
    }

    fn depth(&self, p: DVec3) -> f64 {
        p.dot(self.view.toward)
    }

    /// 0 at the nearest bounding-box corner, 1 at the farthest.
    pub(super) fn farness(&self, p: DVec3) -> f64 {
        let (near, far) = self.depth_range;
        if near - far > 0.0 {
            ((near - self.depth(p)) / (near - far)).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}

/// The four panels: FRONT, TOP, RIGHT, ISOMETRIC.
pub(super) struct Layout {
    pub(super) panels: [Panel; 4],
    pub(super) legend: Rect,
    pub(super) title: Rect,
}

fn corners(bbox: (DVec3, DVec3)) -> [DVec3; 8] {
    let (lo, hi) = bbox;
    std::array::from_fn(|k| {
        DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// `(u range, v range, centre, depth range)` of the bounding box in a view.
fn extent(view: &View, bbox: (DVec3, DVec3)) -> (DVec2, DVec2, (f64, f64)) {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
    for c in corners(bbox) {
        let q = DVec2::new(c.dot(view.u), c.dot(view.v));
        lo = lo.min(q);
        hi = hi.max(q);
        let d = c.dot(view.toward);
        near = near.max(d);
        far = far.min(d);
    }
    (hi - lo, (lo + hi) * 0.5, (near, far))
}

pub(super) fn layout(bbox: (DVec3, DVec3)) -> Layout {
    let grid_w = PAGE_WIDTH - 3.0 * MARGIN - LEGEND_WIDTH;
    let grid_h = PAGE_HEIGHT - 3.0 * MARGIN - TITLE_HEIGHT;
    // Split the grid where the orthographic views need it: the left column holds x (TOP,
    // FRONT), the right one y (RIGHT); the top row holds y (TOP), the bottom one z (FRONT,
    // RIGHT). Each column and row keeps at least MIN_SPLIT of the grid, so a flat part still
    // leaves the isometric view room. Cells of one column share their x, cells of one row
    // their y, so the views stay aligned.
    let size = (bbox.1 - bbox.0).max(DVec3::splat(MIN_EXTENT_MM));
    let split = |a: f64, b: f64| (a / (a + b)).clamp(MIN_SPLIT, 1.0 - MIN_SPLIT);
    let cw = [
        split(size.x, size.y) * grid_w,
        (1.0 - split(size.x, size.y)) * grid_w,
    ];
    let rh = [
        split(size.y, size.z) * grid_h,
        (1.0 - split(size.y, size.z)) * grid_h,
    ];
    let cell = |col: usize, row: usize| Rect {
        x: MARGIN + if col == 0 { 0.0 } else { cw[0] },
        y: MARGIN + if row == 0 { 0.0 } else { rh[0] },
        w: cw[col],
        h: rh[row],
    };
    // Third-angle: TOP above FRONT, RIGHT right of FRONT, ISOMETRIC in the free corner.
    let views = [FRONT, TOP, RIGHT, isometric()];
    let cells = [cell(0, 1), cell(0, 0), cell(1, 1), cell(1, 0)];
    let fit = |size: DVec2, c: Rect| {
        let size = size.max(DVec2::splat(MIN_EXTENT_MM));
        let (aw, ah) = (c.w - 2.0 * INSET, c.h - LABEL_BAND - 2.0 * INSET);
        (aw / size.x).min(ah / size.y)
    };
    let extents = views.map(|v| extent(&v, bbox));
    let ortho = (0..3)
        .map(|k| fit(extents[k].0, cells[k]))
        .fold(f64::INFINITY, f64::min);
    let panels = std::array::from_fn(|k| {
        let c = cells[k];
        Panel {
            view: views[k],
            cell: c,
            scale: if k < 3 { ortho } else { fit(extents[k].0, c) },
            centre: extents[k].1,
            origin: DVec2::new(c.x + c.w / 2.0, c.y + LABEL_BAND + (c.h - LABEL_BAND) / 2.0),
            depth_range: extents[k].2,
        }
    });
    Layout {
        panels,
        legend: Rect {
            x: PAGE_WIDTH - MARGIN - LEGEND_WIDTH,
            y: MARGIN,
            w: LEGEND_WIDTH,
            h: grid_h,
        },
        title: Rect {
            x: MARGIN,
            y: PAGE_HEIGHT - MARGIN - TITLE_HEIGHT,
            w: PAGE_WIDTH - 2.0 * MARGIN,
            h: TITLE_HEIGHT,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_are_third_angle_aligned_with_model_up_pointing_up() {
        let bbox = (DVec3::ZERO, DVec3::new(60.0, 40.0, 20.0));
        let lay = layout(bbox);
        let [front, top, right, iso] = lay.panels;
        // Third angle: TOP above FRONT, RIGHT to the right of FRONT.
        assert!(top.cell.y + top.cell.h <= front.cell.y + 1e-9);
        assert!((top.cell.x - front.cell.x).abs() < 1e-9);
        assert!(front.cell.x + front.cell.w <= right.cell.x + 1e-9);
        assert!((right.cell.y - front.cell.y).abs() < 1e-9);
        // One scale for the orthographic views.
        assert_eq!(front.scale, top.scale);
        assert_eq!(front.scale, right.scale);
        let p = DVec3::new(10.0, 30.0, 5.0);
        let q = DVec3::new(50.0, 5.0, 15.0);
        let (fp, fq) = (front.page_point(p), front.page_point(q));
        // FRONT: x to the right, z up (SVG y down), y is depth.
        assert!((fq.x - fp.x - 40.0 * front.scale).abs() < 1e-9);
        assert!((fp.y - fq.y - 10.0 * front.scale).abs() < 1e-9);
        assert_eq!(
            front.page_point(p),
            front.page_point(p + DVec3::new(0.0, 17.0, 0.0))
        );
        // TOP: x to the right, y up; aligned with FRONT in x.
        let (tp, tq) = (top.page_point(p), top.page_point(q));
        assert!((tp.x - fp.x).abs() < 1e-9 && (tq.x - fq.x).abs() < 1e-9);
        assert!((tq.y - tp.y - 25.0 * top.scale).abs() < 1e-9);
        // RIGHT: y to the right, z up; aligned with FRONT in z.
        let (rp, rq) = (right.page_point(p), right.page_point(q));
        assert!((rp.y - fp.y).abs() < 1e-9 && (rq.y - fq.y).abs() < 1e-9);
        assert!((rp.x - rq.x - 25.0 * right.scale).abs() < 1e-9);
        // ISOMETRIC: x goes right and down, y right and up, z straight up.
        let o = iso.page_point(DVec3::ZERO);
        let dx = iso.page_point(DVec3::X) - o;
        let dy = iso.page_point(DVec3::Y) - o;
        let dz = iso.page_point(DVec3::Z) - o;
        assert!(dx.x > 0.0 && dx.y > 0.0, "{dx}");
        assert!(dy.x > 0.0 && dy.y < 0.0, "{dy}");
        assert!(dz.x.abs() < 1e-9 && dz.y < 0.0, "{dz}");
        assert!((dx.length() - dy.length()).abs() < 1e-9);
        // The whole part lies in each panel's drawing area, below the label band.
        for panel in lay.panels {
            let c = panel.cell;
            for k in corners(bbox) {
                let q = panel.page_point(k);
                assert!(q.x >= c.x + INSET - 1e-6 && q.x <= c.x + c.w - INSET + 1e-6);
                assert!(q.y >= c.y + LABEL_BAND + INSET - 1e-6);
                assert!(q.y <= c.y + c.h - INSET + 1e-6, "{} {q}", panel.view.name);
            }
        }
    }
}
