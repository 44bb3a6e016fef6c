//! Environmentally-sensitive and open L-systems.
//!
//! Query modules `?P`, `?H`, `?L`, `?U` receive the turtle's position or
//! axis after each derivation step (Prusinkiewicz, James & Měch 1994, as
//! summarised by Měch & Prusinkiewicz 1996, §4). The communication module
//! `?E(x1, …, xm)` exchanges data with an [`Environment`] (Měch &
//! Prusinkiewicz 1996, §4, Fig. 4): after a step the string is interpreted,
//! every `?E` sends its address (index in the string), its parameters and the
//! turtle state; the environment answers selected addresses with new values,
//! which are written into those modules' parameters before the next step.
//!
//! The source runs plant and environment as two processes joined by pipes;
//! here the environment is a Rust value called in the same process, which
//! keeps the same message protocol and makes a simulation deterministic.

use crate::engine::Derivation;
use crate::error::{PlantError, Result};
use crate::turtle::{Turtle, TurtleState};

/// A message from one `?E` module to the environment.
#[derive(Clone, Debug, PartialEq)]
pub struct Message {
    /// Index of the `?E` module in the string (the reply goes back to it).
    pub address: usize,
    /// The module's parameters.
    pub values: Vec<f64>,
    /// The turtle's state at the module.
    pub state: TurtleState,
    /// Symbol id of the module following the `?E`, if any (the source's optional field).
    pub next_symbol: Option<u32>,
}

/// A reply of the environment to one `?E` module.
#[derive(Clone, Debug, PartialEq)]
pub struct Reply {
    /// Address of the `?E` module (from its [`Message`]).
    pub address: usize,
    /// New values of its first `values.len()` parameters.
    pub values: Vec<f64>,
}

/// The environment of an open L-system, implemented by the caller.
pub trait Environment {
    /// Receives every message of one communication phase (in string order,
    /// the whole set before any reply, as the source's end-of-transmission
    /// marker ensures) and pushes replies for the modules it answers.
    ///
    /// # Errors
    ///
    /// Whatever the environment reports; the derivation stops with it.
    fn respond(&mut self, step: u32, messages: &[Message], replies: &mut Vec<Reply>) -> Result<()>;
}

/// Ids of the query and communication modules in an L-system.
fn query_ids(d: &Derivation<'_>) -> [Option<u32>; 5] {
    let l = d.lsystem();
    ["?P", "?H", "?L", "?U", "?E"].map(|n| l.symbol(n))
}

impl Derivation<'_> {
    /// Fills the query modules `?P ?H ?L ?U` of the current string with the
    /// turtle's position, heading, left and up vectors.
    ///
    /// # Errors
    ///
    /// Errors of [`Turtle::visit`].
    pub fn fill_queries(&mut self, turtle: &Turtle<'_>) -> Result<()> {
        let ids = query_ids(self);
        if ids[..4].iter().all(Option::is_none) {
            return Ok(());
        }
        let mut found: Vec<(usize, [f64; 3])> = Vec::new();
        let s = &self.cur;
        turtle.visit(s, |i, st| {
            let sym = s.symbol(i);
            let f = &st.frame;
            let v = if Some(sym) == ids[0] {
                f.p
            } else if Some(sym) == ids[1] {
                f.h
            } else if Some(sym) == ids[2] {
                f.l
            } else if Some(sym) == ids[3] {
                f.u
            } else {
                return;
            };
            found.push((i, v.to_array()));
        })?;
        for (i, v) in found {
            let p = self.cur.params_mut(i);
            let n = p.len().min(3);
            p[..n].copy_from_slice(&v[..n]);
        }
        Ok(())
    }

    /// Runs one communication phase on the current string: fills the query
    /// modules, sends every `?E` to `env` and writes its replies back.
    ///
    /// # Errors
    ///
    /// [`PlantError::Environment`] if a reply names an address that is not a
    /// `?E` module, carries more values than the module has parameters, or a
    /// non-finite value; the environment's own errors; turtle errors.
    pub fn communicate(&mut self, turtle: &Turtle<'_>, env: &mut dyn Environment) -> Result<()> {
        self.fill_queries(turtle)?;
        let Some(e_id) = query_ids(self)[4] else {
            return Ok(());
        };
        let s = &self.cur;
        let mut msgs = Vec::new();
        turtle.visit(s, |i, st| {
            if s.symbol(i) == e_id {
                msgs.push(Message {
                    address: i,
                    values: s.params(i).to_vec(),
                    state: *st,
                    next_symbol: (i + 1 < s.len()).then(|| s.symbol(i + 1)),
                });
            }
        })?;
        let mut replies = Vec::new();
        env.respond(self.steps(), &msgs, &mut replies)?;
        for r in replies {
            if r.address >= self.cur.len() || self.cur.symbol(r.address) != e_id {
                return Err(PlantError::Environment {
                    message: format!("reply to address {} which is not a ?E module", r.address),
                });
            }
            let p = self.cur.params_mut(r.address);
            if r.values.len() > p.len() {
                return Err(PlantError::Environment {
                    message: format!(
                        "reply to address {} carries {} values for {} parameters",
                        r.address,
                        r.values.len(),
                        p.len()
                    ),
                });
            }
            if let Some(v) = r.values.iter().find(|v| !v.is_finite()) {
                return Err(PlantError::Environment {
                    message: format!("reply to address {} carries the value {v}", r.address),
                });
            }
            p[..r.values.len()].copy_from_slice(&r.values);
        }
        Ok(())
    }

    /// One step of an open L-system: a derivation step, then a communication phase.
    ///
    /// # Errors
    ///
    /// As [`Derivation::step`] and [`Derivation::communicate`].
    pub fn step_open(&mut self, turtle: &Turtle<'_>, env: &mut dyn Environment) -> Result<()> {
        self.step()?;
        self.communicate(turtle, env)
    }
}
