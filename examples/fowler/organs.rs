//! The organs that replace the primordia (Fowler et al. 1992, §3.1), each
//! a small mesh in the organ's own frame: contact point at the origin,
//! `+z` the receptacle's normal, `+x` the generating curve's tangent
//! (towards the tip), one unit the primordium's radius. The source models
//! them as Bézier surfaces; here they are parametric patches and surfaces
//! of revolution, tessellated at `res` (1 coarse, 2 fine).

use std::f64::consts::PI;

use natura::core::glam::{DMat3, DVec3, Vec3};

use super::mesh::Mesh;

/// Linear RGB colours of the figures.
pub mod colour {
    use natura::core::glam::Vec3;
    /// Stems and leaves.
    pub const LEAF: Vec3 = Vec3::new(0.06, 0.22, 0.04);
    /// Ray petals of the coneflower.
    pub const GOLD: Vec3 = Vec3::new(0.95, 0.62, 0.02);
    /// Daisy petals, pappus, spines.
    pub const WHITE: Vec3 = Vec3::new(0.88, 0.88, 0.84);
    /// Disk florets of a daisy.
    pub const YELLOW: Vec3 = Vec3::new(0.9, 0.55, 0.02);
}

/// A mix of `a` and `b`, `s` of the way to `b`.
pub fn mix(a: Vec3, b: Vec3, s: f64) -> Vec3 {
    a + (b - a) * s.clamp(0.0, 1.0) as f32
}

/// A strap-shaped petal (ray floret) reaching outwards along `−x`: `len`
/// long, `width` wide, leaving the receptacle at `rise` radians above its
/// tangent plane and bending by `bend` radians along its length, cupped
/// across; `base` to `tip` colour.
pub fn petal(len: f64, width: f64, rise: f64, bend: f64, base: Vec3, tip: Vec3, res: u32) -> Mesh {
    // The midrib: θ(u) = rise + bend·u, integrated in closed form.
    let mid = move |u: f64| {
        let (a, b) = (rise, bend);
        if b.abs() < 1e-9 {
            DVec3::new(-len * u * a.cos(), 0.0, len * u * a.sin())
        } else {
            DVec3::new(
                -len * ((a + b * u).sin() - a.sin()) / b,
                0.0,
                len * (a.cos() - (a + b * u).cos()) / b,
            )
        }
    };
    let mut m = Mesh::default();
    m.patch(
        8 * res,
        2 * res,
        |u, v| {
            let w = width
                * (4.0 * u * (1.0 - u))
                    .max(0.0)
                    .powf(0.45)
                    .max(0.12 * (1.0 - u));
            let across = 2.0 * v - 1.0;
            let p = mid(u);
            // Normal to the midrib in the x-z plane, for the cup.
            let th = rise + bend * u;
            let up = DVec3::new(th.sin(), 0.0, th.cos());
            p + DVec3::new(0.0, 0.5 * w * across, 0.0) + up * (0.18 * w * across * across)
        },
        |u, _| mix(base, tip, u.powf(0.5)),
    );
    m
}

/// A disk floret, open: a short tube flaring into five lobes, `height`
/// tall, green at the foot and `top` at the lobes.
pub fn open_floret(height: f64, top: Vec3, res: u32) -> Mesh {
    let mut m = Mesh::default();
    m.revolve(
        10 * res,
        3 * res,
        |s| (0.45 + 0.5 * s * s * s, height * s),
        |a| 1.0 + 0.22 * (5.0 * a).cos(),
        |s| mix(Vec3::new(0.2, 0.3, 0.04), top, s * s),
    );
    // The style in the middle.
    m.tube(DVec3::ZERO, DVec3::Z * height * 1.25, 0.12, 4, top * 0.6);
    m
}

/// A closed bud: an egg `height` tall and `radius` wide, `bottom` to `top`.
pub fn bud(height: f64, radius: f64, bottom: Vec3, top: Vec3, res: u32) -> Mesh {
    let mut m = Mesh::default();
    m.revolve(
        8 * res,
        4 * res,
        |s| {
            (
                radius * (PI * s).sin().max(0.0).powf(0.7),
                height * (1.0 - (PI * s).cos()) / 2.0,
            )
        },
        |_| 1.0,
        |s| mix(bottom, top, s),
    );
    m
}

/// A bell (the urn-shaped flower of the grape hyacinth), hanging from the
/// contact point along `axis` (a unit vector of the organ's frame): `len`
/// long, `width` wide, closing to a narrow mouth with a white rim.
pub fn bell(axis: DVec3, len: f64, width: f64, body: Vec3, res: u32) -> Mesh {
    let mut b = Mesh::default();
    b.revolve(
        8 * res,
        5 * res,
        |s| {
            let r = if s < 0.85 {
                width * (0.3 + 0.7 * (PI * s / 0.85).sin().powf(0.6)).min(1.0)
            } else {
                width * (0.35 + 0.6 * (s - 0.85) / 0.15)
            };
            (r * 0.5, len * s)
        },
        |a| 1.0 + 0.06 * (6.0 * a).cos(),
        |s| {
            if s > 0.9 {
                mix(body, Vec3::splat(0.85), 0.8)
            } else {
                mix(body * 0.6, body, s)
            }
        },
    );
    let mut m = Mesh::default();
    m.append(
        &b,
        |p| super::mesh::along(axis, p),
        |n| super::mesh::along(axis, n),
    );
    m
}

/// A small flower open to the front (water smartweed): a cup of five
/// rounded lobes, `size` across, pointing along `axis`.
pub fn cup(axis: DVec3, size: f64, body: Vec3, res: u32) -> Mesh {
    let mut c = Mesh::default();
    c.revolve(
        10 * res,
        2 * res,
        |s| (size * (0.25 + 0.5 * s), size * 0.7 * s.sqrt()),
        |a| 1.0 + 0.25 * (5.0 * a).cos(),
        |s| mix(body * 0.55, body, s),
    );
    c.sphere(
        DVec3::Z * size * 0.45,
        size * 0.12,
        3,
        Vec3::new(0.8, 0.7, 0.5),
    );
    let mut m = Mesh::default();
    m.append(
        &c,
        |p| super::mesh::along(axis, p),
        |n| super::mesh::along(axis, n),
    );
    m
}

/// A tubercle of a cactus with its cluster of spines (Fig. 9): a green
/// cone `height` tall, an areole of white wool and `radial` spines spread
/// by the divergence angle around it (the source's compound use of the
/// model), with two central spines; spines `spine` long, `spines` in
/// colour, their tips `tips`.
pub fn tubercle(height: f64, radial: u32, spine: f64, spines: Vec3, tips: Vec3, res: u32) -> Mesh {
    let mut m = Mesh::default();
    m.revolve(
        8 * res,
        2 * res,
        |s| (1.0 - 0.65 * s, height * s),
        |_| 1.0,
        |s| mix(Vec3::new(0.05, 0.2, 0.08), Vec3::new(0.12, 0.3, 0.12), s),
    );
    let top = DVec3::Z * height;
    m.sphere(top, 0.32, 3, Vec3::new(0.8, 0.78, 0.7));
    let golden = 137.507_764_f64.to_radians();
    let thin = 0.035 * spine.max(1.0);
    for k in 0..radial {
        let a = f64::from(k) * golden;
        let d = DVec3::new(a.cos(), a.sin(), 0.35).normalize();
        spike(&mut m, top, d * spine, thin, spines, tips);
    }
    for d in [DVec3::new(0.35, 0.2, 1.0), DVec3::new(-0.3, -0.25, 1.0)] {
        spike(
            &mut m,
            top,
            d.normalize() * spine * 1.3,
            thin * 1.3,
            spines,
            tips,
        );
    }
    m
}

/// A spine: a thin tube from `at` along `d`, coloured towards its tip.
fn spike(m: &mut Mesh, at: DVec3, d: DVec3, r: f64, body: Vec3, tip: Vec3) {
    let mid = at + d * 0.7;
    m.tube(at, mid, r, 3, body);
    m.tube(mid, at + d, r * 0.6, 3, tip);
}

/// A goatsbeard achene with its parachute (Fig. 8): a ribbed seed, a long
/// beak, and a pappus of `rays` feathery bristles whose directions are
/// spread by the divergence angle (the compound use of the model).
pub fn parachute_seed(seed: f64, beak: f64, rays: u32, ray_len: f64, res: u32) -> Mesh {
    let mut m = Mesh::default();
    m.revolve(
        6 * res,
        4 * res,
        |s| (0.32 * (PI * s).sin().powf(0.6), seed * s),
        |a| 1.0 + 0.12 * (10.0 * a).cos(),
        |s| mix(Vec3::new(0.25, 0.16, 0.06), Vec3::new(0.45, 0.33, 0.15), s),
    );
    let top = DVec3::Z * (seed + beak);
    m.tube(
        DVec3::Z * seed * 0.95,
        top,
        0.06,
        3,
        Vec3::new(0.6, 0.55, 0.4),
    );
    let golden = 137.507_764_f64.to_radians();
    for k in 0..rays {
        let a = f64::from(k) * golden;
        // Rays on a shallow cone, longer near the rim of the umbrella.
        let f = (f64::from(k) + 0.5) / f64::from(rays);
        let d = DVec3::new(a.cos(), a.sin(), 0.55 - 0.35 * f).normalize();
        let end = top + d * ray_len;
        m.tube(top, end, 0.05, 3, colour::WHITE * 0.95);
        // Side hairs make the bristle feathery.
        let side = d.cross(DVec3::Z).normalize_or(DVec3::X);
        for j in 1..4 {
            let at = top + d * ray_len * f64::from(j) / 4.0;
            let l = 0.18 * ray_len;
            m.tube(at, at + (d + side) * l * 0.5, 0.025, 3, colour::WHITE * 0.9);
            m.tube(at, at + (d - side) * l * 0.5, 0.025, 3, colour::WHITE * 0.9);
        }
    }
    m
}

/// A leaf blade: an ellipse-like patch `len` long and `width` wide along
/// `+x` from the origin, lying in the x-y plane and arching by `arch`.
pub fn leaf(len: f64, width: f64, arch: f64, body: Vec3, res: u32) -> Mesh {
    let mut m = Mesh::default();
    m.patch(
        10 * res,
        3 * res,
        |u, v| {
            let w = width * (PI * u).sin().max(0.0).powf(0.7);
            let a = 2.0 * v - 1.0;
            DVec3::new(
                len * u,
                0.5 * w * a,
                arch * 4.0 * u * (1.0 - u) * len + 0.1 * w * a * a,
            )
        },
        |_, v| mix(body, body * 1.4, 1.0 - (2.0 * v - 1.0).abs()),
    );
    m
}

/// Turns the organ frame's `+z` towards `d` (a rotation for [`Mesh::put`]).
pub fn aim(d: DVec3) -> DMat3 {
    let z = d.normalize();
    let x = if z.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let y = z.cross(x).normalize();
    DMat3::from_cols(y.cross(z), y, z)
}
