//! The source papers' plant models, each with typed parameters whose
//! defaults are the source's values, its L-system text where the source
//! prints one, and, for open L-systems, its [`Environment`].
//!
//! | model | source | module |
//! |---|---|---|
//! | branch tiers of *Terminalia* (Honda) | Měch & Prusinkiewicz 1996, §5, Fig. 5 | [`tiers`] |
//! | foraging of a clonal plant over patches of light | Měch & Prusinkiewicz 1996, §6, Fig. 6–7 | [`clonal`] |
//! | roots growing in soil water | Měch & Prusinkiewicz 1996, §7, Fig. 8–9 | [`roots`] |
//! | the same in 3-D soil | Měch & Prusinkiewicz 1996, §7, Fig. 10 | [`roots3d`] |
//! | tree crowns competing for light | Měch & Prusinkiewicz 1996, §8, Fig. 11–14, 16 | [`crowns`] |
//! | conifers in tiers competing for light (rules our own) | Měch & Prusinkiewicz 1996, §8, Fig. 15 | [`conifers`] |
//! | a climbing plant following a tree's bark, avoiding crowding (rules our own) | Měch & Prusinkiewicz 1996, §8, Fig. 13 | [`climber`] |
//! | collision-based spiral phyllotaxis and organ placement | Fowler et al. 1992, §2.4, §3.1 | [`phyllotaxis`] |
//! | curved limbs by differential turtle geometry (stems, twisted leaves) | Prusinkiewicz et al. 2001, §3, eq. 4, Alg. 1 | [`limb`] |
//! | compound leaves (organs at a density along a curved stem) | Prusinkiewicz et al. 2001, §5, Alg. 4 | [`compound`] |
//! | organ spacing, Ridley packing, branch mapping | Prusinkiewicz et al. 2001, §4–6, Alg. 3, 5, 6 | [`positional`] |
//!
//! [`Environment`]: crate::Environment

pub mod climber;
pub mod clonal;
pub mod compound;
pub mod conifers;
pub mod crowns;
pub mod limb;
pub mod phyllotaxis;
pub mod positional;
pub mod roots;
pub mod roots3d;
pub mod tiers;

use crate::error::Result;
use crate::lang::LSystem;
use crate::open::Environment;
use crate::turtle::{Turtle, TurtleParams};
use crate::{Derivation, ModuleString};

/// An axis-aligned rectangle of the plane carrying one value (a patch of
/// light, a region of wet soil), as the source paints its fields.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Patch {
    /// Lower corner `[x, y]`.
    pub min: [f64; 2],
    /// Upper corner `[x, y]`.
    pub max: [f64; 2],
    /// The value inside.
    pub value: f64,
}

impl Patch {
    /// Whether `[x, y]` lies inside (lower edges included, upper excluded).
    #[must_use]
    pub fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.min[0] && x < self.max[0] && y >= self.min[1] && y < self.max[1]
    }

    /// Area of the rectangle.
    #[must_use]
    pub fn area(&self) -> f64 {
        (self.max[0] - self.min[0]) * (self.max[1] - self.min[1])
    }
}

/// Checks every patch has finite corners in order and a value in `lo..=hi`.
pub(crate) fn check_patches(
    name: &'static str,
    patches: &[Patch],
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Result<()> {
    for p in patches {
        let ok = p.min.iter().chain(&p.max).all(|v| v.is_finite())
            && p.min[0] < p.max[0]
            && p.min[1] < p.max[1];
        if !ok {
            return Err(crate::PlantError::InvalidParameter {
                name,
                value: format!("{p:?}"),
                reason: "finite corners with min < max".into(),
            });
        }
        natura_core::check::in_range(name, p.value, lo, hi, expected)?;
    }
    Ok(())
}

/// Checks a raster's layout: a finite `origin`, a positive `cell`, and each
/// side of `size` positive and 1 to 4096 cells long. `names` are the
/// parameters' names for errors: origin, size, cell.
pub(crate) fn check_layout(
    names: [&'static str; 3],
    origin: [f64; 2],
    size: [f64; 2],
    cell: f64,
) -> Result<()> {
    let [origin_name, size_name, cell_name] = names;
    natura_core::check::finite(origin_name, origin[0])?;
    natura_core::check::finite(origin_name, origin[1])?;
    natura_core::check::positive(cell_name, cell)?;
    for v in size {
        natura_core::check::positive(size_name, v)?;
        natura_core::check::in_range(size_name, v / cell, 1.0, 4096.0, "1 to 4096 cells a side")?;
    }
    Ok(())
}

/// Paints `patches` over `background` into the cells of side `cell` that
/// cover `size` from the lower corner `origin` (later patches over earlier
/// ones; a cell takes the value at its centre). Returns the cell counts
/// along each side and the values, row by row.
pub(crate) fn rasterize(
    patches: &[Patch],
    background: f64,
    origin: [f64; 2],
    cell: f64,
    size: [f64; 2],
) -> (usize, usize, Vec<f64>) {
    let nx = (size[0] / cell).round() as usize;
    let ny = (size[1] / cell).round() as usize;
    let mut v = vec![background; nx * ny];
    for j in 0..ny {
        for i in 0..nx {
            let x = origin[0] + (i as f64 + 0.5) * cell;
            let y = origin[1] + (j as f64 + 0.5) * cell;
            if let Some(p) = patches.iter().rev().find(|p| p.contains(x, y)) {
                v[j * nx + i] = p.value;
            }
        }
    }
    (nx, ny, v)
}

/// The outcome of running an open L-system model.
#[derive(Clone, Debug)]
pub struct Run {
    /// The model's L-system (for symbol names and interpretation).
    pub lsystem: LSystem,
    /// The final string.
    pub string: ModuleString,
    /// Turtle settings that draw it.
    pub turtle: TurtleParams,
}

impl Run {
    /// Interprets the final string into turtle geometry.
    ///
    /// # Errors
    ///
    /// Errors of [`Turtle::interpret`].
    pub fn geometry(&self) -> Result<crate::Geometry> {
        Turtle::new(&self.lsystem, self.turtle.clone())?.interpret(&self.string)
    }

    /// Number of modules named `name` in the final string.
    #[must_use]
    pub fn count(&self, name: &str) -> usize {
        self.lsystem.symbol(name).map_or(0, |id| {
            self.string.symbols().iter().filter(|&&s| s == id).count()
        })
    }
}

/// Runs an open L-system: a communication phase on the axiom, then `steps`
/// derivation steps each followed by one (Měch & Prusinkiewicz 1996, §4, Fig. 4).
/// Communication on the axiom lets models whose axiom holds `?E` read the
/// environment before their first step.
pub(crate) fn run_open(
    lsystem: LSystem,
    turtle: TurtleParams,
    env: &mut dyn Environment,
    steps: u32,
    seed: u64,
) -> Result<Run> {
    let string = {
        let t = Turtle::new(&lsystem, turtle.clone())?;
        let mut d = Derivation::new(&lsystem, seed)?;
        d.communicate(&t, env)?;
        for _ in 0..steps {
            d.step_open(&t, env)?;
        }
        d.into_string()
    };
    Ok(Run {
        lsystem,
        string,
        turtle,
    })
}

#[cfg(test)]
pub(crate) mod testenv {
    //! An environment wrapper that records what the model's environment sees.
    use crate::open::{Environment, Message, Reply};

    pub struct Recorder<'a> {
        pub inner: &'a mut dyn Environment,
        pub seen: Vec<Vec<Message>>,
    }

    impl Environment for Recorder<'_> {
        fn respond(&mut self, step: u32, m: &[Message], r: &mut Vec<Reply>) -> crate::Result<()> {
            self.seen.push(m.to_vec());
            self.inner.respond(step, m, r)
        }
    }
}
