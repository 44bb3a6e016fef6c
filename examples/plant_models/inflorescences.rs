//! Three inflorescences of Prusinkiewicz et al. 2001 whose flowers are
//! placed by Algorithm 5 (natura-plant's `positional::ridley`: organs of
//! radius `ρ(s)` packed on a surface of revolution where
//! `N(0, s) = ∫₀ˢ 2 f_x(s)/ρ²(s) ds` passes an integer, each 137.5° round
//! the axis from the last): the strawflower *Helichrysum bracteatum*
//! (Fig. 9), beargrass *Xerophyllum tenax* (Fig. 10) and the red-hot poker
//! *Kniphofia* at two stages of its development (Fig. 14). What varies
//! along the axis (the organ's size, whether it is a bud, an open flower or
//! a bract, its colour and posture) is a function of its position `s`, the
//! paper's positional information. The source prints none of its functions
//! or sizes: the receptacles, radii and organs here are ours, from its
//! pictures. The organ meshes are those of `figures_fowler`.

use natura::core::glam::{DMat3, DVec2, DVec3, Vec3};
use natura::core::{mix64, unit_f64};
use natura::plant::models::positional::{self, Organ};

use crate::common::{Exit, outln};
use crate::mesh::{Mesh, View, render};
use crate::organs::{self, colour, mix};

/// The curve `shape(u)`, `u ∈ [0, 1]`, as `(f_x, f_y)` by arc length from
/// a table of `chords` chords: its length and the curve (held at its ends
/// outside `[0, length]`).
pub fn by_arc_length(
    shape: impl Fn(f64) -> (f64, f64),
    chords: u32,
) -> (f64, impl Fn(f64) -> (f64, f64)) {
    let pts: Vec<(f64, f64)> = (0..=chords)
        .map(|k| shape(f64::from(k) / f64::from(chords)))
        .collect();
    let mut arc = vec![0.0];
    for w in pts.windows(2) {
        let d = (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1);
        arc.push(arc.last().copied().unwrap_or(0.0) + d);
    }
    let len = arc.last().copied().unwrap_or(0.0);
    let curve = move |s: f64| {
        let k = arc.partition_point(|&a| a <= s).clamp(1, arc.len() - 1);
        let t = ((s - arc[k - 1]) / (arc[k] - arc[k - 1]).max(1e-12)).clamp(0.0, 1.0);
        let (a, b) = (pts[k - 1], pts[k]);
        (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t)
    };
    (len, curve)
}

/// Where organ `o` of Algorithm 5 sits on the surface of revolution of
/// `curve` (of length `len`, about `+z`), and its frame for
/// [`Mesh::put`]: `+z` the surface's outward normal, `+x` the curve's
/// tangent towards its end, as the organs are modelled.
pub fn organ_frame(curve: &impl Fn(f64) -> (f64, f64), len: f64, o: &Organ) -> (DVec3, DMat3) {
    let h = 1e-3 * len;
    let (a, b) = (curve((o.s - h).max(0.0)), curve((o.s + h).min(len)));
    let t = DVec2::new(b.0 - a.0, b.1 - a.1).normalize_or(DVec2::Y);
    let th = o.angle_deg.to_radians();
    let radial = DVec3::new(th.cos(), th.sin(), 0.0);
    let x = radial * t.x + DVec3::Z * t.y;
    let z = radial * t.y - DVec3::Z * t.x;
    (
        radial * o.x + DVec3::Z * o.y,
        DMat3::from_cols(x, z.cross(x), z),
    )
}

/// A number in `[0, 1)` for organ `k` of a plant, the same every run.
fn jitter(k: usize, salt: u64) -> f64 {
    unit_f64(mix64(k as u64 ^ salt.rotate_left(32)))
}

/// Integration step of Algorithm 5, as a fraction of the curve's length.
const DS: f64 = 1e-4;

/// Fig. 14: a *Kniphofia* spike at `stage` of its development (0 all in
/// bud, 1 flowering over its lower half), its foot at the origin: a
/// rounded spike `3.5 + 2.5·stage` long and 0.35 across carrying tubular
/// flowers of radius 0.17 at its foot to 0.11 at its tip (Algorithm 5),
/// the buds closed, orange to red and turned up the spike, the open
/// flowers yellow bells hanging down it, on a stalk 5 long. Returns the mesh and its organ count.
///
/// # Errors
///
/// Algorithm 5's errors (none for these functions).
pub fn kniphofia(stage: f64, res: u32) -> Result<(Mesh, usize), Exit> {
    let spike = 3.5 + 2.5 * stage;
    let (len, curve) = by_arc_length(
        |u| (0.35 * (1.0 - u.powi(4)).max(0.0).sqrt(), spike * u),
        2048,
    );
    let rho = |s: f64| 0.17 - 0.06 * s / len;
    let organs = positional::ridley(len, DS * len, &curve, rho)?;
    let open_to = 0.5 * stage;
    let mut m = Mesh::default();
    for (k, o) in organs.iter().enumerate() {
        let t = o.s / len;
        // 1 for an open flower, 0 for a bud, blended over a tenth of the spike.
        let open = ((open_to - t) / 0.1 + 0.5).clamp(0.0, 1.0);
        let bud = mix(
            Vec3::new(0.95, 0.42, 0.04),
            Vec3::new(0.75, 0.07, 0.03),
            t.powf(0.7),
        );
        let body = mix(bud, Vec3::new(0.95, 0.78, 0.12), open) * (0.9 + 0.2 * jitter(k, 14) as f32);
        // Buds point 40° up the spike; open flowers hang 80° down it.
        let beta = (40.0 - 120.0 * open).to_radians();
        let axis = DVec3::new(beta.sin(), 0.0, beta.cos());
        let flower = if open >= 0.5 {
            organs::bell(axis, 8.0, 1.8, body, res)
        } else {
            // A closed bud: a slender egg along the axis.
            let mut b = Mesh::default();
            b.put(
                &organs::bud(6.5, 0.75, body * 0.8, body, res),
                DVec3::ZERO,
                organs::aim(axis),
                1.0,
            );
            b
        };
        let (at, rot) = organ_frame(&curve, len, o);
        m.put(&flower, at, rot, o.radius);
    }
    m.tube(
        DVec3::ZERO,
        DVec3::Z * (0.95 * spike),
        0.2,
        6 * res,
        colour::LEAF,
    );
    m.tube(
        DVec3::Z * -5.0,
        DVec3::Z * 0.05,
        0.07,
        6 * res,
        colour::LEAF,
    );
    Ok((m, organs.len()))
}

/// Fig. 10: beargrass, its foot at the origin: a dense club of small white
/// flowers, open on long pedicels below and in bud at the pointed top,
/// placed by Algorithm 5 (radius 0.1) on a spike 3.6 long and 0.8
/// across, on a stalk 6 long over a tuft of 48 wiry arching leaves.
/// Returns the mesh and its flower count.
///
/// # Errors
///
/// Algorithm 5's errors (none for these functions).
pub fn beargrass(res: u32) -> Result<(Mesh, usize), Exit> {
    let spike = 3.6;
    let (len, curve) = by_arc_length(
        |u| {
            let r = 0.4 * (std::f64::consts::PI * u.max(0.02)).sin().powf(0.6);
            (r * (1.0 - 0.5 * u), spike * u)
        },
        2048,
    );
    let organs = positional::ridley(len, DS * len, &curve, |_| 0.1)?;
    let foot = DVec3::Z * 6.0;
    let white = Vec3::new(0.9, 0.9, 0.84);
    let mut m = Mesh::default();
    for (k, o) in organs.iter().enumerate() {
        let t = o.s / len;
        // Pedicels 9 radii long at the foot, none at the tip; the flowers
        // open below 0.7 of the spike, in bud above.
        let pedicel = 9.0 * (1.0 - t / 0.9).max(0.0).powf(0.8) + 0.3;
        let up = (20.0 + 40.0 * t).to_radians();
        let d = DVec3::new(up.sin(), 0.0, up.cos());
        let mut f = Mesh::default();
        f.tube(
            DVec3::ZERO,
            d * pedicel,
            0.2,
            3 * res,
            Vec3::new(0.55, 0.6, 0.45),
        );
        let flower = if t < 0.7 {
            organs::cup(
                DVec3::Z,
                1.6,
                white * (0.92 + 0.1 * jitter(k, 10) as f32),
                res,
            )
        } else {
            organs::bud(1.3, 0.7, Vec3::new(0.6, 0.65, 0.5), white, res)
        };
        f.put(&flower, d * pedicel, organs::aim(d), 1.0);
        let (at, rot) = organ_frame(&curve, len, o);
        m.put(&f, foot + at, rot, o.radius);
    }
    m.tube(
        DVec3::ZERO,
        foot + DVec3::Z * (0.9 * spike),
        0.06,
        6 * res,
        colour::LEAF,
    );
    // The tuft: leaves rising 35°–75° and arching over, round the foot.
    for k in 0..48 {
        let az = k as f64 * 137.5f64.to_radians();
        let elev = (35.0 + 40.0 * jitter(k, 3)).to_radians();
        let leaf = organs::leaf(
            2.6 + 1.6 * jitter(k, 4),
            0.07,
            -0.35,
            Vec3::new(0.12, 0.28, 0.06),
            res,
        );
        let rot = DMat3::from_rotation_z(az) * DMat3::from_rotation_y(-elev);
        m.put(&leaf, DVec3::ZERO, rot, 1.0);
    }
    Ok((m, organs.len()))
}

/// Fig. 9: a strawflower head of `bracts` colour, its receptacle's rim at
/// the origin: a low dome 1 across and 0.25 high carrying, by Algorithm 5,
/// yellow disc florets of radius 0.05 over its middle and stiff papery
/// bracts (ray organs) growing to radius 0.13 towards the rim, the inner
/// ones upright, the outer spreading. Returns the mesh and its organ count.
///
/// # Errors
///
/// Algorithm 5's errors (none for these functions).
pub fn strawflower_head(bracts: Vec3, res: u32) -> Result<(Mesh, usize), Exit> {
    // From the rim (s = 0) to the top of the dome.
    let (len, curve) = by_arc_length(|u| (1.0 - u, 0.25 * (1.0 - (1.0 - u) * (1.0 - u))), 2048);
    let rho = |s: f64| 0.05 + 0.08 * (1.0 - (s / len / 0.6).min(1.0)).powf(1.3);
    let organs = positional::ridley(len, DS * len, &curve, rho)?;
    let mut m = Mesh::default();
    for (k, o) in organs.iter().enumerate() {
        let t = o.s / len;
        let (at, rot) = organ_frame(&curve, len, o);
        let organ = if t > 0.55 {
            organs::open_floret(2.0, colour::YELLOW, res)
        } else {
            // 0 at the rim, 1 at the innermost bract.
            let inner = t / 0.55;
            let tint = 0.85 + 0.25 * jitter(k, 9) as f32;
            organs::petal(
                4.5 - 1.5 * inner,
                2.6,
                (15.0 + 70.0 * inner).to_radians(),
                (-25.0 + 35.0 * inner).to_radians(),
                mix(bracts, colour::YELLOW, 0.25 + 0.4 * inner) * tint,
                bracts * tint,
                res,
            )
        };
        m.put(&organ, at, rot, o.radius);
    }
    Ok((m, organs.len()))
}

/// Fig. 9: three strawflower heads (red, orange and yellow bracts) on
/// leafy stems. Returns the mesh and the organs of each head.
///
/// # Errors
///
/// Algorithm 5's errors (none for these functions).
pub fn strawflowers(res: u32) -> Result<(Mesh, Vec<usize>), Exit> {
    let heads = [
        (Vec3::new(0.75, 0.06, 0.08), [0.0, 0.0, 3.2], 0.25, 0.0),
        (Vec3::new(0.95, 0.45, 0.04), [-1.9, 0.6, 2.3], 0.45, 0.9),
        (Vec3::new(0.92, 0.75, 0.1), [1.8, 0.4, 1.9], 0.4, -0.8),
    ];
    let mut m = Mesh::default();
    let mut counts = Vec::new();
    for (k, &(c, at, tilt, turn)) in heads.iter().enumerate() {
        let (head, n) = strawflower_head(c, res)?;
        counts.push(n);
        let rot = DMat3::from_rotation_z(turn) * DMat3::from_rotation_x(tilt);
        let top = DVec3::from(at);
        m.put(&head, top, rot, 1.0);
        let foot = DVec3::new(0.25 * top.x, 0.25 * top.y, -2.0);
        m.tube(foot, top, 0.05, 6 * res, colour::LEAF);
        // Narrow leaves up the stem.
        for j in 0..5 {
            let f = 0.15 + 0.15 * f64::from(j);
            let p = foot + (top - foot) * f;
            let az = (k * 5 + j as usize) as f64 * 137.5f64.to_radians();
            let leaf = organs::leaf(1.1 - 0.12 * f64::from(j), 0.22, -0.15, colour::LEAF, res);
            let rot = DMat3::from_rotation_z(az) * DMat3::from_rotation_y(-0.7);
            m.put(&leaf, p, rot, 1.0);
        }
    }
    Ok((m, counts))
}

/// Draws the models of this module that `want` names (`strawflower`,
/// `beargrass`, `kniphofia`) into `out`, small and coarse when `quick`.
///
/// # Errors
///
/// The models' errors; natura-core's if a picture cannot be drawn or
/// written.
pub fn draw(want: impl Fn(&str) -> bool, quick: bool, out: &std::path::Path) -> crate::common::Run {
    let (size, res) = if quick { (240, 1) } else { (700, 2) };
    if want("strawflower") {
        let (m, counts) = strawflowers(res)?;
        let view = View::along(Vec3::new(0.0, 1.0, -0.75)).zoomed(1.3);
        render(&m, &view, size, size)?.save_png(out.join("strawflower.png"))?;
        outln(format_args!("strawflower.png: heads of {counts:?} organs"))?;
    }
    if want("beargrass") {
        let (m, n) = beargrass(res)?;
        let view = View::along(Vec3::new(0.0, 1.0, -0.12)).zoomed(1.1);
        render(&m, &view, size, size)?.save_png(out.join("beargrass.png"))?;
        outln(format_args!("beargrass.png: {n} flowers"))?;
    }
    if want("kniphofia") {
        let mut m = Mesh::default();
        let mut counts = Vec::new();
        for (stage, x) in [(0.2, -1.6), (1.0, 1.6)] {
            let (spike, n) = kniphofia(stage, res)?;
            counts.push(n);
            m.put(&spike, DVec3::new(x, 0.0, 0.0), DMat3::IDENTITY, 1.0);
        }
        let view = View::along(Vec3::new(0.0, 1.0, -0.1)).zoomed(1.2);
        render(&m, &view, size, size)?.save_png(out.join("kniphofia.png"))?;
        outln(format_args!(
            "kniphofia.png: two stages of {counts:?} flowers"
        ))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_organ_faces_out_of_its_surface() {
        // On a cylinder of radius 2 the normal is radial and the tangent up;
        // on a disc drawn from its rim inwards the normal is up.
        let o = Organ {
            s: 1.0,
            x: 2.0,
            y: 1.0,
            angle_deg: 90.0,
            radius: 0.1,
        };
        let (at, rot) = organ_frame(&|s| (2.0, s), 3.0, &o);
        assert!((at - DVec3::new(0.0, 2.0, 1.0)).length() < 1e-9, "{at}");
        assert!((rot.z_axis - DVec3::Y).length() < 1e-9, "{}", rot.z_axis);
        assert!((rot.x_axis - DVec3::Z).length() < 1e-9, "{}", rot.x_axis);
        assert!((rot.determinant() - 1.0).abs() < 1e-9);
        let disc = Organ {
            x: 0.5,
            y: 0.0,
            angle_deg: 0.0,
            ..o
        };
        let (_, rot) = organ_frame(&|s| (1.5 - s, 0.0), 1.5, &disc);
        assert!((rot.z_axis - DVec3::Z).length() < 1e-9, "{}", rot.z_axis);
    }

    #[test]
    fn the_spike_carries_as_many_flowers_as_its_density_integrates_to() {
        // Algorithm 5 places an organ at each unit of N(0, s) = ∫ 2 f_x/ρ² ds;
        // the count against the integral by the trapezoid rule on 10⁵ steps.
        let (len, curve) = by_arc_length(
            |u| (0.35 * (1.0 - u.powi(4)).max(0.0).sqrt(), 6.0 * u),
            2048,
        );
        let rho = |s: f64| 0.17 - 0.06 * s / len;
        let n = 100_000;
        let f = |k: u32| {
            let s = len * f64::from(k) / f64::from(n);
            2.0 * curve(s).0 / (rho(s) * rho(s))
        };
        let integral = (1..n).map(f).sum::<f64>() * len / f64::from(n)
            + 0.5 * (f(0) + f(n)) * len / f64::from(n);
        let (_, flowers) = kniphofia(1.0, 1).unwrap();
        assert_eq!(flowers, integral.floor() as usize, "N = {integral}");
    }
}
