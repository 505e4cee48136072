//! The browser client's files, embedded in the binary so that `blurlab serve` needs nothing on
//! disk but the design and its stimuli. The client owns the files in `experiment/web/`; a new file
//! is one more entry in [`ASSETS`].

/// One embedded file: its name under `/assets/` and its MIME type.
pub struct Asset {
    pub name: &'static str,
    pub mime: &'static str,
    pub body: &'static str,
}

/// The page every subject link (`/s/{token}`) serves; the script reads the token from the path.
pub const INDEX_HTML: &str = include_str!("../../web/index.html");

/// One embedded file of `experiment/web/`, served under its own name.
macro_rules! asset {
    ($name:literal, $mime:literal) => {
        Asset {
            name: $name,
            mime: $mime,
            body: include_str!(concat!("../../web/", $name)),
        }
    };
}

/// Files served under `/assets/{name}`.
pub const ASSETS: &[Asset] = &[
    asset!("app.js", "text/javascript; charset=utf-8"),
    asset!("api.js", "text/javascript; charset=utf-8"),
    asset!("calibrate.js", "text/javascript; charset=utf-8"),
    asset!("canvas.js", "text/javascript; charset=utf-8"),
    asset!("trial.js", "text/javascript; charset=utf-8"),
    asset!("ui.js", "text/javascript; charset=utf-8"),
    asset!("videos.js", "text/javascript; charset=utf-8"),
    asset!("style.css", "text/css; charset=utf-8"),
];

/// The embedded file called `name`, if any (names are compared, never joined to a path).
pub fn asset(name: &str) -> Option<&'static Asset> {
    ASSETS.iter().find(|a| a.name == name)
}
