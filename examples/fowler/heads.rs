//! The flower heads, fruits and cacti of Fowler et al. 1992's figures:
//! primordia placed by natura-plant's collision model on the figure's
//! receptacle, then each replaced by its organ at its organ frame (§3.1).
//! Every head is built with its receptacle's axis along `+z` and its base
//! at the origin.

use natura::core::glam::{DMat3, DVec3, Vec3};
use natura::plant::models::phyllotaxis::{
    OrganFrame, PhyllotaxisParams, Primordium, Receptacle, organ_frames, phyllotaxis,
};

use super::mesh::Mesh;
use super::organs::{self, colour, mix};
use crate::common::Exit;

type R<T> = Result<T, Exit>;

/// A head: its mesh and how many organs the model placed.
pub struct Head {
    /// The mesh, base at the origin, axis `+z`.
    pub mesh: Mesh,
    /// Primordia placed (of the outer level, for compound heads).
    pub organs: usize,
}

/// The collision model on `receptacle` with radii `r_base` to `r_tip`
/// between `t_min` and `t_max`: the primordia and their organ frames.
pub fn place(
    receptacle: Receptacle,
    r_base: f64,
    r_tip: f64,
    t: [f64; 2],
) -> R<(Vec<Primordium>, Vec<OrganFrame>)> {
    let p = PhyllotaxisParams {
        receptacle,
        r_base,
        r_tip,
        t_min: t[0],
        t_max: t[1],
        ..PhyllotaxisParams::default()
    };
    let v = phyllotaxis(&p)?;
    let f = organ_frames(&p.receptacle, &v)?;
    Ok((v, f))
}

/// A number in `[0, 1)` fixed by `k` and `salt` (SplitMix64): the organs'
/// small variations, the same on every run.
pub fn jitter(k: usize, salt: u64) -> f64 {
    let mut z = (k as u64).wrapping_add(salt.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

/// The receptacle's own surface, shrunk by `inset` along its normal, so
/// the gaps between organs show it rather than the background.
pub fn receptacle_surface(r: &Receptacle, inset: f64, body: Vec3, res: u32) -> Mesh {
    let mut m = Mesh::default();
    m.patch(
        16 * res,
        8 * res,
        |u, v| {
            let phi = u * std::f64::consts::TAU;
            let (d0, d1) = r.derivative(v.clamp(1e-4, 1.0 - 1e-4));
            let n = DVec3::new(d1 * phi.cos(), d1 * phi.sin(), -d0).normalize_or(DVec3::Z);
            r.point(phi, v) - n * inset
        },
        |_, _| body,
    );
    m
}

/// A stem from `a` to `b`.
pub fn stem(m: &mut Mesh, a: DVec3, b: DVec3, r: f64) {
    m.tube(a, b, r, 8, colour::LEAF * 1.3);
}

/// Fig. 4: green coneflower (*Rudbeckia laciniata*). A conical
/// receptacle; three organ types: drooping ray florets on the first ring,
/// open disk florets on the lower cone and closed ones above, the disk
/// florets shrinking linearly towards the tip.
pub fn coneflower(res: u32) -> R<Head> {
    let rec = Receptacle::Cone {
        radius: 1.0,
        height: 1.5,
    };
    let (v, f) = place(rec.clone(), 0.12, 0.05, [0.0, 1.0])?;
    let mut m = receptacle_surface(&rec, 0.05, Vec3::new(0.12, 0.18, 0.03), res);
    for (k, (q, o)) in v.iter().zip(&f).enumerate() {
        let organ = if q.t < 1e-9 {
            let len = 2.6 * (0.9 + 0.2 * jitter(k, 1)) / o.scale;
            let shade = 0.85 + 0.15 * jitter(k, 2) as f32;
            organs::petal(
                len,
                2.0,
                0.9,
                -1.6,
                colour::GOLD * 0.8,
                colour::GOLD * shade,
                res,
            )
        } else if q.t < 0.42 {
            organs::open_floret(1.3, Vec3::new(0.75, 0.6, 0.08), res)
        } else {
            let s = (q.t - 0.42) / 0.58;
            organs::bud(
                1.5,
                0.95,
                Vec3::new(0.15, 0.3, 0.04),
                mix(Vec3::new(0.4, 0.55, 0.1), Vec3::new(0.3, 0.45, 0.06), s),
                res,
            )
        };
        m.place(&organ, o);
    }
    stem(&mut m, DVec3::new(0.0, 0.0, -5.0), DVec3::ZERO, 0.12);
    Ok(Head {
        mesh: m,
        organs: v.len(),
    })
}

/// A low dome of height `h` over a disc of radius 1 (Fig. 5's "almost
/// flat" receptacles), as one Bézier curve.
pub fn low_dome(h: f64) -> Receptacle {
    Receptacle::Bezier {
        segments: vec![[[1.0, 0.0], [0.7, 0.5 * h], [0.35, h], [0.0, h]]],
    }
}

/// Fig. 5: a daisy: white ray florets on the first ring of a nearly flat
/// head, yellow disk florets shrinking towards the centre.
pub fn daisy(petal: Vec3, res: u32) -> R<Head> {
    let rec = low_dome(0.25);
    let (v, f) = place(rec.clone(), 0.085, 0.03, [0.0, 1.0])?;
    let mut m = receptacle_surface(&rec, 0.03, Vec3::new(0.4, 0.25, 0.02), res);
    let dome = organs::bud(0.9, 1.0, colour::YELLOW * 0.7, colour::YELLOW, res);
    for (k, (q, o)) in v.iter().zip(&f).enumerate() {
        if q.t < 1e-9 {
            let len = 1.5 * (0.92 + 0.16 * jitter(k, 3)) / o.scale;
            let p = organs::petal(len, 2.6, 0.1, -0.15, petal * 0.8, petal, res);
            m.place(&p, o);
        } else {
            let mut d = dome.clone();
            d.tint(Vec3::splat(0.85 + 0.3 * (q.t as f32)));
            m.place(&d, o);
        }
    }
    Ok(Head {
        mesh: m,
        organs: v.len(),
    })
}

/// Fig. 5: a chrysanthemum: every organ a ray floret, shorter and more
/// upright towards the centre, so the head closes into a ball.
pub fn chrysanthemum(body: Vec3, res: u32) -> R<Head> {
    let rec = low_dome(0.4);
    let (v, f) = place(rec.clone(), 0.075, 0.04, [0.0, 0.97])?;
    let mut m = receptacle_surface(&rec, 0.03, body * 0.4, res);
    for (k, (q, o)) in v.iter().zip(&f).enumerate() {
        let len = (1.1 * (1.0 - q.t) + 0.3) * (0.95 + 0.1 * jitter(k, 4)) / o.scale;
        let rise = 0.15 + 1.25 * q.t;
        let p = organs::petal(len, 2.4, rise, 0.5, body * 0.55, body, res);
        m.place(&p, o);
    }
    Ok(Head {
        mesh: m,
        organs: v.len(),
    })
}

/// Fig. 6: a raspberry: drupelets as intersecting spheres on a spherical
/// receptacle, the bottom left to the calyx.
pub fn raspberry(res: u32, salt: u64) -> R<Head> {
    let rec = Receptacle::Sphere { radius: 1.0 };
    let (v, f) = place(rec.clone(), 0.19, 0.17, [0.12, 1.0])?;
    let mut m = receptacle_surface(&rec, 0.1, Vec3::new(0.25, 0.01, 0.03), res);
    for (k, o) in f.iter().enumerate() {
        let c = Vec3::new(0.5, 0.02, 0.05) * (0.75 + 0.45 * jitter(k, salt) as f32);
        let mut d = Mesh::default();
        d.sphere(DVec3::ZERO, 1.28, 3 * res, c);
        m.place(&d, o);
    }
    // The calyx: five green sepals under the berry.
    for k in 0..5 {
        let a = f64::from(k) * std::f64::consts::TAU / 5.0 + 0.3;
        let l = organs::leaf(0.9, 0.45, -0.1, colour::LEAF, res);
        let rot = DMat3::from_rotation_z(a) * DMat3::from_rotation_y(0.5);
        m.put(&l, DVec3::new(0.0, 0.0, -0.95), rot, 1.0);
    }
    stem(
        &mut m,
        DVec3::new(0.0, 0.0, -1.6),
        DVec3::new(0.0, 0.0, -0.9),
        0.08,
    );
    Ok(Head {
        mesh: m,
        organs: v.len(),
    })
}

/// Fig. 7: buttonbush (*Cephalanthus occidentalis*): a small spherical
/// receptacle in the centre, its flowers at the ends of long pedicels
/// forming a much larger ball.
pub fn buttonbush(res: u32) -> R<Head> {
    let rec = Receptacle::Sphere { radius: 1.0 };
    let (v, f) = place(rec.clone(), 0.16, 0.16, [0.0, 1.0])?;
    let mut m = receptacle_surface(&rec, 0.0, Vec3::new(0.3, 0.35, 0.1), res);
    for (k, o) in f.iter().enumerate() {
        let s = o.scale;
        let len = (1.6 + 0.2 * jitter(k, 5)) / s;
        let mut fl = Mesh::default();
        fl.tube(
            DVec3::ZERO,
            DVec3::Z * len,
            0.25,
            4,
            Vec3::new(0.45, 0.5, 0.2),
        );
        fl.revolve(
            8 * res,
            3 * res,
            |t| (0.35 + 1.3 * t * t * t, len + 4.0 * t),
            |a| 1.0 + 0.3 * (4.0 * a).cos(),
            |t| mix(Vec3::new(0.6, 0.65, 0.45), Vec3::new(0.95, 0.95, 0.9), t),
        );
        // The long style with its knob.
        let top = DVec3::Z * (len + 7.0);
        fl.tube(DVec3::Z * len, top, 0.12, 3, Vec3::new(0.9, 0.88, 0.75));
        fl.sphere(top, 0.4, 3, Vec3::new(0.85, 0.75, 0.35));
        m.place(&fl, o);
    }
    Ok(Head {
        mesh: m,
        organs: v.len(),
    })
}

/// Fig. 8: the seed head of goatsbeard (*Tragopogon dubius*): achenes on
/// a spherical receptacle, each carrying a parachute whose rays are
/// arranged by the same model.
pub fn goatsbeard(res: u32) -> R<Head> {
    let rec = Receptacle::Sphere { radius: 1.0 };
    let (v, f) = place(rec.clone(), 0.16, 0.16, [0.14, 1.0])?;
    let mut m = receptacle_surface(&rec, 0.05, Vec3::new(0.35, 0.3, 0.15), res);
    let s = f.first().map_or(1.0, |o| o.scale);
    let seed = organs::parachute_seed(2.2 / s, 3.6 / s, 21, 3.0 / s, res);
    for o in &f {
        m.place(&seed, o);
    }
    stem(
        &mut m,
        DVec3::new(0.0, 0.0, -7.0),
        DVec3::new(0.0, 0.0, -0.8),
        0.14,
    );
    Ok(Head {
        mesh: m,
        organs: v.len(),
    })
}

/// A columnar cactus body, `height` tall, as two Bézier curves: the side,
/// then the dome.
pub fn cactus_body(height: f64) -> Receptacle {
    let h = height;
    Receptacle::Bezier {
        segments: vec![
            [
                [0.85, 0.0],
                [1.05, 0.25 * h],
                [1.05, 0.55 * h],
                [1.0, 0.7 * h],
            ],
            [[1.0, 0.7 * h], [0.95, 0.9 * h], [0.55, h], [0.0, h]],
        ],
    }
}

/// Fig. 9's *Mammillaria geminispina*: a short body (1.6) with white
/// spines 0.3 long, brown at the tips (also the short cactus of Fig. 11).
pub fn geminispina(res: u32) -> R<Head> {
    mammillaria(
        1.6,
        0.3,
        Vec3::new(0.9, 0.9, 0.86),
        Vec3::new(0.35, 0.2, 0.1),
        res,
    )
}

/// Fig. 9 (and 11): a *Mammillaria*: tubercles in a spiral on the cactus
/// body, each with its cluster of spines. `spines` and `tips` colour them;
/// `length` is the spines' length.
pub fn mammillaria(height: f64, length: f64, spines: Vec3, tips: Vec3, res: u32) -> R<Head> {
    let rec = cactus_body(height);
    let (v, f) = place(rec.clone(), 0.13, 0.09, [0.0, 0.985])?;
    let mut m = receptacle_surface(&rec, 0.02, Vec3::new(0.04, 0.14, 0.05), res);
    for o in &f {
        let t = organs::tubercle(1.2, 18, length / o.scale, spines, tips, res);
        m.place(&t, o);
    }
    Ok(Head {
        mesh: m,
        organs: v.len(),
    })
}

/// A dome: a quarter circle from the rim to the top, as one Bézier curve.
pub fn dome() -> Receptacle {
    let k = 0.552_284_749_8;
    Receptacle::Bezier {
        segments: vec![[[1.0, 0.0], [1.0, k], [k, 1.0], [0.0, 1.0]]],
    }
}

/// Fig. 10: a cauliflower or broccoli: two levels of the model. Florets
/// on a dome, each on a stalk `stalk` long and carrying its own
/// phyllotactic head of buds (`buds` coloured), a dome in turn.
pub fn brassica(stalk: f64, buds: Vec3, leaves: bool, res: u32) -> R<Head> {
    let rec = dome();
    let (v, f) = place(rec.clone(), 0.2, 0.13, [0.1, 0.99])?;
    let inner = dome();
    let (_, fi) = place(inner.clone(), 0.16, 0.11, [0.0, 0.98])?;
    // One floret: stalk, its small dome, its buds.
    let mut floret = Mesh::default();
    let lift = DVec3::Z * stalk;
    floret.tube(
        DVec3::ZERO,
        lift,
        0.45,
        6,
        mix(buds, Vec3::new(0.6, 0.65, 0.4), 0.6),
    );
    let mut head = receptacle_surface(&inner, 0.05, buds * 0.6, res);
    for o in &fi {
        let mut b = Mesh::default();
        b.sphere(DVec3::ZERO, 1.25, 2 * res + 1, buds);
        head.place(&b, o);
    }
    floret.put(&head, lift, DMat3::IDENTITY, 1.35);
    let mut m = receptacle_surface(&rec, 0.05, buds * 0.5, res);
    for (k, o) in f.iter().enumerate() {
        let mut fl = floret.clone();
        fl.tint(Vec3::splat(0.85 + 0.3 * jitter(k, 6) as f32));
        m.place(&fl, o);
    }
    if leaves {
        for k in 0..7 {
            let a = f64::from(k) * 137.5f64.to_radians();
            let l = organs::leaf(2.4, 1.6, 0.12, Vec3::new(0.08, 0.25, 0.1), res);
            let rot = DMat3::from_rotation_z(a) * DMat3::from_rotation_y(-0.25);
            m.put(&l, DVec3::new(0.0, 0.0, -0.2), rot, 1.0);
        }
    } else {
        stem(&mut m, DVec3::new(0.0, 0.0, -2.0), DVec3::ZERO, 0.45);
    }
    Ok(Head {
        mesh: m,
        organs: v.len() * fi.len(),
    })
}

/// Fig. 13: a grape hyacinth (*Muscari*): an elongated raceme of bells,
/// dark blue below, paler and smaller towards the tip.
pub fn grape_hyacinth(res: u32) -> R<Head> {
    let rec = Receptacle::Bezier {
        segments: vec![[[0.3, 0.0], [0.4, 1.0], [0.35, 2.2], [0.0, 2.6]]],
    };
    let (v, f) = place(rec.clone(), 0.16, 0.09, [0.0, 0.99])?;
    let mut m = receptacle_surface(&rec, 0.0, Vec3::new(0.04, 0.05, 0.2), res);
    for (q, o) in v.iter().zip(&f) {
        let body = mix(
            Vec3::new(0.05, 0.05, 0.4),
            Vec3::new(0.3, 0.3, 0.75),
            (q.t - 0.5) / 0.5,
        );
        // Lower bells hang towards the base; upper ones point outwards.
        let axis = DVec3::new(-0.8 + 0.6 * q.t, 0.0, 0.6).normalize();
        let b = organs::bell(axis, 2.3, 2.3, body, res);
        m.place(&b, o);
    }
    stem(
        &mut m,
        DVec3::new(0.0, 0.0, -3.0),
        DVec3::new(0.0, 0.0, 0.05),
        0.09,
    );
    Ok(Head {
        mesh: m,
        organs: v.len(),
    })
}

/// Fig. 14: an inflorescence of water smartweed (*Persicaria amphibia*):
/// a dense oblong spike of small pink flowers.
pub fn smartweed(res: u32) -> R<Head> {
    let rec = Receptacle::Bezier {
        segments: vec![[[0.22, 0.0], [0.3, 0.9], [0.3, 1.7], [0.0, 2.0]]],
    };
    let (v, f) = place(rec.clone(), 0.085, 0.07, [0.0, 0.99])?;
    let mut m = receptacle_surface(&rec, 0.0, Vec3::new(0.35, 0.1, 0.12), res);
    for (k, (q, o)) in v.iter().zip(&f).enumerate() {
        let pink = Vec3::new(0.85, 0.22, 0.35) * (0.8 + 0.3 * jitter(k, 7) as f32);
        let axis = DVec3::new(0.35, 0.0, 1.0).normalize();
        let c = if q.t > 0.75 {
            organs::bud(1.4, 0.9, pink * 0.7, pink, res)
        } else {
            organs::cup(axis, 1.4, pink, res)
        };
        m.place(&c, o);
    }
    stem(
        &mut m,
        DVec3::new(0.0, 0.0, -3.0),
        DVec3::new(0.0, 0.0, 0.05),
        0.06,
    );
    Ok(Head {
        mesh: m,
        organs: v.len(),
    })
}
