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

/// Files served under `/assets/{name}`.
pub const ASSETS: &[Asset] = &[
    Asset {
        name: "app.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../../web/app.js"),
    },
    Asset {
        name: "api.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../../web/api.js"),
    },
    Asset {
        name: "calibrate.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../../web/calibrate.js"),
    },
    Asset {
        name: "stage.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../../web/stage.js"),
    },
    Asset {
        name: "trial.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../../web/trial.js"),
    },
    Asset {
        name: "ui.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../../web/ui.js"),
    },
    Asset {
        name: "style.css",
        mime: "text/css; charset=utf-8",
        body: include_str!("../../web/style.css"),
    },
];

/// The embedded file called `name`, if any (names are compared, never joined to a path).
pub fn asset(name: &str) -> Option<&'static Asset> {
    ASSETS.iter().find(|a| a.name == name)
}
