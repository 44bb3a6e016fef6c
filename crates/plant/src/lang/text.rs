//! L-system text as characters with positions, split into statements.
//!
//! Comments are C's `/* … */`. A statement is one line, continued on the next
//! line while a `(` or `{` is open, or while the next line neither starts a
//! directive nor holds a production arrow (so a long successor may wrap, as
//! the listings of Měch & Prusinkiewicz 1996 do).

use crate::error::{PlantError, Result, Span};

/// The deepest nesting of parentheses, prefix operators, `?:`, `^` and
/// `if` / `while` blocks an expression or block may have.
pub(crate) const MAX_NESTING: u32 = 256;

/// The largest L-system text accepted, in bytes (16 MiB).
pub const MAX_SOURCE_BYTES: usize = 16 << 20;

/// A character and where it came from.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ch {
    pub c: char,
    pub span: Span,
}

/// One logical statement: characters with positions, comments removed.
#[derive(Clone, Debug, Default)]
pub(crate) struct Stmt {
    pub chars: Vec<Ch>,
}

impl Stmt {
    pub fn end(&self) -> Span {
        self.chars
            .last()
            .map(|c| Span::new(c.span.line, c.span.col + 1))
            .unwrap_or_default()
    }

    pub fn span(&self) -> Span {
        self.chars.first().map(|c| c.span).unwrap_or_default()
    }

    pub fn text(&self) -> String {
        self.chars.iter().map(|c| c.c).collect()
    }
}

/// Strips comments and returns the lines as positioned characters.
fn lines(src: &str) -> Result<Vec<Vec<Ch>>> {
    // A UTF-8 byte-order mark (as some editors write) is not text.
    let src = src.strip_prefix('\u{feff}').unwrap_or(src);
    let mut out = vec![Vec::new()];
    let mut line = 1u32;
    let mut col = 1u32;
    let mut it = src.chars().peekable();
    let mut in_comment: Option<Span> = None;
    while let Some(c) = it.next() {
        let span = Span::new(line, col);
        if c == '\n' {
            line += 1;
            col = 1;
            out.push(Vec::new());
            continue;
        }
        col += 1;
        if in_comment.is_some() {
            if c == '*' && it.peek() == Some(&'/') {
                it.next();
                col += 1;
                in_comment = None;
            }
            continue;
        }
        if c == '/' && it.peek() == Some(&'*') {
            it.next();
            col += 1;
            in_comment = Some(span);
            continue;
        }
        if c == '\r' {
            continue;
        }
        let c = if c == '\t' { ' ' } else { c };
        if let Some(l) = out.last_mut() {
            l.push(Ch { c, span });
        }
    }
    if let Some(span) = in_comment {
        return Err(PlantError::syntax(span, "comment `/*` is never closed"));
    }
    Ok(out)
}

/// Returns true if `chars` (trimmed) starts with a directive keyword.
fn starts_directive(s: &str) -> bool {
    let t = s.trim_start();
    let lower = t.to_ascii_lowercase();
    t.starts_with('#')
        || t.starts_with("ω")
        || [
            "axiom",
            "lsystem",
            "endlsystem",
            "derivation",
            "maximum",
            "max depth",
            "ignore",
            "consider",
            "productions",
            "production:",
            "decomposition",
            "homomorphism",
            "interpretation",
            "endgroup",
            "define",
            "array",
            "angle",
            "step",
            "seed",
            "group",
        ]
        .iter()
        .any(|k| lower.starts_with(k))
}

/// Returns the index of the top-level production arrow in `chars` and its length.
pub(crate) fn find_arrow(chars: &[Ch]) -> Option<(usize, usize)> {
    let mut depth = 0i32;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i].c;
        match c {
            '(' | '{' => depth += 1,
            ')' | '}' => depth -= 1,
            _ => {}
        }
        if depth == 0 {
            if c == '→' || c == '⇝' {
                return Some((i, 1));
            }
            let next = |k: usize| chars.get(i + k).map(|c| c.c);
            if c == '-' && next(1) == Some('-') && next(2) == Some('>') {
                return Some((i, 3));
            }
            if (c == '-' || c == '=') && next(1) == Some('>') {
                return Some((i, 2));
            }
        }
        i += 1;
    }
    None
}

fn open_depth(chars: &[Ch]) -> i32 {
    chars.iter().fold(0, |d, c| match c.c {
        '(' | '{' => d + 1,
        ')' | '}' => d - 1,
        _ => d,
    })
}

/// Splits L-system text into statements.
pub(crate) fn statements(src: &str) -> Result<Vec<Stmt>> {
    if src.len() > MAX_SOURCE_BYTES {
        return Err(PlantError::syntax(
            Span::new(1, 1),
            format!(
                "the text is {} bytes, more than the {MAX_SOURCE_BYTES} bytes (16 MiB) an L-system may have",
                src.len()
            ),
        ));
    }
    let mut out: Vec<Stmt> = Vec::new();
    let mut prev_is_production = false;
    for l in lines(src)? {
        let text: String = l.iter().map(|c| c.c).collect();
        if text.trim().is_empty() {
            continue;
        }
        let cont = match out.last() {
            Some(prev) => {
                open_depth(&prev.chars) > 0
                    || (prev_is_production && !starts_directive(&text) && find_arrow(&l).is_none())
            }
            None => false,
        };
        if cont {
            if let Some(prev) = out.last_mut() {
                let span = l.first().map(|c| c.span).unwrap_or_default();
                prev.chars.push(Ch { c: ' ', span });
                prev.chars.extend(l);
            }
        } else {
            prev_is_production = !starts_directive(&text) && find_arrow(&l).is_some();
            out.push(Stmt { chars: l });
        }
    }
    Ok(out)
}

/// A cursor over positioned characters, for the recursive-descent parsers.
#[derive(Debug)]
pub(crate) struct Cursor<'a> {
    pub chars: &'a [Ch],
    pub pos: usize,
    /// Span reported at the end of input.
    pub end: Span,
    /// Nesting of the recursive descent (parentheses, operators, blocks).
    nest: u32,
}

impl<'a> Cursor<'a> {
    pub fn new(chars: &'a [Ch]) -> Self {
        let end = chars
            .last()
            .map(|c| Span::new(c.span.line, c.span.col + 1))
            .unwrap_or_default();
        Self {
            chars,
            pos: 0,
            end,
            nest: 0,
        }
    }

    /// Enters one level of nesting; a syntax error past [`MAX_NESTING`] levels.
    pub fn enter(&mut self) -> Result<()> {
        self.nest += 1;
        if self.nest > MAX_NESTING {
            return Err(PlantError::syntax(
                self.span(),
                format!(
                    "nested deeper than {MAX_NESTING} levels (parentheses, operators or blocks)"
                ),
            ));
        }
        Ok(())
    }

    /// Leaves a level entered with [`Cursor::enter`].
    pub fn leave(&mut self) {
        self.nest = self.nest.saturating_sub(1);
    }

    /// Sets the span reported at the end of input when it holds no character
    /// (an empty remainder of a statement reports the statement's end).
    pub fn end_at(mut self, end: Span) -> Self {
        if self.chars.is_empty() {
            self.end = end;
        }
        self
    }

    pub fn peek(&self) -> Option<char> {
        self.chars.get(self.pos).map(|c| c.c)
    }

    pub fn peek_at(&self, k: usize) -> Option<char> {
        self.chars.get(self.pos + k).map(|c| c.c)
    }

    pub fn span(&self) -> Span {
        self.chars.get(self.pos).map_or(self.end, |c| c.span)
    }

    pub fn bump(&mut self) -> Option<char> {
        let c = self.peek();
        if c.is_some() {
            self.pos += 1;
        }
        c
    }

    pub fn skip_ws(&mut self) {
        while self.peek().is_some_and(char::is_whitespace) {
            self.pos += 1;
        }
    }

    pub fn at_end(&mut self) -> bool {
        self.skip_ws();
        self.pos >= self.chars.len()
    }

    /// Consumes `c` (after whitespace) if it is next.
    pub fn eat(&mut self, c: char) -> bool {
        self.skip_ws();
        if self.peek() == Some(c) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    /// Consumes `s` (after whitespace) if it is next.
    pub fn eat_str(&mut self, s: &str) -> bool {
        self.skip_ws();
        let n = s.chars().count();
        let ok = s
            .chars()
            .enumerate()
            .all(|(k, c)| self.peek_at(k) == Some(c));
        if ok {
            self.pos += n;
        }
        ok
    }

    pub fn expect(&mut self, c: char, what: &str) -> Result<()> {
        if self.eat(c) {
            Ok(())
        } else {
            let found = self
                .peek()
                .map_or("end of line".to_string(), |c| format!("`{c}`"));
            Err(PlantError::syntax(
                self.span(),
                format!("expected `{c}` {what}, found {found}"),
            ))
        }
    }

    /// Reads an identifier (letters, digits, `_`, and `'` after the first character).
    pub fn ident(&mut self) -> Option<String> {
        self.skip_ws();
        let first = self.peek()?;
        if !(first.is_alphabetic() || first == '_') {
            return None;
        }
        let mut s = String::new();
        while let Some(c) = self.peek() {
            if c.is_alphanumeric() || c == '_' || (c == '\'' && !s.is_empty()) {
                s.push(c);
                self.pos += 1;
            } else {
                break;
            }
        }
        Some(s)
    }
}
