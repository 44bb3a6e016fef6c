//! The source papers' plant models, each with typed parameters whose
//! defaults are the source's values, its L-system text where the source
//! prints one, and, for open L-systems, its [`Environment`].
//!
//! | model | source | module |
//! |---|---|---|
//! | branch tiers of *Terminalia* (Honda) | Měch & Prusinkiewicz 1996, §6.1, Fig. 5 | [`tiers`] |
//! | tree crowns competing for light | Měch & Prusinkiewicz 1996, §6.4, Fig. 11–16 | [`crowns`] |
//! | collision-based spiral phyllotaxis | Fowler et al. 1992, §3 | [`phyllotaxis`] |
//! | organ spacing, Ridley packing, branch mapping | Prusinkiewicz et al. 2001, §4–6, Alg. 3, 5, 6 | [`positional`] |
//!
//! [`Environment`]: crate::Environment

pub mod crowns;
pub mod phyllotaxis;
pub mod positional;
pub mod tiers;

use crate::error::Result;
use crate::lang::LSystem;
use crate::open::Environment;
use crate::turtle::{Turtle, TurtleParams};
use crate::{Derivation, ModuleString};

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
/// derivation steps each followed by one (Měch & Prusinkiewicz 1996, §5, Fig. 4).
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
