//! Writing `key value ...` lines. Numbers are written in Rust's shortest form that reads back
//! to the same bits (`0.3`, `-1000`, `1e-7` as `0.0000001`), words bare or quoted
//! ([`super::quote`]); a value equal to its default is left out (compared bit for bit, so `-0`
//! is kept), which makes the writers deterministic and their output as short as Figure 13.

use super::quote;
use std::fmt::Write as _;

/// Text being written, one line per call.
#[derive(Default)]
pub struct Out {
    pub text: String,
    /// Indentation of key lines (inside a block).
    pub indent: &'static str,
}

impl Out {
    /// A line of raw words (already quoted where needed).
    pub fn raw(&mut self, words: &[&str]) {
        let _ = writeln!(self.text, "{}{}", self.indent, words.join(" "));
    }

    /// An unindented line (a block keyword, `end`, a comment).
    pub fn bare(&mut self, line: &str) {
        let _ = writeln!(self.text, "{line}");
    }

    pub fn word(&mut self, key: &str, w: &str) {
        self.raw(&[key, &quote(w)]);
    }

    pub fn words(&mut self, key: &str, ws: &[String]) {
        let q: Vec<String> = ws.iter().map(|w| quote(w).into_owned()).collect();
        let mut all = vec![key];
        all.extend(q.iter().map(String::as_str));
        self.raw(&all);
    }

    pub fn number(&mut self, key: &str, v: impl std::fmt::Display) {
        self.raw(&[key, &v.to_string()]);
    }

    pub fn numbers(&mut self, key: &str, v: &[f32]) {
        let s: Vec<String> = v.iter().map(f32::to_string).collect();
        let mut all = vec![key];
        all.extend(s.iter().map(String::as_str));
        self.raw(&all);
    }

    /// `key x y z` unless `v` is `default`.
    pub fn vec_unless(&mut self, key: &str, v: [f32; 3], default: [f32; 3]) {
        if !same(&v, &default) {
            self.numbers(key, &v);
        }
    }

    /// `key v` unless `v` is `default`.
    pub fn f32_unless(&mut self, key: &str, v: f32, default: f32) {
        if v.to_bits() != default.to_bits() {
            self.number(key, v);
        }
    }
}

/// Bitwise equality of float lists (so that -0 and 0 differ, as they do in JSON).
pub fn same(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}
