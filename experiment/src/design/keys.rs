//! Response key names, checked without the GUI: the design names keys as text, the app maps the
//! canonical names to `egui::Key::from_name` (every name here is one egui accepts).

/// Canonical key names a design may use.
pub const KNOWN_KEYS: &[&str] = &[
    "0",
    "1",
    "2",
    "3",
    "4",
    "5",
    "6",
    "7",
    "8",
    "9",
    "A",
    "B",
    "C",
    "D",
    "E",
    "F",
    "G",
    "H",
    "I",
    "J",
    "K",
    "L",
    "M",
    "N",
    "O",
    "P",
    "Q",
    "R",
    "S",
    "T",
    "U",
    "V",
    "W",
    "X",
    "Y",
    "Z",
    "ArrowLeft",
    "ArrowRight",
    "ArrowUp",
    "ArrowDown",
    "Enter",
    "Space",
    "Escape",
];

/// Keys the app uses itself: Esc pauses, Space continues from a screen.
pub const RESERVED_KEYS: &[&str] = &["Escape", "Space"];

/// The canonical spelling of a key name (`left` -> `ArrowLeft`, `a` -> `A`), or the input when
/// it is not a known key.
pub fn canonical(name: &str) -> &str {
    let alias = match name {
        "Left" | "left" => Some("ArrowLeft"),
        "Right" | "right" => Some("ArrowRight"),
        "Up" | "up" => Some("ArrowUp"),
        "Down" | "down" => Some("ArrowDown"),
        "Esc" | "esc" | "escape" => Some("Escape"),
        "space" | " " => Some("Space"),
        "Return" | "enter" => Some("Enter"),
        _ => None,
    };
    if let Some(a) = alias {
        return a;
    }
    if name.len() == 1 {
        let upper = name.to_ascii_uppercase();
        if let Some(k) = KNOWN_KEYS.iter().find(|k| **k == upper) {
            return k;
        }
    }
    KNOWN_KEYS
        .iter()
        .find(|k| **k == name)
        .copied()
        .unwrap_or(name)
}

pub fn is_known(name: &str) -> bool {
    KNOWN_KEYS.contains(&canonical(name))
}

/// How to name keys to a subject: `1 or Left arrow`.
pub fn describe(names: &[String]) -> String {
    let words: Vec<String> = names
        .iter()
        .map(|n| match canonical(n) {
            "ArrowLeft" => "Left arrow".to_string(),
            "ArrowRight" => "Right arrow".to_string(),
            "ArrowUp" => "Up arrow".to_string(),
            "ArrowDown" => "Down arrow".to_string(),
            other => other.to_string(),
        })
        .collect();
    words.join(" or ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aliases_map_to_canonical_names() {
        assert_eq!(canonical("left"), "ArrowLeft");
        assert_eq!(canonical("a"), "A");
        assert_eq!(canonical("7"), "7");
        assert_eq!(canonical("Bogus"), "Bogus");
        assert!(is_known("Esc"));
        assert!(!is_known("F13"));
        assert_eq!(
            describe(&["1".into(), "ArrowLeft".into()]),
            "1 or Left arrow"
        );
    }
}
