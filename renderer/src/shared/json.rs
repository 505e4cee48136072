//! Reading the suite's JSON files (scenes, jobs, manifests, designs, observers) with errors a
//! user can act on: the file, the field path where parsing stopped (`objects[2].velocity`),
//! serde's words with the line and column, and what kind of file was expected.

use anyhow::{Result, anyhow};
use serde::de::DeserializeOwned;
use std::path::Path;

/// Parse `text`, the contents of `path`, as one `what` (e.g. "scene file"). A UTF-8 byte-order
/// mark (some Windows editors write one) is skipped; anything after the closing brace is
/// refused.
pub fn from_str<T: DeserializeOwned>(text: &str, path: &Path, what: &str) -> Result<T> {
    let article = crate::utf8::article(what);
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let de = &mut serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let field = e.path().to_string();
        let said = crate::quote::clip_quoted(&e.inner().to_string());
        if field == "." || field.is_empty() {
            anyhow!("{}: {said}; expected {article} {what}", path.display())
        } else {
            let field = crate::quote::short(&field);
            anyhow!(
                "{}: field `{field}`: {said}; expected {article} {what}",
                path.display()
            )
        }
    })?;
    de.end().map_err(|e| {
        anyhow!(
            "{}: {e}: expected nothing after the {what}'s closing `}}`",
            path.display()
        )
    })?;
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[allow(dead_code)]
    struct T {
        a: Vec<Inner>,
    }
    #[derive(Debug, serde::Deserialize)]
    #[allow(dead_code)]
    struct Inner {
        n: u32,
    }

    fn err(text: &str) -> String {
        from_str::<T>(text, Path::new("f.json"), "test file")
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn type_errors_name_the_field_path_and_line() {
        let e = err("{\"a\": [{\"n\": 1},\n {\"n\": -3}]}");
        assert!(
            e.starts_with("f.json: field `a[1].n`: invalid value"),
            "{e}"
        );
        assert!(e.contains("line 2"), "{e}");
    }

    #[test]
    fn trailing_text_is_refused_and_a_byte_order_mark_skipped() {
        assert!(err("{\"a\": []} x").contains("expected nothing after the test file's closing"));
        assert!(from_str::<T>("\u{feff}{\"a\": []}", Path::new("f"), "t").is_ok());
    }

    #[test]
    fn syntax_errors_name_the_line() {
        let e = err("{\"a\": [\n,]}");
        assert!(e.starts_with("f.json: ") && e.contains("line 2"), "{e}");
    }
}
