//! Writing a [`SceneFile`] as a `.scene` file: blocks in the order of [`super::BLOCKS`], keys
//! in Figure 13's order. Every key Figure 13 shows is written (so a converted scene reads like
//! the figure), every other key only when it differs from its default; every name is written,
//! derived or not.

use crate::sampling::SamplingConfig;
use crate::scene::SCENE_FORMAT;
use crate::scene::file::{
    CameraDesc, DEFAULT_FPS, DEFAULT_PHONG_EXPONENT, GroupDesc, InstanceDesc, LightDesc, LightKind,
    MaterialDesc, ObjectDesc, ObjectKind, Scale, SceneFile, SettingsDesc,
};
use crate::text::sampling::{self as options, Host};
use crate::text::{Out, names};
use anyhow::{Result, bail};

/// The text of `f`. Fails only for what the text cannot say: another format version.
pub fn write(f: &SceneFile) -> Result<String> {
    if f.format != SCENE_FORMAT {
        bail!(
            "field `format` is {:?}; the block format holds {SCENE_FORMAT:?} scenes",
            f.format
        );
    }
    let mut out = Out::default();
    out.bare("# blurlab scene, the thesis's block format (Figure 13); see docs/thesis-formats.md");
    for m in &f.materials {
        block(&mut out, "material", |o| material(o, m));
    }
    for d in &f.objects {
        block(&mut out, "object", |o| object(o, d));
    }
    for d in &f.instances {
        block(&mut out, "objectinstance", |o| instance(o, d));
    }
    for g in &f.groups {
        block(&mut out, "group", |o| group(o, g));
    }
    for l in &f.lights {
        block(&mut out, "light", |o| light(o, l));
    }
    block(&mut out, "camera", |o| camera(o, &f.camera));
    let mut result = Ok(());
    block(&mut out, "settings", |o| {
        result = settings(o, &f.settings, f.name.as_deref(), f.description.as_deref())
    });
    result?;
    Ok(out.text)
}

fn block(out: &mut Out, kind: &str, body: impl FnOnce(&mut Out)) {
    out.bare("");
    out.bare(kind);
    body(out);
    out.bare("end");
}

fn material(o: &mut Out, m: &MaterialDesc) {
    o.word("materialname", &m.name);
    o.numbers("diffusecolor", &m.diffuse);
    o.numbers("specularcolor", &m.specular);
    o.numbers("ambientcolor", &m.ambient);
    o.f32_unless("phongexponent", m.phong_exponent, DEFAULT_PHONG_EXPONENT);
    if let Some(fr) = m.fresnel {
        o.number("fresnelminimum", fr.min);
        o.number("fresnelmaximum", fr.max);
        o.number("fresnelexponent", fr.exponent);
    }
}

fn scale(o: &mut Out, s: Option<Scale>) {
    match s {
        None => {}
        Some(Scale::Uniform(k)) => o.number("scale", k),
        Some(Scale::PerAxis(v)) => o.numbers("scale", &v),
    }
}

/// Location and velocity (Figure 13's), then rotation and angular velocity when not zero.
fn placement(o: &mut Out, p: [[f32; 3]; 4]) {
    o.numbers("location", &p[0]);
    o.numbers("velocity", &p[1]);
    o.vec_unless("rotation", p[2], [0.0; 3]);
    o.vec_unless("angularvelocity", p[3], [0.0; 3]);
}

fn object(o: &mut Out, d: &ObjectDesc) {
    o.word("objectname", &d.name);
    let kind = match d.kind {
        ObjectKind::Model => "model",
        ObjectKind::Sphere => "sphere",
        ObjectKind::Plane => "plane",
    };
    o.raw(&["type", kind]);
    o.word("materialname", &d.material);
    if let Some(f) = &d.file {
        o.word("modelfilename", f);
    }
    if let Some(r) = d.radius {
        o.number("radius", r);
    }
    if let Some(h) = d.half_extent {
        o.numbers("halfextent", &h);
    }
    scale(o, d.scale);
    placement(o, [d.location, d.velocity, d.rotation, d.angular_velocity]);
    if d.hidden {
        o.raw(&["hidden", "true"]);
    }
}

fn instance(o: &mut Out, d: &InstanceDesc) {
    o.word("instancename", &d.name);
    o.word("objectname", &d.object);
    if let Some(m) = &d.material {
        o.word("materialname", m);
    }
    scale(o, d.scale);
    placement(o, [d.location, d.velocity, d.rotation, d.angular_velocity]);
}

fn group(o: &mut Out, g: &GroupDesc) {
    o.word("groupname", &g.name);
    if !g.children.is_empty() {
        o.words("children", &g.children);
    }
    scale(o, g.scale);
    placement(o, [g.location, g.velocity, g.rotation, g.angular_velocity]);
}

fn light(o: &mut Out, l: &LightDesc) {
    let kind = match l.kind {
        LightKind::Point => "point",
        LightKind::Directional => "directional",
    };
    o.raw(&["type", kind]);
    o.vec_unless("color", l.color, [1.0; 3]);
    o.f32_unless("intensity", l.intensity, 1.0);
    if let Some(p) = l.position {
        o.numbers("position", &p);
    }
    if let Some(d) = l.direction {
        o.numbers("direction", &d);
    }
}

/// Figure 13's order.
fn camera(o: &mut Out, c: &CameraDesc) {
    o.numbers("location", &c.location);
    o.numbers("locationvelocity", &c.location_velocity);
    o.numbers("lookat", &c.look_at);
    o.numbers("up", &c.up);
    o.numbers("upvelocity", &c.up_velocity);
    o.numbers("lookatvelocity", &c.look_at_velocity);
    o.number("fov", c.fov);
}

/// Figure 13's order, then what Figure 13 leaves out.
fn settings(
    o: &mut Out,
    s: &SettingsDesc,
    name: Option<&str>,
    description: Option<&str>,
) -> Result<()> {
    o.number("starttime", s.start_time);
    o.number("frametime", s.frame_time);
    o.number("numframes", s.frames);
    if s.fps.to_bits() != DEFAULT_FPS.to_bits() {
        o.number("fps", s.fps);
    }
    o.number("sizex", s.width);
    o.number("sizey", s.height);
    o.numbers("ambientlightcolor", &s.ambient_light);
    o.number("maxdepth", s.max_depth);
    sampling(o, &s.sampling)?;
    if let Some(e) = &s.environment {
        o.word("envmap", &e.file);
        o.f32_unless("envmapintensity", e.intensity, 1.0);
        o.f32_unless("envmaprotation", e.rotation, 0.0);
        if let Some(n) = e.negatives {
            o.word("envmapnegatives", n.name());
        }
    }
    o.f32_unless("exposure", s.exposure, 1.0);
    if let Some(n) = name {
        o.word("scenename", n);
    }
    if let Some(d) = description {
        o.word("description", d);
    }
    Ok(())
}

fn sampling(o: &mut Out, c: &SamplingConfig) -> Result<()> {
    let (ps, tf) = (
        names::point_set_to_text(c.point_set),
        names::time_filter_to_text(c.time_filter),
    );
    o.word("pointset", ps);
    o.number("numsamples", c.spp);
    o.word("timefilter", tf);
    options::write(&c.options(), o, Host::Scene);
    Ok(())
}
