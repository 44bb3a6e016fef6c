//! Module names and their ids.

use std::collections::HashMap;

/// Id of `[` (push the turtle, start a branch).
pub const LBRACKET: u32 = 0;
/// Id of `]` (pop the turtle, end a branch).
pub const RBRACKET: u32 = 1;
/// Id of `%` (cut the rest of the branch).
pub const CUT: u32 = 2;

/// The names of an L-system's modules, interned as `u32` ids.
///
/// `[`, `]` and `%` always have the ids [`LBRACKET`], [`RBRACKET`] and [`CUT`].
#[derive(Clone, Debug)]
pub struct SymbolTable {
    names: Vec<String>,
    ids: HashMap<String, u32>,
}

impl Default for SymbolTable {
    fn default() -> Self {
        Self::new()
    }
}

impl SymbolTable {
    /// Returns a table holding `[`, `]` and `%`.
    #[must_use]
    pub fn new() -> Self {
        let mut t = Self {
            names: Vec::new(),
            ids: HashMap::new(),
        };
        for s in ["[", "]", "%"] {
            t.intern(s);
        }
        t
    }

    /// Returns the id of `name`, adding it if new.
    pub fn intern(&mut self, name: &str) -> u32 {
        if let Some(&id) = self.ids.get(name) {
            return id;
        }
        let id = self.names.len() as u32;
        self.names.push(name.to_string());
        self.ids.insert(name.to_string(), id);
        id
    }

    /// Returns the id of `name` if it is known.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<u32> {
        self.ids.get(name).copied()
    }

    /// Returns the name of `id` (`"?"` for an unknown id).
    #[must_use]
    pub fn name(&self, id: u32) -> &str {
        self.names.get(id as usize).map_or("?", String::as_str)
    }

    /// Number of symbols.
    #[must_use]
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Always false: the brackets and the cut are always present.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}
