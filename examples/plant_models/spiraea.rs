//! Fig. 16 of Prusinkiewicz et al. 2001: a *Spiraea* twig. The shoots sit
//! on the twig, and the leaves and flowers on each shoot, in the spiral
//! phyllotactic pattern (137.5° between successive organs); the shoots'
//! near-vertical posture is their orthotropism, simulated as the source
//! says by biasing the turtle's heading towards the vertical (ABOP's
//! tropism, natura-plant's `tropism:` directive). By position along the
//! twig, the shoots shorten towards its tip, and along each shoot the
//! leaves give way to flowers on pedicels in a cluster at its end. The
//! L-system and its values are ours; the twig's own arch is a pitch down
//! at each node that the upward bias balances (the shoots' divergence is
//! rolled inside each branch, so the twig keeps its plane).

use natura::core::glam::{DMat3, DVec3, Vec3};
use natura::plant::{Derivation, LSystem, TurtleParams};

use crate::common::{Exit, outln};
use crate::mesh::{Mesh, View, render};
use crate::organs;

/// The twig's L-system: `N` shoots on the twig.
pub const SPIRAEA: &str = "\
#define N 18
tropism: 0, 0, 1, 0.45
ω: !(0.045) &(75) T(0)
T(k) : k < N { s = k/N; n = 9 - 5*s; } -> &(21) F(0.32) [ /(137.5*k) &(50) !(0.02) S(n, 0) ] T(k+1)
T(k) : k >= N -> F(0.15) ~L(0.3, 0.12)
S(n,i) : i < n - 3 -> F(0.07) F(0.07) /(137.5) [ &(55) ~L(0.34, 0.14) ] S(n, i+1)
S(n,i) : i >= n - 3 && i < n -> F(0.07) /(137.5) [ &(45) F(0.12) ~K(0.1) ] S(n, i+1)
S(n,i) : i >= n -> [ F(0.1) ~K(0.11) ]
";

/// The twig's turtle geometry, the tropism's elasticity `elasticity` or
/// the listing's.
///
/// # Errors
///
/// The L-system's and the turtle's errors (none for this text).
fn grow(elasticity: Option<f64>) -> Result<natura::plant::Geometry, Exit> {
    let l = LSystem::parse(SPIRAEA)?;
    let mut d = Derivation::new(&l, 0)?;
    d.derive(40)?;
    let listing = TurtleParams::for_lsystem(&l);
    let run = natura::plant::models::Run {
        turtle: TurtleParams {
            width: 0.045,
            elasticity: elasticity.unwrap_or(listing.elasticity),
            ..listing
        },
        string: d.string().clone(),
        lsystem: l,
    };
    Ok(run.geometry()?)
}

/// Fig. 16: the twig drawn with round stems of their width, leaves
/// (`~L`) as arched blades and flowers (`~K`) as small white cups. Returns
/// the mesh, its leaves and its flowers.
///
/// # Errors
///
/// The L-system's and the turtle's errors (none for this text).
pub fn twig(res: u32) -> Result<(Mesh, usize, usize), Exit> {
    let g = grow(None)?;
    let mut m = Mesh::default();
    let bark = Vec3::new(0.35, 0.2, 0.12);
    for k in 0..g.segment_count() {
        let r = 0.5 * f64::from(g.width0[k].max(g.width1[k]));
        m.tube(g.start[k].as_dvec3(), g.end[k].as_dvec3(), r, 5 * res, bark);
    }
    let leaf = organs::leaf(1.0, 0.42, 0.08, Vec3::new(0.1, 0.3, 0.05), res);
    let (mut leaves, mut flowers) = (0, 0);
    for s in &g.surfaces {
        let f = s.frame;
        match s.name {
            'L' => {
                leaves += 1;
                m.put(&leaf, f.p, DMat3::from_cols(f.h, f.l, f.u), s.length);
            }
            'K' => {
                flowers += 1;
                let cup = organs::cup(DVec3::Z, 1.0, Vec3::new(0.9, 0.9, 0.86), res);
                m.put(&cup, f.p, DMat3::from_cols(f.l, f.u, f.h), s.length);
            }
            _ => {}
        }
    }
    Ok((m, leaves, flowers))
}

/// Draws Fig. 16 into `out` as `spiraea.png` when `want` names `spiraea`,
/// small when `quick`.
///
/// # Errors
///
/// [`twig`]'s errors; natura-core's if the picture cannot be drawn or
/// written.
pub fn draw(want: impl Fn(&str) -> bool, quick: bool, out: &std::path::Path) -> crate::common::Run {
    if want("spiraea") {
        let (size, res) = if quick { (240, 1) } else { (700, 2) };
        let (m, leaves, flowers) = twig(res)?;
        // The twig arches in the y–z plane: seen from its side.
        let view = View::along(Vec3::new(1.0, 0.2, -0.2)).zoomed(1.3);
        render(&m, &view, size * 4 / 3, size)?.save_png(out.join("spiraea.png"))?;
        outln(format_args!(
            "spiraea.png: {leaves} leaves, {flowers} flowers"
        ))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The heading's rise of each shoot's last flower (the `~K(0.11)` at
    /// its tip), for the twig grown with the tropism's elasticity `e`.
    fn tips(e: f64) -> Vec<f64> {
        grow(Some(e))
            .unwrap()
            .surfaces
            .iter()
            .filter(|s| s.name == 'K' && (s.length - 0.11).abs() < 1e-9)
            .map(|s| s.frame.h.z)
            .collect()
    }

    #[test]
    fn the_tropism_stands_every_shoot_up() {
        let up = tips(0.45);
        assert_eq!(up.len(), 18, "one tip a shoot");
        assert!(up.iter().all(|&z| z > 0.85), "{up:?}");
        // Without it the shoots leave the twig every way round.
        let free = tips(0.0);
        assert!(free.iter().filter(|&&z| z > 0.85).count() < 9, "{free:?}");
    }
}
