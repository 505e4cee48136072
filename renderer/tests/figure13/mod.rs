//! Figure 13's plane scene as plain numbers, independent of the renderer: the scene file's
//! camera and airliner values, the model's vertices, and a pinhole projection written from them.
//! Shared by `thesis_plane.rs`, `figure13_readings.rs` and the example
//! `figure13_readings` (which includes this file by path), so the numbers the docs print and
//! the numbers the tests check against renders come from one projection.

#![allow(dead_code)] // each user takes what it needs

use renderer::progress::NoProgress;
use renderer::render::render_frame;
use renderer::sampling::{SamplingConfig, SpatialFilter};
use renderer::scene::Scene;
use serde_json::Value;
use std::path::{Path, PathBuf};

pub type V3 = [f64; 3];

pub fn scene_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/thesis/plane.json")
}

/// The scene file as JSON.
pub fn scene_json() -> Value {
    serde_json::from_str(&std::fs::read_to_string(scene_path()).unwrap()).unwrap()
}

fn v3(v: &Value) -> V3 {
    let a = v.as_array().expect("a 3-vector");
    [0, 1, 2].map(|i| a[i].as_f64().expect("a number"))
}
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn mul(a: V3, s: f64) -> V3 {
    a.map(|x| x * s)
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: V3) -> V3 {
    mul(a, 1.0 / dot(a, a).sqrt())
}

/// The scene's numbers as the file gives them, and the model's vertices in world units at t = 0.
pub struct Plane {
    pub json: Value,
    pub vertices: Vec<V3>,
    pub velocity: V3,
    pub start: f64,
    pub frame_time: f64,
    pub frames: u32,
}

impl Plane {
    pub fn load() -> Self {
        Self::from_json(scene_json())
    }

    /// The plane scene with `json`'s values (the model file resolved beside `plane.json`).
    pub fn from_json(json: Value) -> Self {
        let object = &json["objects"][0];
        let scale = object["scale"].as_f64().unwrap();
        let location = v3(&object["location"]);
        let obj = scene_path()
            .parent()
            .unwrap()
            .join(object["file"].as_str().unwrap());
        let vertices = std::fs::read_to_string(obj)
            .unwrap()
            .lines()
            .filter_map(|l| l.strip_prefix("v "))
            .map(|l| {
                let p: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
                add(mul([p[0], p[1], p[2]], scale), location)
            })
            .collect();
        let s = &json["settings"];
        Self {
            velocity: v3(&object["velocity"]),
            start: s["start_time"].as_f64().unwrap(),
            frame_time: s["frame_time"].as_f64().unwrap(),
            frames: s["frames"].as_u64().unwrap() as u32,
            vertices,
            json,
        }
    }

    pub fn mid_time(&self, frame: u32) -> f64 {
        self.start + (frame as f64 + 0.5) * self.frame_time
    }

    /// Film coordinates (pixels from the top-left, x right, y down) of world point `p` at time
    /// `t` in a `size` x `size` image, or `None` behind the eye.
    pub fn project(&self, p: V3, t: f64, size: f64) -> Option<(f64, f64)> {
        let c = &self.json["camera"];
        let at = |k: &str, kv: &str| add(v3(&c[k]), mul(v3(&c[kv]), t));
        let eye = at("location", "location_velocity");
        let forward = unit(sub(at("look_at", "look_at_velocity"), eye));
        let right = unit(cross(forward, at("up", "up_velocity")));
        let up = cross(right, forward);
        let half = (c["fov"].as_f64().unwrap().to_radians() / 2.0).tan();
        let d = sub(p, eye);
        let z = dot(d, forward);
        (z > 0.0).then(|| {
            let (sx, sy) = (dot(d, right) / z / half, dot(d, up) / z / half);
            ((sx + 1.0) / 2.0 * size, (1.0 - sy) / 2.0 * size)
        })
    }

    /// Projected bounding box (x0, x1, y0, y1) of the airliner's vertices at frame `frame`'s
    /// mid-shutter time, if every vertex is in front of the eye.
    pub fn extent(&self, frame: u32, size: f64) -> Option<[f64; 4]> {
        let t = self.mid_time(frame);
        let moved = mul(self.velocity, t);
        let mut e = [f64::MAX, f64::MIN, f64::MAX, f64::MIN];
        for &v in &self.vertices {
            let (x, y) = self.project(add(v, moved), t, size)?;
            e = [e[0].min(x), e[1].max(x), e[2].min(y), e[3].max(y)];
        }
        Some(e)
    }

    /// Projected position of the airliner's centre (its vertices' bounding-box centre).
    pub fn centre(&self, frame: u32, size: f64) -> Option<(f64, f64)> {
        let (lo, hi) = self
            .vertices
            .iter()
            .fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), v| {
                (
                    [0, 1, 2].map(|i| lo[i].min(v[i])),
                    [0, 1, 2].map(|i| hi[i].max(v[i])),
                )
            });
        let t = self.mid_time(frame);
        self.project(add(mul(add(lo, hi), 0.5), mul(self.velocity, t)), t, size)
    }
}

/// Where the airliner is on screen over the whole animation, at `size` x `size`.
#[derive(Debug, PartialEq)]
pub struct Track {
    /// Frames where some of the airliner is in view (its projected box meets the image).
    pub any: Vec<u32>,
    /// Frames where all of it is in view.
    pub whole: Vec<u32>,
    /// Frames where its centre is in view.
    pub centre: Vec<u32>,
    /// The centre's largest move between consecutive frames with the centre in view, pixels.
    pub peak_px_per_frame: f64,
    /// Its longest projected length (box width) in a frame where it is whole in view, pixels.
    pub longest_px: f64,
}

pub fn track(plane: &Plane, size: f64) -> Track {
    let inside = |x: f64, y: f64| (0.0..size).contains(&x) && (0.0..size).contains(&y);
    let mut t = Track {
        any: vec![],
        whole: vec![],
        centre: vec![],
        peak_px_per_frame: 0.0,
        longest_px: 0.0,
    };
    for f in 0..plane.frames {
        if let Some([x0, x1, y0, y1]) = plane.extent(f, size) {
            if x1 > 0.0 && x0 < size && y1 > 0.0 && y0 < size {
                t.any.push(f);
            }
            if x0 >= 0.0 && x1 <= size && y0 >= 0.0 && y1 <= size {
                t.whole.push(f);
                t.longest_px = t.longest_px.max(x1 - x0);
            }
        }
        let c = plane.centre(f, size).filter(|&(x, y)| inside(x, y));
        let next = plane.centre(f + 1, size).filter(|&(x, y)| inside(x, y));
        if c.is_some() {
            t.centre.push(f);
        }
        if let (Some(a), Some(b)) = (c, next.filter(|_| f + 1 < plane.frames)) {
            t.peak_px_per_frame = t.peak_px_per_frame.max((a.0 - b.0).hypot(a.1 - b.1));
        }
    }
    t
}

/// One way to read Figure 13's printed values: what it changes in `plane.json`.
pub struct Reading {
    pub name: &'static str,
    pub what: &'static str,
    pub edit: fn(&mut Value),
}

/// The stand-in model's fuselage axis above its origin, in model units (scenes/README.md).
pub const AXIS_MODEL_Y: f64 = 350.0 / 13.0;
/// The stand-in model's length in model units (153.2 ft at scale 13).
pub const MODEL_LENGTH: f64 = 153.2 / 13.0;

fn set_location_y(v: &mut Value, y: f64) {
    v["objects"][0]["location"][1] = y.into();
}

fn set_scale(v: &mut Value, scale: f64) {
    v["objects"][0]["scale"] = scale.into();
}

/// The readings of Figure 13's geometry that keep its printed numbers, the suite's first.
pub fn readings() -> Vec<Reading> {
    vec![
        Reading {
            name: "suite",
            what: "feet; model 13 ft per unit with its axis 350 ft above its origin; `location` \
                   the origin; fov 50 deg per side (square image); frametime between frames, \
                   shutter the frame interval",
            edit: |_| {},
        },
        Reading {
            name: "centred model",
            what: "the model centred on its origin (or `location` naming its centre): the \
                   airliner flies at y = 0, 375 ft below the camera",
            edit: |v| set_location_y(v, -AXIS_MODEL_Y * 13.0),
        },
        Reading {
            name: "model in metres",
            what: "the model's units metres (a 46.7 m model), centred: scale 13 makes it 607 ft long",
            edit: |v| {
                let s = 13.0 * MODEL_LENGTH / 46.69;
                set_scale(v, s);
                set_location_y(v, -AXIS_MODEL_Y * s);
            },
        },
        Reading {
            name: "unit-length model",
            what: "the model normalised to length 1, centred: scale 13 makes it 13 ft long",
            edit: |v| {
                let s = 13.0 / MODEL_LENGTH;
                set_scale(v, s);
                set_location_y(v, -AXIS_MODEL_Y * s);
            },
        },
        Reading {
            name: "diagonal fov",
            what: "fov 50 deg across the diagonal: 36.5 deg per side",
            edit: |v| {
                let side = 2.0 * ((25f64).to_radians().tan() / 2f64.sqrt()).atan();
                v["camera"]["fov"] = side.to_degrees().into();
            },
        },
        Reading {
            name: "half-angle fov",
            what: "fov 50 deg from the centre to the edge: 100 deg per side",
            edit: |v| v["camera"]["fov"] = 100.0.into(),
        },
        Reading {
            name: "frametime = shutter",
            what: "frametime 0.12 s the shutter only, frames 1/30 s of scene time apart: the \
                   animation spans -12.5 to -5.5 s",
            edit: |v| v["settings"]["frame_time"] = (1.0 / 30.0).into(),
        },
    ]
}

/// The plane scene under `reading`.
pub fn read_as(reading: &Reading) -> Value {
    let mut v = scene_json();
    (reading.edit)(&mut v);
    v
}

/// Columns and rows of the airliner's pixels in a render held still at the frame's mid-shutter
/// time, without the sky (black background; the airliner is never black: ambient light), or
/// `None` when no pixel shows it.
pub fn rendered_extent(scene: &Scene, frame: u32, size: u32) -> Option<[u32; 4]> {
    let (t0, t1) = scene.settings.shutter(frame);
    let still = scene.frozen_at(0.5 * (t0 + t1));
    let cfg = SamplingConfig {
        point_set: renderer::condition::PointSetKind::Stratified,
        spp: 8,
        time_filter: renderer::condition::TimeFilter::Box,
        // Samples stay inside their pixel: a pixel shows the airliner only if it covers it.
        spatial_filter: Some(SpatialFilter::Box),
        ..SamplingConfig::default()
    };
    let (film, stats) = render_frame(&still, &cfg, 1, frame, &NoProgress).unwrap();
    assert_eq!(stats.non_finite, 0);
    let mut e: Option<[u32; 4]> = None;
    for (i, p) in film.pixels.iter().enumerate() {
        if p.max_element() > 0.0 {
            let (x, y) = (i as u32 % size, i as u32 / size);
            e = Some(match e {
                None => [x, x, y, y],
                Some([x0, x1, y0, y1]) => [x0.min(x), x1.max(x), y0.min(y), y1.max(y)],
            });
        }
    }
    e
}
