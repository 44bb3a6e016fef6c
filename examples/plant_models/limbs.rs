//! Curved limbs of Prusinkiewicz et al. 2001: the leaves and stems of a
//! herb lily and a tulip grown by Algorithm 1 (natura-plant's
//! `models::limb`: the turtle turned by rates of `s` along the limb, the
//! blade twisted apart from its midrib; Fig. 4), and field garlic
//! (*Allium vineale*) whose stems follow given curves framed by Algorithm 2
//! (the curve framing of natura-plant's `models::compound`; Fig. 5). The
//! source prints none of its functions or curves: these are ours, read off
//! the plants' habit. Blades are swept across the turtle's `L` with `U`
//! their normal, as the limb model records them; the flowers' bulbils are
//! placed by Algorithm 5.

use natura::core::glam::{DVec3, Vec3};
use natura::plant::Geometry;
use natura::plant::lang::{Curve, Function};
use natura::plant::models::{compound, limb, positional};
use natura::plant::turtle::{TurtleFrame, rotate};

use crate::common::{Exit, outln};
use crate::inflorescences::{by_arc_length, organ_frame};
use crate::mesh::{Mesh, View, render};
use crate::organs::{self, mix};

/// Leaf green (linear RGB), darker at the base and paler at the tip.
const LEAF_BASE: Vec3 = Vec3::new(0.05, 0.2, 0.04);
const LEAF_TIP: Vec3 = Vec3::new(0.16, 0.36, 0.08);
/// The tulip's grey-green leaves.
const TULIP_LEAF: Vec3 = Vec3::new(0.12, 0.26, 0.14);

/// The polyline of `g`'s segments (one limb, in order) as points, widths,
/// headings and ups at each joint.
fn joints(g: &Geometry) -> Vec<(DVec3, f64, DVec3, DVec3)> {
    let n = g.segment_count();
    (0..=n)
        .map(|i| {
            let k = i.min(n - 1);
            let (a, b) = (g.start[k].as_dvec3(), g.end[k].as_dvec3());
            let h = (b - a).normalize_or(DVec3::Z);
            let (p, w) = if i < n {
                (a, f64::from(g.width0[k]))
            } else {
                (b, f64::from(g.width1[k]))
            };
            (p, w, h, g.up[k].as_dvec3())
        })
        .collect()
}

/// Sweeps a blade along the limb `g`: across its `L` (`U × H`) as wide as
/// the limb, cupped towards `U` by `keel` of its width, coloured from
/// `base` to `tip`.
fn blade(m: &mut Mesh, g: &Geometry, keel: f64, base: Vec3, tip: Vec3, res: u32) {
    if g.segment_count() == 0 {
        return;
    }
    let j = joints(g);
    let n = j.len() - 1;
    m.patch(
        n as u32,
        4 * res,
        |u, v| {
            let (p, w, h, up) = j[((u * n as f64).round() as usize).min(n)];
            let across = up.cross(h).normalize_or(DVec3::X);
            let a = 2.0 * v - 1.0;
            p + across * (0.5 * w * a) + up * (keel * w * a * a)
        },
        |u, _| mix(base, tip, u),
    );
}

/// Draws the limb `g` as a round stem of its width.
fn stem(m: &mut Mesh, g: &Geometry, colour: Vec3, res: u32) {
    for k in 0..g.segment_count() {
        let r = 0.5 * f64::from(g.width0[k].max(g.width1[k]));
        m.tube(
            g.start[k].as_dvec3(),
            g.end[k].as_dvec3(),
            r,
            6 * res,
            colour,
        );
    }
}

/// A function through `points`.
fn f(points: &[(f64, f64)]) -> Result<Function, Exit> {
    Ok(Function::new(points)?)
}

/// The frame of a leaf leaving the stem at `p` (stem heading `h`) towards
/// `radial`, `angle` degrees from the stem, its blade across the stem's
/// tangent circle.
fn leaf_start(p: DVec3, h: DVec3, radial: DVec3, angle: f64) -> TurtleFrame {
    let side = h.cross(radial).normalize_or(DVec3::X);
    let heading = rotate(h, side, angle.to_radians());
    TurtleFrame::new(p, heading, side)
}

/// Fig. 4, left: a herb lily at `x`: a stem 7 long with a slight S-bend,
/// and 14 alternate lanceolate leaves (137.5° apart) arching from it, each
/// twisted half a turn near its base as the plant's leaves are.
fn herb_lily(m: &mut Mesh, x: f64, res: u32) -> Result<usize, Exit> {
    let ds = if res > 1 { 0.02 } else { 0.05 };
    let stem_p = limb::LimbParams {
        length: 7.0,
        ds,
        omega_l: f(&[(0.0, 4.0), (3.5, -6.0), (7.0, 3.0)])?,
        width: f(&[(0.0, 0.12), (7.0, 0.05)])?,
        start: TurtleFrame::new(DVec3::new(x, 0.0, 0.0), DVec3::Z, DVec3::Y),
        ..limb::LimbParams::default()
    };
    let g = limb::limb(&stem_p)?.geometry()?;
    stem(m, &g, Vec3::new(0.12, 0.3, 0.06), res);
    let j = joints(&g);
    let leaves = 14;
    for k in 0..leaves {
        let t = 0.18 + 0.78 * f64::from(k) / f64::from(leaves);
        let (p, _, h, up) = j[(t * (j.len() - 1) as f64) as usize];
        let az = f64::from(k) * 137.5f64.to_radians();
        let radial = rotate(up, h, az);
        let len = 2.4 - 1.2 * t;
        let leaf = limb::LimbParams {
            length: len,
            ds: ds * 0.5,
            omega_l: f(&[(0.0, 10.0), (len, 55.0)])?,
            omega_u: f(&[(0.0, 0.0), (len, 8.0 * (az.sin()))])?,
            twist: f(&[(0.0, 500.0), (0.3, 120.0), (0.45, 0.0)])?,
            width: f(&[
                (0.0, 0.04),
                (0.25 * len, 0.42),
                (0.7 * len, 0.3),
                (len, 0.0),
            ])?,
            start: leaf_start(p, h, radial, 55.0 - 15.0 * t),
            ..limb::LimbParams::default()
        };
        blade(
            m,
            &limb::limb(&leaf)?.geometry()?,
            0.08,
            LEAF_BASE,
            LEAF_TIP,
            res,
        );
    }
    Ok(leaves as usize)
}

/// Fig. 4, right: a tulip at `x`: a stem 5.5 long curving a little under
/// a closed red flower, and three broad, keeled leaves from its foot
/// bending outwards, their tips turning over.
fn tulip(m: &mut Mesh, x: f64, res: u32) -> Result<usize, Exit> {
    let ds = if res > 1 { 0.02 } else { 0.05 };
    let foot = DVec3::new(x, 0.0, 0.0);
    let stem_p = limb::LimbParams {
        length: 5.5,
        ds,
        omega_l: f(&[(0.0, -2.0), (5.5, 9.0)])?,
        width: f(&[(0.0, 0.14), (5.5, 0.1)])?,
        start: TurtleFrame::new(foot, DVec3::Z, DVec3::Y),
        ..limb::LimbParams::default()
    };
    let g = limb::limb(&stem_p)?.geometry()?;
    stem(m, &g, Vec3::new(0.16, 0.3, 0.12), res);
    // The flower, closed, on the stem's tip.
    let n = g.segment_count();
    let top = g.end[n - 1].as_dvec3();
    let h = (top - g.start[n - 1].as_dvec3()).normalize_or(DVec3::Z);
    let red = Vec3::new(0.75, 0.05, 0.06);
    m.put(
        &organs::bud(1.2, 0.55, red * 0.5, red, res),
        top,
        organs::aim(h),
        1.0,
    );
    let leaves = [(0.0, 4.2, 30.0), (2.2, 3.6, 40.0), (4.1, 2.8, 22.0)];
    for (k, &(az, len, angle)) in leaves.iter().enumerate() {
        let radial = DVec3::new(f64::cos(az), f64::sin(az), 0.0);
        let leaf = limb::LimbParams {
            length: len,
            ds,
            omega_l: f(&[(0.0, 2.0), (0.5 * len, 12.0), (len, 60.0)])?,
            omega_u: f(&[(0.0, 0.0), (len, if k == 1 { -10.0 } else { 10.0 })])?,
            twist: f(&[(0.0, 0.0), (0.6 * len, 0.0), (len, 30.0)])?,
            width: f(&[(0.0, 0.6), (0.3 * len, 1.2), (0.8 * len, 0.7), (len, 0.0)])?,
            start: leaf_start(foot + DVec3::Z * 0.1 * k as f64, DVec3::Z, radial, angle),
            ..limb::LimbParams::default()
        };
        blade(
            m,
            &limb::limb(&leaf)?.geometry()?,
            0.18,
            TULIP_LEAF * 0.8,
            TULIP_LEAF,
            res,
        );
    }
    Ok(leaves.len())
}

/// Fig. 4: the herb lily (left) and the tulip (right), leaves and stems.
///
/// # Errors
///
/// The limb model's errors (none for these functions).
pub fn lily_and_tulip(res: u32) -> Result<(Mesh, [usize; 2]), Exit> {
    let mut m = Mesh::default();
    let a = herb_lily(&mut m, -2.4, res)?;
    let b = tulip(&mut m, 2.4, res)?;
    Ok((m, [a, b]))
}

/// The curve of field-garlic stem `k` from its foot at `(x, y)`: rising
/// 6 to 8, leaning, and curling into a loop of growing radius over its top
/// third, as the photographed stems do.
fn garlic_curve(k: usize, x: f64, y: f64) -> Result<Curve, Exit> {
    let turn = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
    let height = 6.0 + 0.5 * k as f64;
    let lean = 0.35 * (k as f64 * 2.1).cos();
    let pts: Vec<DVec3> = (0..=400)
        .map(|i| {
            let t = f64::from(i) / 400.0;
            let curl = ((t - 0.62) / 0.38).clamp(0.0, 1.0);
            let r = 0.9 * curl * curl;
            let a = turn * 2.4 * std::f64::consts::PI * curl + k as f64;
            DVec3::new(
                x + lean * height * t * t + r * a.cos() - r * (k as f64).cos(),
                y + r * a.sin() - r * (k as f64).sin(),
                height * t - 1.2 * curl * curl,
            )
        })
        .collect();
    Ok(Curve::new(&pts)?)
}

/// Fig. 5: a clump of five field-garlic stems, each framed along its curve
/// by Algorithm 2, carrying a head of bulbils (placed by Algorithm 5 on a
/// ball 0.3 across) with a few long thin sprouts.
///
/// # Errors
///
/// The compound model's and Algorithm 5's errors (none for these curves).
pub fn field_garlic(res: u32) -> Result<(Mesh, usize), Exit> {
    let mut m = Mesh::default();
    let feet = [
        (0.0, 0.0),
        (0.5, 0.3),
        (-0.4, 0.4),
        (0.3, -0.5),
        (-0.5, -0.3),
    ];
    let (blen, ball) = by_arc_length(
        |u| {
            let a = std::f64::consts::PI * u;
            (0.3 * a.sin(), -0.3 * a.cos())
        },
        1024,
    );
    let bulbils = positional::ridley(blen, 1e-4 * blen, &ball, |_| 0.075)?;
    for (k, &(x, y)) in feet.iter().enumerate() {
        let curve = garlic_curve(k, x, y)?;
        let len = curve.length();
        let p = compound::CompoundParams {
            length: len,
            ds: if res > 1 { 0.02 } else { 0.05 },
            // No organs: the stem alone, framed along its curve.
            internode: Function::new(&[(0.0, 2.0 * len)])?,
            stem_width: Function::new(&[(0.0, 0.09), (len, 0.05)])?,
            stem: Some(curve),
            ..compound::CompoundParams::default()
        };
        let g = compound::compound(&p)?.geometry()?;
        // The turtle starts at the origin: the stem is moved to its foot.
        let mut g = g;
        for q in g.start.iter_mut().chain(g.end.iter_mut()) {
            *q += Vec3::new(x as f32, y as f32, 0.0);
        }
        stem(&mut m, &g, Vec3::new(0.2, 0.35, 0.15), res);
        let n = g.segment_count();
        let top = g.end[n - 1].as_dvec3();
        let h = (top - g.start[n - 1].as_dvec3()).normalize_or(DVec3::Z);
        let rot = organs::aim(h);
        let centre = top + h * 0.3;
        for (i, o) in bulbils.iter().enumerate() {
            let (at, frame) = organ_frame(&ball, blen, o);
            let colour = mix(
                Vec3::new(0.35, 0.12, 0.22),
                Vec3::new(0.3, 0.4, 0.15),
                (i as f64 * 0.618).fract(),
            );
            let b = organs::bud(1.6, 0.8, colour * 0.7, colour, res);
            m.put(&b, centre + rot * at, rot * frame, o.radius);
        }
        // Sprouts: thin tubes arching out of the head.
        for s in 0..3 {
            let a = (k * 3 + s) as f64 * 2.4;
            let out = rot * DVec3::new(a.cos(), a.sin(), 1.2).normalize();
            let mut p0 = centre + out * 0.3;
            let mut d = out;
            for _ in 0..12 {
                let p1 = p0 + d * 0.12;
                m.tube(p0, p1, 0.012, 4 * res, Vec3::new(0.25, 0.4, 0.15));
                d = (d - DVec3::Z * 0.06).normalize();
                p0 = p1;
            }
        }
    }
    Ok((m, feet.len() * bulbils.len()))
}

/// Draws the models of this module that `want` names (`lily`, `garlic`)
/// into `out`, small and coarse when `quick`.
///
/// # Errors
///
/// The models' errors; natura-core's if a picture cannot be drawn or
/// written.
pub fn draw(want: impl Fn(&str) -> bool, quick: bool, out: &std::path::Path) -> crate::common::Run {
    let (size, res) = if quick { (240, 1) } else { (700, 2) };
    if want("lily") {
        let (m, leaves) = lily_and_tulip(res)?;
        let view = View::along(Vec3::new(0.0, 1.0, -0.25)).zoomed(1.3);
        render(&m, &view, size, size)?.save_png(out.join("lily_tulip.png"))?;
        outln(format_args!("lily_tulip.png: {leaves:?} leaves"))?;
    }
    if want("garlic") {
        let (m, n) = field_garlic(res)?;
        let view = View::along(Vec3::new(0.2, 1.0, -0.2)).zoomed(1.3);
        render(&m, &view, size, size)?.save_png(out.join("field_garlic.png"))?;
        outln(format_args!("field_garlic.png: {n} bulbils"))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_blade_spans_the_limbs_left_and_turns_with_its_twist() {
        // A straight limb 2 long and 1 wide heading +z with L along +y:
        // the flat blade spans y ∈ [−0.5, 0.5] at x = 0; twisted by 90°
        // along its length, it turns from across y to across x.
        let flat = |twist: f64| {
            let p = limb::LimbParams {
                length: 2.0,
                ds: 0.01,
                width: Function::new(&[(0.0, 1.0)]).unwrap(),
                twist: Function::new(&[(0.0, twist)]).unwrap(),
                ..limb::LimbParams::default()
            };
            let mut m = Mesh::default();
            blade(
                &mut m,
                &limb::limb(&p).unwrap().geometry().unwrap(),
                0.0,
                Vec3::ONE,
                Vec3::ONE,
                1,
            );
            m.bounds().unwrap()
        };
        let (lo, hi) = flat(0.0);
        assert!(
            (lo.y + 0.5).abs() < 1e-6 && (hi.y - 0.5).abs() < 1e-6,
            "{lo} {hi}"
        );
        assert!(lo.x.abs() < 1e-6 && hi.x.abs() < 1e-6, "{lo} {hi}");
        assert!(lo.z.abs() < 1e-6 && (hi.z - 2.0).abs() < 1e-6, "{lo} {hi}");
        let (lo, hi) = flat(45.0);
        assert!(hi.x - lo.x > 0.99 && hi.y - lo.y > 0.99, "{lo} {hi}");
    }
}
