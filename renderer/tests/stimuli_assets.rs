//! The committed procedural assets under `scenes/` are exactly what the generators produce
//! (regenerate with `render assets` after changing the generators).

#[test]
fn committed_assets_equal_the_generators_output() {
    let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    for a in renderer::procedural::assets().unwrap() {
        let path = scenes.join(a.path);
        let on_disk = std::fs::read(&path)
            .unwrap_or_else(|e| panic!("{}: {e}; run `render assets`", path.display()));
        assert!(
            on_disk == a.bytes,
            "{} differs from the generator's output; run `render assets`",
            path.display()
        );
    }
}
