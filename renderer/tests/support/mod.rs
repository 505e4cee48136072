//! Figure 13's scene in a folder with stand-ins for the files it names; shared by the
//! renderer's `thesis_formats` tests and, included by path, the root package's
//! `render_cli` tests.

/// A folder holding Figure 13's scene (`figure13`, the text, as `name`) and small stand-ins at the paths it names:
/// `models/B-727-200.obj` (a 4 x 1 x 4 box) and `data/CedarCity.hdr` (an 8 x 4 gradient sky).
pub fn figure13_folder(figure13: &str, name: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join(name), figure13).unwrap();
    std::fs::create_dir_all(d.join("models")).unwrap();
    std::fs::create_dir_all(d.join("data")).unwrap();
    let mut obj = String::new();
    for z in [-2.0, 2.0] {
        for y in [-0.5, 0.5] {
            for x in [-2.0, 2.0] {
                obj += &format!("v {x} {y} {z}\n");
            }
        }
    }
    for f in [
        [1, 2, 4, 3],
        [5, 7, 8, 6],
        [1, 5, 6, 2],
        [3, 4, 8, 7],
        [1, 3, 7, 5],
        [2, 6, 8, 4],
    ] {
        obj += &format!("f {} {} {} {}\n", f[0], f[1], f[2], f[3]);
    }
    std::fs::write(d.join("models/B-727-200.obj"), obj).unwrap();
    let (w, h) = (8usize, 4usize);
    let sky: Vec<image::Rgb<f32>> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32, (i / w) as f32);
            image::Rgb([
                0.2 + 0.1 * x,
                0.4 + 0.2 * y,
                1.0 + 3.0 * (y == 0.0) as u8 as f32,
            ])
        })
        .collect();
    let mut hdr = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut hdr)
        .encode(&sky, w, h)
        .unwrap();
    std::fs::write(d.join("data/CedarCity.hdr"), hdr).unwrap();
    dir
}
