//! A small line-plot canvas for the figure programs: an RGB picture split
//! into panels, each with its own data → pixel transform, drawn with
//! anti-aliased polylines (solid or dashed), dots, a frame, tick marks and
//! a zero line. There is no text: captions live in docs/figures.md.
//!
//! Coverage is the distance from a pixel centre to the nearest segment of
//! the polyline, so joints are drawn once and a line of width `w` covers
//! about `w` pixels per pixel of length.

use natura::core::Image;
use natura::core::glam::Vec3;

/// Colours (linear RGB) the figures share.
pub mod colour {
    use natura::core::glam::Vec3;
    /// Background.
    pub const PAPER: Vec3 = Vec3::ONE;
    /// Frames, ticks, the first curve.
    pub const INK: Vec3 = Vec3::new(0.02, 0.02, 0.02);
    /// Zero lines and secondary guides.
    pub const GUIDE: Vec3 = Vec3::new(0.55, 0.55, 0.55);
    /// Second curve.
    pub const BLUE: Vec3 = Vec3::new(0.02, 0.18, 0.75);
    /// Third curve.
    pub const RED: Vec3 = Vec3::new(0.80, 0.05, 0.03);
    /// Fourth curve.
    pub const GREEN: Vec3 = Vec3::new(0.03, 0.45, 0.06);
    /// Fifth curve.
    pub const ORANGE: Vec3 = Vec3::new(0.95, 0.45, 0.02);
}

/// A rectangle of the canvas showing `x ∈ [x0, x1]`, `y ∈ [y0, y1]` (y up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Panel {
    /// Left, top, right, bottom edges in pixels.
    pub rect: [f32; 4],
    /// Data range shown: `[x0, x1, y0, y1]`.
    pub range: [f64; 4],
}

impl Panel {
    /// The panel in pixels `rect` (left, top, right, bottom) showing the data
    /// `range` (x0, x1, y0, y1).
    #[must_use]
    pub fn new(rect: [f32; 4], range: [f64; 4]) -> Self {
        Self { rect, range }
    }

    /// A panel whose y range is chosen so one data unit has the same length
    /// in x and y (for curves in the plane), centred on `yc`.
    #[must_use]
    pub fn equal_aspect(rect: [f32; 4], x: [f64; 2], yc: f64) -> Self {
        let per_px = (x[1] - x[0]) / f64::from(rect[2] - rect[0]);
        let half = 0.5 * per_px * f64::from(rect[3] - rect[1]);
        Self::new(rect, [x[0], x[1], yc - half, yc + half])
    }

    /// Pixel position of data point `(x, y)`.
    #[must_use]
    pub fn px(&self, x: f64, y: f64) -> [f32; 2] {
        let [l, t, r, b] = self.rect;
        let [x0, x1, y0, y1] = self.range;
        let u = ((x - x0) / (x1 - x0)) as f32;
        let v = ((y - y0) / (y1 - y0)) as f32;
        [l + u * (r - l), b - v * (b - t)]
    }
}

/// An RGB canvas of linear colours on white paper.
#[derive(Clone, Debug)]
pub struct Canvas {
    width: usize,
    height: usize,
    pixels: Vec<Vec3>,
}

/// How a polyline is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pen {
    /// Colour (linear RGB).
    pub colour: Vec3,
    /// Width in pixels.
    pub width: f32,
    /// Dash and gap lengths in pixels, or `None` for a solid line.
    pub dash: Option<(f32, f32)>,
}

impl Pen {
    /// A solid pen.
    #[must_use]
    pub fn solid(colour: Vec3, width: f32) -> Self {
        Self {
            colour,
            width,
            dash: None,
        }
    }

    /// A dashed pen (dashes of 6 px, gaps of 4 px).
    #[must_use]
    pub fn dashed(colour: Vec3, width: f32) -> Self {
        Self {
            colour,
            width,
            dash: Some((6.0, 4.0)),
        }
    }
}

impl Canvas {
    /// A blank `width × height` canvas.
    #[must_use]
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            pixels: vec![colour::PAPER; width * height],
        }
    }

    /// A `width × height` canvas whose paper is `paper(x, y)`: a field
    /// the curves are drawn over.
    #[must_use]
    pub fn with_paper(width: usize, height: usize, paper: impl Fn(usize, usize) -> Vec3) -> Self {
        let pixels = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| paper(x, y))
            .collect();
        Self {
            width,
            height,
            pixels,
        }
    }

    /// Size in pixels.
    #[must_use]
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// Colour of pixel `(x, y)`.
    #[must_use]
    pub fn get(&self, x: usize, y: usize) -> Vec3 {
        self.pixels[y * self.width + x]
    }

    /// Panels in a grid of `cols × rows` cells with a `margin` in pixels
    /// around each, all showing `range`; row-major order.
    #[must_use]
    pub fn grid(&self, cols: usize, rows: usize, margin: f32, range: [f64; 4]) -> Vec<Panel> {
        let cw = self.width as f32 / cols as f32;
        let ch = self.height as f32 / rows as f32;
        (0..rows * cols)
            .map(|k| {
                let (c, r) = ((k % cols) as f32, (k / cols) as f32);
                Panel::new(
                    [
                        c * cw + margin,
                        r * ch + margin,
                        (c + 1.0) * cw - margin,
                        (r + 1.0) * ch - margin,
                    ],
                    range,
                )
            })
            .collect()
    }

    /// Draws the panel's frame, tick marks every `tick` data units along x
    /// and y (none for 0) and, where it is inside the range, the line y = 0.
    pub fn axes(&mut self, p: &Panel, tick: [f64; 2]) {
        let [l, t, r, b] = p.rect;
        let [x0, x1, y0, y1] = p.range;
        if y0 < 0.0 && y1 > 0.0 {
            let (a, c) = (p.px(x0, 0.0), p.px(x1, 0.0));
            self.stroke_px(&[a, c], Pen::solid(colour::GUIDE, 1.0), None);
        }
        let frame = [[l, t], [r, t], [r, b], [l, b], [l, t]];
        self.stroke_px(&frame, Pen::solid(colour::INK, 1.0), None);
        let len = 5.0;
        let ink = Pen::solid(colour::INK, 1.0);
        for (k, &step) in tick.iter().enumerate() {
            if step.is_nan() || step <= 0.0 {
                continue;
            }
            let (lo, hi) = if k == 0 { (x0, x1) } else { (y0, y1) };
            let mut v = (lo / step).ceil() * step;
            let mut n = 0;
            while v <= hi + 1e-9 * step.abs() && n < 200 {
                let q = if k == 0 { p.px(v, y0) } else { p.px(x0, v) };
                if k == 0 {
                    self.stroke_px(&[[q[0], b], [q[0], b - len]], ink, None);
                    self.stroke_px(&[[q[0], t], [q[0], t + len]], ink, None);
                } else {
                    self.stroke_px(&[[l, q[1]], [l + len, q[1]]], ink, None);
                    self.stroke_px(&[[r, q[1]], [r - len, q[1]]], ink, None);
                }
                v += step;
                n += 1;
            }
        }
    }

    /// Draws the polyline through the data points `pts` in panel `p`,
    /// clipped to the panel.
    pub fn line(&mut self, p: &Panel, pts: &[(f64, f64)], pen: Pen) {
        let px: Vec<[f32; 2]> = pts.iter().map(|&(x, y)| p.px(x, y)).collect();
        self.stroke_px(&px, pen, Some(p.rect));
    }

    /// Draws a filled dot of `radius` pixels at each data point, clipped to the panel.
    pub fn dots(&mut self, p: &Panel, pts: &[(f64, f64)], colour: Vec3, radius: f32) {
        for &(x, y) in pts {
            let c = p.px(x, y);
            self.stroke_px(&[c, c], Pen::solid(colour, 2.0 * radius), Some(p.rect));
        }
    }

    /// Draws a polyline given in pixels, optionally clipped to `clip`.
    fn stroke_px(&mut self, pts: &[[f32; 2]], pen: Pen, clip: Option<[f32; 4]>) {
        let pieces = match pen.dash {
            None => vec![pts.to_vec()],
            Some((on, off)) => dashes(pts, on, off),
        };
        for piece in pieces {
            self.stroke_solid(&piece, pen.colour, pen.width, clip);
        }
    }

    fn stroke_solid(&mut self, pts: &[[f32; 2]], col: Vec3, width: f32, clip: Option<[f32; 4]>) {
        if pts.is_empty() || width.is_nan() || width <= 0.0 {
            return;
        }
        let half = 0.5 * width;
        let reach = half + 1.0;
        let (mut lx, mut ty, mut rx, mut by) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN);
        for q in pts {
            lx = lx.min(q[0]);
            rx = rx.max(q[0]);
            ty = ty.min(q[1]);
            by = by.max(q[1]);
        }
        let [cl, ct, cr, cb] = clip.unwrap_or([0.0, 0.0, self.width as f32, self.height as f32]);
        let x0 = (lx - reach).max(cl).max(0.0).floor() as usize;
        let y0 = (ty - reach).max(ct).max(0.0).floor() as usize;
        let x1 = ((rx + reach).min(cr).ceil().max(0.0) as usize).min(self.width);
        let y1 = ((by + reach).min(cb).ceil().max(0.0) as usize).min(self.height);
        if x0 >= x1 || y0 >= y1 {
            return;
        }
        // Coverage of this polyline alone (the maximum over its segments),
        // blended once, so joints are not drawn twice.
        let w = x1 - x0;
        let mut cover = vec![0.0f32; w * (y1 - y0)];
        let segs: Vec<([f32; 2], [f32; 2])> = if pts.len() == 1 {
            vec![(pts[0], pts[0])]
        } else {
            pts.windows(2).map(|s| (s[0], s[1])).collect()
        };
        for (a, b) in segs {
            if !(a[0].is_finite() && a[1].is_finite() && b[0].is_finite() && b[1].is_finite()) {
                continue;
            }
            let sx0 = ((a[0].min(b[0]) - reach).floor().max(x0 as f32)) as usize;
            let sx1 = ((a[0].max(b[0]) + reach).ceil().min(x1 as f32)) as usize;
            let sy0 = ((a[1].min(b[1]) - reach).floor().max(y0 as f32)) as usize;
            let sy1 = ((a[1].max(b[1]) + reach).ceil().min(y1 as f32)) as usize;
            for y in sy0..sy1 {
                for x in sx0..sx1 {
                    let d = segment_distance([x as f32 + 0.5, y as f32 + 0.5], a, b);
                    let c = (half + 0.5 - d).clamp(0.0, 1.0);
                    let k = (y - y0) * w + (x - x0);
                    cover[k] = cover[k].max(c);
                }
            }
        }
        for y in y0..y1 {
            for x in x0..x1 {
                let c = cover[(y - y0) * w + (x - x0)];
                if c > 0.0 {
                    let p = &mut self.pixels[y * self.width + x];
                    *p = *p * (1.0 - c) + col * c;
                }
            }
        }
    }

    /// The picture.
    ///
    /// # Errors
    ///
    /// natura-core's error if the image cannot be allocated.
    pub fn into_image(self) -> natura::core::Result<Image> {
        let w = self.width;
        Image::from_fn(self.width, self.height, |x, y| self.pixels[y * w + x])
    }
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(p: [f32; 2], a: [f32; 2], b: [f32; 2]) -> f32 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (ex, ey) = (a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
    (ex * ex + ey * ey).sqrt()
}

/// The polyline cut into dashes `on` pixels long with gaps of `off`.
fn dashes(pts: &[[f32; 2]], on: f32, off: f32) -> Vec<Vec<[f32; 2]>> {
    let period = (on + off).max(1e-3);
    let mut out: Vec<Vec<[f32; 2]>> = Vec::new();
    let mut s = 0.0f32; // arc length at the segment's start
    let mut current: Vec<[f32; 2]> = Vec::new();
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        if len.is_nan() || len <= 0.0 {
            continue;
        }
        let at = |u: f32| [a[0] + (b[0] - a[0]) * u, a[1] + (b[1] - a[1]) * u];
        let mut u = 0.0f32;
        while u < len {
            let phase = (s + u) % period;
            let drawing = phase < on;
            let next = if drawing { on - phase } else { period - phase };
            let v = (u + next).min(len);
            if drawing {
                if current.is_empty() {
                    current.push(at(u / len));
                }
                current.push(at(v / len));
                if v < len {
                    out.push(std::mem::take(&mut current));
                }
            }
            u = v;
        }
        s += len;
    }
    if current.len() > 1 {
        out.push(current);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panel_maps_its_corners() {
        let p = Panel::new([10.0, 20.0, 110.0, 70.0], [-1.0, 1.0, 0.0, 5.0]);
        assert_eq!(p.px(-1.0, 0.0), [10.0, 70.0]);
        assert_eq!(p.px(1.0, 5.0), [110.0, 20.0]);
        assert_eq!(p.px(0.0, 2.5), [60.0, 45.0]);
    }

    #[test]
    fn a_line_covers_its_width_times_its_length_once() {
        let mut c = Canvas::new(64, 32);
        let p = Panel::new([0.0, 0.0, 64.0, 32.0], [0.0, 64.0, 0.0, 32.0]);
        // Horizontal, through pixel centres, drawn as many short segments:
        // the ink is still about width × length (joints are not doubled).
        let pts: Vec<(f64, f64)> = (0..=40).map(|i| (10.0 + i as f64, 15.5)).collect();
        c.line(&p, &pts, Pen::solid(colour::INK, 2.0));
        let ink: f32 = c.pixels.iter().map(|v| 1.0 - v.x).sum::<f32>() / (1.0 - colour::INK.x);
        assert!((ink - 2.0 * 40.0).abs() < 2.0 * 2.0, "ink {ink}");
        assert_eq!(c.get(5, 16), colour::PAPER);
    }

    #[test]
    fn dashes_leave_gaps_and_clipping_holds() {
        let mut c = Canvas::new(100, 10);
        let p = Panel::new([0.0, 0.0, 50.0, 10.0], [0.0, 50.0, 0.0, 10.0]);
        c.line(
            &p,
            &[(0.0, 5.0), (100.0, 5.0)],
            Pen::dashed(colour::INK, 1.0),
        );
        // Nothing right of the panel.
        assert!((50..100).all(|x| c.get(x, 4) == colour::PAPER && c.get(x, 5) == colour::PAPER));
        // Dashes of 6 px then gaps of 4: pixel 2 inked, pixel 8 not.
        assert!(c.get(2, 4).x < 0.9 || c.get(2, 5).x < 0.9);
        assert_eq!(c.get(8, 4), colour::PAPER);
        assert_eq!(dashes(&[[0.0, 0.0], [25.0, 0.0]], 6.0, 4.0).len(), 3);
    }
}
