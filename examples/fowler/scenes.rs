//! The figures of Fowler et al. 1992 that show several heads: berries on
//! a plate, buttonbush balls on a twig, cauliflowers and broccoli, grape
//! hyacinths, water smartweed, and the composed scenes (a table of cacti,
//! a flower shop whose pots are filled by the same model, a window sill).

use natura::core::Image;
use natura::core::glam::{DMat3, DVec3, Vec3};
use natura::plant::models::phyllotaxis::Receptacle;

use super::heads::{self, Head};
use super::mesh::{Mesh, View, render};
use super::organs::{self, colour};
use crate::common::Exit;
use crate::{Detail, report, tilt};

type R<T> = Result<T, Exit>;

/// A clay pot of top radius `r` and height `h` standing at `at`, its soil
/// surface `0.1 h` below the rim.
fn pot(m: &mut Mesh, at: DVec3, r: f64, h: f64, res: u32) {
    let mut p = Mesh::default();
    p.revolve(
        24 * res,
        4,
        |s| {
            if s < 0.8 {
                (r * (0.72 + 0.28 * s / 0.8), h * s / 0.8 * 0.82)
            } else {
                (r * 1.08, h * (0.82 + 0.18 * (s - 0.8) / 0.2))
            }
        },
        |_| 1.0,
        |s| {
            if s < 0.8 {
                Vec3::new(0.45, 0.15, 0.06)
            } else {
                Vec3::new(0.52, 0.19, 0.08)
            }
        },
    );
    p.revolve(
        24 * res,
        2,
        |s| (r * 1.0 * (1.0 - s), h * 0.9),
        |_| 1.0,
        |_| Vec3::new(0.12, 0.07, 0.03),
    );
    m.put(&p, at, DMat3::IDENTITY, 1.0);
}

/// Where `n` stems stand in a pot's soil of radius `r`: the collision
/// model on a flat disc (Fig. 12: "the soil surface was considered as a
/// large, almost flat receptacle"), primordia of radius `spacing`.
fn stems_in_pot(r: f64, spacing: f64, n: usize) -> R<Vec<DVec3>> {
    let (v, _) = heads::place(Receptacle::Disc { radius: r }, spacing, spacing, [0.0, 1.0])?;
    Ok(v.iter().rev().take(n).map(|q| q.centre).collect())
}

/// A pot at `at` planted with `head` on stems placed by the model.
#[allow(clippy::too_many_arguments)]
fn planted(
    m: &mut Mesh,
    head: &Mesh,
    at: DVec3,
    r: f64,
    h: f64,
    scale: f64,
    stem_h: f64,
    res: u32,
    salt: u64,
) -> R<()> {
    pot(m, at, r, h, res);
    let soil = at + DVec3::Z * h * 0.9;
    for (k, c) in stems_in_pot(r * 0.85, r * 0.22, 12)?.iter().enumerate() {
        let lean = DVec3::new(c.x, c.y, 0.0) * 0.35 / r;
        let tall = stem_h * (0.8 + 0.4 * heads::jitter(k, salt));
        let top = soil + *c + (DVec3::Z + lean) * tall;
        heads::stem(m, soil + *c, top, 0.025);
        let dir = (DVec3::Z + lean * 1.5).normalize();
        m.put(head, top, organs::aim(dir), scale);
    }
    Ok(())
}

/// A table top from `(x0, y0)` to `(x1, y1)` at height `z`.
fn table(m: &mut Mesh, x: [f64; 2], y: [f64; 2], z: f64, c: Vec3) {
    m.slab(
        DVec3::new(x[0], y[0], z - 0.2),
        DVec3::new(x[1], y[1], z),
        c,
    );
}

/// Fig. 6: raspberries on a plate.
pub fn raspberries(res: u32, d: Detail) -> R<Image> {
    let mut s = Mesh::default();
    let berries: Vec<Head> = (0..3)
        .map(|k| heads::raspberry(res, 11 + k))
        .collect::<R<_>>()?;
    report("raspberry", &berries[0])?;
    let spots = [
        ([0.0, 0.0, 1.0], 0.3, 0.0),
        ([2.1, 0.5, 1.0], -0.4, 1.0),
        ([-2.0, 0.7, 1.0], 0.5, 2.0),
        ([0.9, 2.2, 1.0], -1.2, 0.5),
        ([-1.0, 2.3, 1.0], 1.4, 2.5),
        ([1.1, -1.8, 1.0], 1.6, 1.5),
        ([-1.2, -1.7, 1.0], -1.5, 0.2),
    ];
    for (k, (at, a, b)) in spots.iter().enumerate() {
        s.put(
            &berries[k % 3].mesh,
            DVec3::from_array(*at),
            tilt(*a, *b),
            1.0,
        );
    }
    let mut plate = Mesh::default();
    plate.revolve(
        48,
        3,
        |t| (4.3 * t.sqrt(), -0.05 + 0.25 * t * t),
        |_| 1.0,
        |_| Vec3::new(0.8, 0.8, 0.78),
    );
    s.put(&plate, DVec3::ZERO, DMat3::IDENTITY, 1.0);
    render(
        &s,
        &View::along(Vec3::new(0.0, 1.0, -0.8)).zoomed(1.5),
        d.size * 4 / 3,
        d.size,
    )
}

/// Fig. 7: balls of buttonbush flowers at the ends of a leafy twig.
pub fn buttonbush(res: u32, d: Detail) -> R<Image> {
    let ball = heads::buttonbush(res)?;
    report("buttonbush", &ball)?;
    let mut s = Mesh::default();
    let twig = Vec3::new(0.3, 0.25, 0.15);
    let tips = [
        DVec3::new(-4.0, 0.0, 4.5),
        DVec3::new(4.5, 1.0, 5.0),
        DVec3::new(0.3, -0.5, 8.5),
    ];
    let base = DVec3::new(0.0, 0.0, -4.0);
    let fork = DVec3::new(0.0, 0.0, 1.0);
    s.tube(base, fork, 0.25, 8, twig);
    for (k, t) in tips.iter().enumerate() {
        let foot = *t - (*t - fork).normalize() * 4.4;
        s.tube(fork, foot, 0.16, 8, twig);
        s.put(&ball.mesh, *t, organs::aim(*t - fork), 1.0);
        for j in 0..2 {
            let a = f64::from(j as u32) * 3.1 + k as f64;
            let leaf = organs::leaf(3.6, 1.5, 0.1, colour::LEAF * 1.2, res);
            let at = fork + (foot - fork) * 0.6;
            s.put(
                &leaf,
                at,
                DMat3::from_rotation_z(a) * DMat3::from_rotation_y(-0.3),
                1.0,
            );
        }
    }
    render(
        &s,
        &View::along(Vec3::new(0.0, 1.0, -0.2)).zoomed(1.25),
        d.size,
        d.size,
    )
}

/// Fig. 10: a cauliflower in its leaves and two broccoli heads.
pub fn brassicas(res: u32, d: Detail) -> R<Image> {
    let cauli = heads::brassica(1.2, Vec3::new(0.78, 0.72, 0.5), true, res)?;
    let broc = heads::brassica(2.4, Vec3::new(0.07, 0.22, 0.06), false, res)?;
    report("cauliflower (florets × buds)", &cauli)?;
    report("broccoli (florets × buds)", &broc)?;
    let mut s = Mesh::default();
    s.put(&cauli.mesh, DVec3::ZERO, DMat3::IDENTITY, 1.0);
    s.put(&broc.mesh, DVec3::new(3.0, 1.8, 0.5), tilt(0.2, 0.6), 0.85);
    s.put(
        &broc.mesh,
        DVec3::new(-3.0, 2.0, 0.4),
        tilt(-0.25, -0.4),
        0.8,
    );
    render(
        &s,
        &View::along(Vec3::new(0.0, 1.0, -0.7)).zoomed(1.6),
        d.size * 4 / 3,
        d.size,
    )
}

/// Fig. 13: grape hyacinths among their strap leaves.
pub fn grape_hyacinths(res: u32, d: Detail) -> R<Image> {
    let h = heads::grape_hyacinth(res)?;
    report("grape hyacinth", &h)?;
    let mut s = Mesh::default();
    let spots = [
        [0.0, 0.0, 0.0],
        [-1.6, 0.8, -0.6],
        [1.5, 0.6, -0.3],
        [0.6, 1.8, -0.9],
    ];
    for (k, at) in spots.iter().enumerate() {
        let a = 0.08 * (k as f64 - 1.5);
        s.put(
            &h.mesh,
            DVec3::from_array(*at),
            tilt(a, 0.3 * k as f64),
            1.0,
        );
    }
    for k in 0..9 {
        let a = f64::from(k) * 2.4;
        let leaf = organs::leaf(4.0, 0.35, 0.12, colour::LEAF * 1.3, res);
        let rot = DMat3::from_rotation_z(a) * DMat3::from_rotation_y(-1.2);
        s.put(&leaf, DVec3::new(0.0, 0.5, -3.0), rot, 1.0);
    }
    render(
        &s,
        &View::along(Vec3::new(0.0, 1.0, -0.25)).zoomed(1.3),
        d.size,
        d.size,
    )
}

/// Fig. 14: three spikes of water smartweed over floating leaves.
pub fn smartweed(res: u32, d: Detail) -> R<Image> {
    let h = heads::smartweed(res)?;
    report("water smartweed", &h)?;
    let mut s = Mesh::default();
    let spots = [[0.0, 0.0, 0.0], [-1.3, 0.9, -0.4], [1.4, 0.7, -0.7]];
    for (k, at) in spots.iter().enumerate() {
        s.put(
            &h.mesh,
            DVec3::from_array(*at),
            tilt(0.15 * (k as f64 - 1.0), 0.0),
            1.0,
        );
    }
    for k in 0..5 {
        let a = f64::from(k) * 1.3;
        let leaf = organs::leaf(3.0, 1.1, 0.02, colour::LEAF * 1.1, res);
        s.put(
            &leaf,
            DVec3::new(0.0, 0.6, -3.0),
            DMat3::from_rotation_z(a),
            1.0,
        );
    }
    render(
        &s,
        &View::along(Vec3::new(0.0, 1.0, -0.3)).zoomed(1.3),
        d.size,
        d.size,
    )
}

/// The cacti of Fig. 11: a short *M. geminispina* (white spines, brown
/// tips) and an elongated *M. spinosissima* (red-brown spines).
fn cactus_pair(res: u32) -> R<(Head, Head)> {
    let gem = heads::geminispina(res)?;
    let spin = heads::mammillaria(
        3.6,
        0.22,
        Vec3::new(0.75, 0.55, 0.45),
        Vec3::new(0.5, 0.1, 0.05),
        res,
    )?;
    Ok((gem, spin))
}

/// Fig. 11: a table of cacti in pots.
pub fn cacti(res: u32, d: Detail) -> R<Image> {
    let (gem, spin) = cactus_pair(res)?;
    report("M. geminispina", &gem)?;
    report("M. spinosissima", &spin)?;
    let mut s = Mesh::default();
    table(
        &mut s,
        [-8.0, 8.0],
        [-3.0, 5.0],
        0.0,
        Vec3::new(0.35, 0.22, 0.12),
    );
    let pots = [
        (-5.0, 0.0, &spin, 1.0),
        (-1.7, 1.2, &gem, 1.1),
        (1.7, -0.3, &spin, 0.8),
        (5.0, 1.0, &gem, 1.3),
    ];
    for (x, y, h, sc) in pots {
        let at = DVec3::new(x, y, 0.0);
        pot(&mut s, at, 1.3 * sc, 1.6 * sc, res);
        s.put(&h.mesh, at + DVec3::Z * 1.45 * sc, DMat3::IDENTITY, sc);
    }
    render(
        &s,
        &View::along(Vec3::new(0.0, 1.0, -0.35)).zoomed(1.6),
        d.size * 3 / 2,
        d.size,
    )
}

/// Fig. 12: a flower shop: shelves of pots, the stems in each pot placed
/// by the collision model on the soil.
pub fn flower_shop(res: u32, d: Detail) -> R<Image> {
    let daisy = heads::daisy(colour::WHITE, res)?;
    let pink = heads::chrysanthemum(Vec3::new(0.75, 0.12, 0.4), res)?;
    let gold = heads::chrysanthemum(Vec3::new(0.9, 0.5, 0.05), res)?;
    let hyac = heads::grape_hyacinth(res)?;
    let mut s = Mesh::default();
    table(
        &mut s,
        [-9.0, 9.0],
        [-2.5, 2.5],
        0.0,
        Vec3::new(0.3, 0.2, 0.12),
    );
    table(
        &mut s,
        [-9.0, 9.0],
        [3.0, 8.0],
        2.5,
        Vec3::new(0.3, 0.2, 0.12),
    );
    let front = [
        (-6.0, &daisy.mesh, 0.4, 3.0),
        (0.0, &pink.mesh, 0.45, 3.2),
        (6.0, &gold.mesh, 0.45, 2.8),
    ];
    for (k, (x, h, sc, tall)) in front.iter().enumerate() {
        planted(
            &mut s,
            h,
            DVec3::new(*x, 0.0, 0.0),
            2.0,
            1.8,
            *sc,
            *tall,
            res,
            k as u64,
        )?;
    }
    let back = [
        (-4.5, &hyac.mesh, 0.45, 1.4),
        (1.5, &daisy.mesh, 0.35, 2.6),
        (6.5, &hyac.mesh, 0.45, 1.2),
    ];
    for (k, (x, h, sc, tall)) in back.iter().enumerate() {
        let at = DVec3::new(*x, 5.5, 2.5);
        planted(&mut s, h, at, 1.8, 1.6, *sc, *tall, res, 10 + k as u64)?;
    }
    render(
        &s,
        &View::along(Vec3::new(0.0, 1.0, -0.45)).zoomed(1.6),
        d.size * 3 / 2,
        d.size,
    )
}

/// Fig. 15: a window sill with several of the plants above in pots.
pub fn window_sill(res: u32, d: Detail) -> R<Image> {
    let cone = heads::coneflower(res)?;
    let (gem, _) = cactus_pair(res)?;
    let hyac = heads::grape_hyacinth(res)?;
    let gold = heads::chrysanthemum(Vec3::new(0.9, 0.5, 0.05), res)?;
    let mut s = Mesh::default();
    // The sill, the wall under the window, the window's frame and panes.
    let white = Vec3::splat(0.75);
    s.slab(
        DVec3::new(-10.0, -2.5, -0.4),
        DVec3::new(10.0, 3.0, 0.0),
        white,
    );
    s.slab(
        DVec3::new(-10.0, 2.8, -6.0),
        DVec3::new(10.0, 3.0, -0.4),
        Vec3::new(0.6, 0.55, 0.45),
    );
    let sky = Vec3::new(0.35, 0.5, 0.75);
    s.slab(DVec3::new(-9.0, 3.2, 0.0), DVec3::new(9.0, 3.3, 11.0), sky);
    for x in [-9.5, 0.0, 9.5] {
        s.slab(
            DVec3::new(x - 0.4, 3.0, 0.0),
            DVec3::new(x + 0.4, 3.2, 11.5),
            white,
        );
    }
    s.slab(
        DVec3::new(-10.0, 3.0, 11.0),
        DVec3::new(10.0, 3.2, 11.8),
        white,
    );
    s.slab(
        DVec3::new(-10.0, 3.0, 5.3),
        DVec3::new(10.0, 3.2, 5.7),
        white,
    );
    // Pots, left to right.
    let at = |x: f64| DVec3::new(x, 0.3, 0.0);
    pot(&mut s, at(-6.5), 1.3, 1.6, res);
    s.put(&gem.mesh, at(-6.5) + DVec3::Z * 1.45, DMat3::IDENTITY, 1.0);
    pot(&mut s, at(-2.3), 1.4, 1.7, res);
    s.put(&cone.mesh, at(-2.3) + DVec3::Z * 5.0, tilt(-0.12, 0.0), 1.0);
    planted(&mut s, &hyac.mesh, at(2.2), 1.5, 1.6, 0.5, 1.3, res, 21)?;
    planted(&mut s, &gold.mesh, at(6.5), 1.5, 1.7, 0.5, 3.0, res, 22)?;
    render(
        &s,
        &View::along(Vec3::new(0.0, 1.0, -0.25)).zoomed(1.45),
        d.size * 3 / 2,
        d.size,
    )
}
