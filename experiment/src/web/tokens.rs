//! Who may open what: one unguessable token per subject (128 bits from the operating system's
//! random source, as 32 lowercase hex digits), an open-enrolment token, and the admin token.
//! They are kept in `OUT/web/tokens.json` (written atomically) so that a restarted server knows
//! them; `--enrol N` also writes `OUT/links.csv`.

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// 128 random bits from the OS, as 32 lowercase hex digits (URL-safe).
pub fn new_token() -> Result<String> {
    let mut bytes = [0u8; 16];
    getrandom::fill(&mut bytes).map_err(|e| anyhow::anyhow!("no OS random numbers: {e}"))?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// A string that could be a token: 32 lowercase hex digits (anything else is refused before
/// any look-up).
pub fn looks_like_token(s: &str) -> bool {
    s.len() == 32
        && s.bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
}

/// Compare two secrets in time that does not depend on where they differ (only on the length,
/// which is public: every token is 32 characters).
pub fn same_secret(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct SubjectToken {
    pub subject: String,
    pub token: String,
    /// A platform participant's query parameters (`participant.rs`), the id's among them.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub ids: std::collections::BTreeMap<String, String>,
    /// The consent given (kept here until the log's header exists).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub consent: Option<crate::log::Consent>,
    /// Why the participant was screened out before any trial (consent declined, display).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub screened_out: Option<String>,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct OpenEnrolment {
    pub token: String,
    /// Most subjects open enrolment creates.
    pub cap: u32,
}

/// The contents of `tokens.json`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Tokens {
    pub admin: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub open: Option<OpenEnrolment>,
    pub subjects: Vec<SubjectToken>,
    /// Keys the videos' ids and export names (`video_ids.rs`); made at the first start that
    /// needs it (older files have none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub video_key: Option<String>,
}

impl Tokens {
    pub fn path(out: &Path) -> PathBuf {
        out.join("web").join("tokens.json")
    }

    /// The tokens kept in `out`, or fresh ones (a new admin token, no subjects).
    pub fn load_or_new(out: &Path) -> Result<Self> {
        let path = Self::path(out);
        if path.exists() {
            let text = std::fs::read_to_string(&path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            let t: Tokens = serde_json::from_str(&text)
                .with_context(|| format!("{}: not a blurlab tokens file", path.display()))?;
            check_tokens(&t, &path)?;
            return Ok(t);
        }
        Ok(Self {
            admin: new_token()?,
            open: None,
            subjects: Vec::new(),
            video_key: None,
        })
    }

    /// The study's video key, made now if the file had none (save the tokens to keep it).
    pub fn video_key(&mut self) -> Result<String> {
        if self.video_key.is_none() {
            self.video_key = Some(new_token()?);
        }
        Ok(self.video_key.clone().expect("set above"))
    }

    pub fn save(&self, out: &Path) -> Result<()> {
        let path = Self::path(out);
        renderer::atomic::write_atomic(&path, serde_json::to_string_pretty(self)?.as_bytes())
    }

    /// Add subjects named `prefix001`... until `n` subjects have that prefix.
    pub fn enrol(&mut self, prefix: &str, n: u32) -> Result<()> {
        let mut have = self.count_with_prefix(prefix);
        while have < n {
            have += 1;
            self.add(format!("{prefix}{have:03}"))?;
        }
        Ok(())
    }

    pub fn count_with_prefix(&self, prefix: &str) -> u32 {
        self.subjects
            .iter()
            .filter(|s| s.subject.starts_with(prefix))
            .count() as u32
    }

    /// A new subject with a fresh token.
    pub fn add(&mut self, subject: String) -> Result<SubjectToken> {
        crate::session::check_subject(&subject)?;
        let s = SubjectToken {
            subject,
            token: new_token()?,
            ..SubjectToken::default()
        };
        self.subjects.push(s.clone());
        Ok(s)
    }

    /// `links.csv`: `subject,url` for every subject, `base` being the server's public URL.
    pub fn write_links(&self, out: &Path, base: &str) -> Result<PathBuf> {
        let path = out.join("links.csv");
        let mut text = String::from("subject,url\n");
        for s in &self.subjects {
            text.push_str(&format!(
                "{},{}/s/{}\n",
                s.subject,
                base.trim_end_matches('/'),
                s.token
            ));
        }
        renderer::atomic::write_atomic(&path, text.as_bytes())?;
        Ok(path)
    }
}

/// `tokens` (read from `path`) hold tokens where tokens go, and no token or subject twice.
fn check_tokens(tokens: &Tokens, path: &Path) -> Result<()> {
    let at = path.display();
    let token_rule = "expected 32 lowercase hex digits, as `blurlab serve` writes them (delete \
                      the file to make new ones; subjects' links change)";
    if !looks_like_token(&tokens.admin) {
        bail!("{at}: field `admin` is not a token; {token_rule}");
    }
    if let Some(open) = &tokens.open
        && !looks_like_token(&open.token)
    {
        bail!("{at}: field `open.token` is not a token; {token_rule}");
    }
    let mut by_token: std::collections::HashMap<&str, &str> = Default::default();
    let mut by_subject: HashSet<&str> = HashSet::new();
    for (i, s) in tokens.subjects.iter().enumerate() {
        crate::session::check_subject(&s.subject)
            .map_err(|e| anyhow::anyhow!("{at}: field `subjects[{i}].subject`: {e}"))?;
        if !looks_like_token(&s.token) {
            bail!(
                "{at}: field `subjects[{i}].token` (subject {}) is not a token; {token_rule}",
                s.subject
            );
        }
        if let Some(other) = by_token.insert(&s.token, &s.subject) {
            bail!(
                "{at}: subjects {other} and {} have the same token; each subject needs their \
                 own (two sessions would write one log)",
                s.subject
            );
        }
        if !by_subject.insert(&s.subject) {
            bail!(
                "{at}: subject {} has two tokens (two entries of `subjects`); keep one",
                s.subject
            );
        }
        let open = tokens.open.as_ref().map(|o| o.token.as_str());
        for (field, secret) in [("admin", Some(tokens.admin.as_str())), ("open.token", open)] {
            if secret == Some(s.token.as_str()) {
                bail!(
                    "{at}: subject {}'s token is also `{field}`; each token must differ",
                    s.subject
                );
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_are_128_bit_hex_and_differ() {
        let a = new_token().unwrap();
        let b = new_token().unwrap();
        assert!(looks_like_token(&a) && looks_like_token(&b));
        assert_ne!(a, b);
        assert!(!looks_like_token("../../etc/passwd"));
        assert!(!looks_like_token(&a.to_uppercase()));
    }

    #[test]
    fn secrets_compare_equal_only_when_equal() {
        assert!(same_secret("abc", "abc"));
        assert!(!same_secret("abc", "abd"));
        assert!(!same_secret("abc", "abcd"));
    }

    #[test]
    fn enrol_adds_up_to_n_and_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        let mut t = Tokens::load_or_new(dir.path()).unwrap();
        t.enrol("w", 3).unwrap();
        t.enrol("w", 2).unwrap();
        assert_eq!(t.subjects.len(), 3);
        assert_eq!(t.subjects[2].subject, "w003");
        t.save(dir.path()).unwrap();
        assert_eq!(Tokens::load_or_new(dir.path()).unwrap(), t);
        let links = t.write_links(dir.path(), "http://x:1/").unwrap();
        let text = std::fs::read_to_string(links).unwrap();
        assert!(
            text.starts_with("subject,url\nw001,http://x:1/s/"),
            "{text}"
        );
    }
}
