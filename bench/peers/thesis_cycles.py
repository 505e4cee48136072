"""The thesis's plane scene (frame 93) in Blender Cycles against the suite at equal CPU time
(issue 30, item 4; docs/benchmarks/peers.md "The thesis's plane scene in Blender Cycles").
Optional tooling: not part of the tests, not run by CI. Needs bpy (5.0.1 in a Python 3.11 venv
was used) and numpy:

    python bench/peers/thesis_cycles.py --bin DIR_WITH_sample_cost --cache DIR [--size 192]

The Cycles scene is built from the suite's own scene file (scenes/thesis/plane.json: the
stand-in airliner OBJ, its velocity, the moving camera, the directional light, the stand-in
Cedar City map), so that both render the same image:

- Shading: the suite's Whitted formula (renderer/src/shading/mod.rs), L = ka A + V E (kd n.l +
  ks max(0, r.v)^p) + F(n.v) ks L(mirror). Cycles has no Phong lobe, but the light is
  directional, so the Phong term is folded into a diffuse BSDF's colour, kd + ks (r.v)^p / (n.l),
  computed by shader nodes (Cycles' diffuse eval is colour n.l / pi, so the sun's strength is
  pi E). The mirror term is a sharp GGX glossy BSDF with colour F(n.v) ks; the ambient term an
  emission that diffuse rays do not see. The sky is seen by camera and glossy rays only (the
  suite has no global illumination); diffuse bounces are 0, glossy bounces max_depth.
- Time: one frame's shutter with the suite's triangle time filter as Cycles' shutter curve;
  the shutter coverage compensated as scramble_cycles.py does (Cycles samples about
  [0.5/256, 254.5/256] of it). The airliner moves linearly (two keys, exact); the camera's
  look-at frame is keyed at 33 times across the shutter and sampled by Cycles at 17 motion
  steps (it interpolates between them).
- Film: the suite's Gaussian pixel filter (sigma 0.5 px) is Cycles' Gaussian of width 2 px
  (Cycles' film.cpp tabulates exp(-2 (6 x / W)^2) with W = 3 w out to W / 2: sigma = w / 4,
  cut at 6 sigma).

Steps: (1) agreement of the converged images (two references per renderer; the squared
difference of their averages over the noise they carry: 1 = they differ by noise only);
(2) cost, interleaved rounds, CPU time of one thread each, medians; (3) equal time: the suite
at the spp its cost per sample affords in Cycles' median CPU time, RMSE against the converged
reference, mean over seeds.
"""

import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys
from pathlib import Path

import numpy as np

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
from peers import cpu, rmse  # noqa: E402
from scramble_cycles import Cycles as BoxScene  # noqa: E402

linear = BoxScene._linear  # linear keyframes, whatever the action API

REPO = Path(__file__).resolve().parents[2]
SCENE = REPO / "scenes/thesis/plane.json"
FRAME = 93
CYCLES_T0, CYCLES_T1 = 0.5 / 256, 254.5 / 256  # the part of the shutter Cycles samples
CAMERA_KEYS = 33  # camera keys across the shutter
CAMERA_STEPS = 5  # Cycles motion steps: 2^(5-1) + 1 = 17 camera transforms


def b(v):
    """The suite is y-up, Blender z-up: (x, y, z) -> (x, -z, y) (a rotation)."""
    return Vector((v[0], -v[2], v[1]))


def unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


# ---------------------------------------------------------------- the suite


def suite_scene(desc, size, path):
    """The scene file at `size` x `size`, its model and map named by absolute path."""
    s = json.loads(json.dumps(desc))
    s["settings"]["width"] = s["settings"]["height"] = size
    for o in s["objects"]:
        if "file" in o:
            o["file"] = str(SCENE.parent / o["file"])
    env = s["settings"]["environment"]
    env["file"] = str(SCENE.parent / env["file"])
    path.write_text(json.dumps(s, indent=1))


def ours(args, scene, spp, seed, out=None):
    cmd = [str(args.bin / "sample_cost"), str(scene), "--frame", str(FRAME), "--spp", str(spp),
           "--rounds", "1", "--seed", str(seed)]
    if out is not None:
        cmd += ["--out", str(out)]
    lines = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.splitlines()
    words = [line for line in lines if line.startswith("round")][0].split()
    img = None
    if out is not None:
        img = np.fromfile(out, dtype="<f4").reshape(args.size, args.size, 3).astype(np.float64)
    return float(words[words.index("cpu_s") + 1]), img


# ---------------------------------------------------------------- Cycles


class Cycles:
    def __init__(self, desc, size, work, threads):
        self.work, self.size = work, size
        bpy.ops.wm.read_factory_settings(use_empty=True)
        sc = bpy.context.scene
        self.sc = sc
        self._settings(size, threads, desc["settings"]["max_depth"])
        st = desc["settings"]
        self.t_open = st["start_time"] + FRAME * st["frame_time"]
        self.frame_time = st["frame_time"]
        self._world(SCENE.parent / st["environment"]["file"])
        light = desc["lights"][0]
        towards = unit(-np.asarray(light["direction"]))
        material = self._material(desc["materials"][0], towards, st["ambient_light"])
        self._airliner(desc["objects"][0], material)
        self._camera(desc["camera"])
        self._sun(light, towards)
        self._shutter()

    def _settings(self, size, threads, depth):
        sc = self.sc
        sc.render.engine = "CYCLES"
        cy = sc.cycles
        cy.device = "CPU"
        sc.render.threads_mode = "FIXED"
        sc.render.threads = threads
        sc.render.resolution_x = sc.render.resolution_y = size
        sc.render.resolution_percentage = 100
        sc.render.use_persistent_data = False
        cy.use_denoising = False
        cy.use_adaptive_sampling = False
        cy.max_bounces = cy.glossy_bounces = depth
        cy.diffuse_bounces = cy.transmission_bounces = cy.volume_bounces = 0
        cy.transparent_max_bounces = 0
        cy.caustics_reflective = cy.caustics_refractive = False
        cy.blur_glossy = 0.0  # no "filter glossy": it would blur the mirror
        cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
        cy.light_sampling_threshold = 0.0
        cy.pixel_filter_type = "GAUSSIAN"
        cy.filter_width = 2.0  # sigma = width / 4 = 0.5 px, the suite's default
        cy.use_animated_seed = False
        sc.view_settings.view_transform = "Standard"
        sc.view_settings.look = "None"
        sc.view_settings.exposure = 0.0
        sc.view_settings.gamma = 1.0
        sc.render.image_settings.file_format = "OPEN_EXR"
        sc.render.image_settings.color_depth = "32"
        sc.render.image_settings.exr_codec = "NONE"
        sc.render.use_compositing = False
        sc.render.use_sequencer = False

    def _world(self, hdr):
        """The sky for camera and glossy rays only, not sampled as a light."""
        world = bpy.data.worlds.new("sky")
        world.use_nodes = True
        nt = world.node_tree
        tex = nt.nodes.new("ShaderNodeTexEnvironment")
        tex.image = bpy.data.images.load(str(hdr))
        tex.interpolation = "Linear"
        tex.projection = "EQUIRECTANGULAR"
        # The suite's u = atan2(x, -z) / 2pi + 0.5 (y up); Cycles' u = -atan2(y, x) / 2pi + 0.5
        # (z up) is the suite's u - 0.25 there: turn the direction by -90 degrees about z.
        coord = nt.nodes.new("ShaderNodeTexCoord")
        mapping = nt.nodes.new("ShaderNodeMapping")
        mapping.vector_type = "VECTOR"
        mapping.inputs["Rotation"].default_value = (0.0, 0.0, -math.pi / 2)
        nt.links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
        nt.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
        bg = nt.nodes["Background"]
        bg.inputs["Strength"].default_value = 1.0
        nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
        self.sc.world = world  # before its Cycles settings, whose update needs it
        world.cycles.sampling_method = "NONE"
        vis = world.cycles_visibility
        vis.diffuse = vis.transmission = vis.scatter = False
        vis.camera = vis.glossy = True

    def _material(self, m, towards, ambient_light):
        mat = bpy.data.materials.new(m["name"])
        mat.use_nodes = True
        mat.cycles.emission_sampling = "NONE"
        nt = mat.node_tree
        nt.nodes.remove(nt.nodes["Principled BSDF"])
        n, link = nt.nodes, nt.links.new
        kd = np.asarray(m["diffuse"], dtype=np.float64)
        ks = np.asarray(m["specular"], dtype=np.float64)
        ka = np.asarray(m["ambient"], dtype=np.float64) * np.asarray(ambient_light)
        p = m.get("phong_exponent", 32.0)
        fr = m["fresnel"]

        def math_node(op, a, c=None, d=None):
            node = n.new("ShaderNodeMath")
            node.operation = op
            for i, x in enumerate((a, c, d)):
                if x is None:
                    continue
                if isinstance(x, (int, float)):
                    node.inputs[i].default_value = x
                else:
                    link(x, node.inputs[i])
            return node.outputs[0]

        def dot(a, c):
            node = n.new("ShaderNodeVectorMath")
            node.operation = "DOT_PRODUCT"
            link(a, node.inputs[0])
            if isinstance(c, Vector):
                node.inputs[1].default_value = c
            else:
                link(c, node.inputs[1])
            return node.outputs["Value"]

        def colour(base, scale, weight):
            """base + scale * weight, per channel (base, scale: RGB arrays; weight: a socket)."""
            comb = n.new("ShaderNodeCombineColor")
            for i, ch in enumerate(("Red", "Green", "Blue")):
                link(math_node("MULTIPLY_ADD", weight, float(scale[i]), float(base[i])),
                     comb.inputs[ch])
            return comb.outputs["Color"]

        geo = n.new("ShaderNodeNewGeometry")
        nrm, view = geo.outputs["Normal"], geo.outputs["Incoming"]
        light = b(towards)
        nl = dot(nrm, light)
        nv = dot(nrm, view)
        # r = reflect(-l, n) = 2 (n.l) n - l, so r.v = 2 (n.l)(n.v) - l.v.
        rv = math_node("SUBTRACT", math_node("MULTIPLY", math_node("MULTIPLY", nl, 2.0), nv),
                       dot(view, light))
        rv = math_node("MINIMUM", math_node("MAXIMUM", rv, 0.0), 1.0)
        phong_over_cos = math_node("DIVIDE", math_node("POWER", rv, float(p)),
                                   math_node("MAXIMUM", nl, 1e-6))
        diffuse = n.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Roughness"].default_value = 0.0
        link(colour(kd, ks, phong_over_cos), diffuse.inputs["Color"])
        # F(n.v) = min + (max - min) (1 - clamp(n.v))^exponent, times ks.
        one_minus = math_node("SUBTRACT", 1.0, math_node("MINIMUM", math_node("MAXIMUM", nv, 0.0),
                                                         1.0))
        f = math_node("MULTIPLY_ADD", math_node("POWER", one_minus, float(fr["exponent"])),
                      float(fr["max"] - fr["min"]), float(fr["min"]))
        glossy = n.new("ShaderNodeBsdfGlossy")
        glossy.distribution = "GGX"
        glossy.inputs["Roughness"].default_value = 0.0
        link(colour(np.zeros(3), ks, f), glossy.inputs["Color"])
        # The ambient term, seen by every ray but the diffuse ones (no global illumination).
        path = n.new("ShaderNodeLightPath")
        emission = n.new("ShaderNodeEmission")
        emission.inputs["Color"].default_value = (*ka, 1.0)
        link(math_node("SUBTRACT", 1.0, path.outputs["Is Diffuse Ray"]),
             emission.inputs["Strength"])
        add1, add2 = n.new("ShaderNodeAddShader"), n.new("ShaderNodeAddShader")
        link(diffuse.outputs[0], add1.inputs[0])
        link(glossy.outputs[0], add1.inputs[1])
        link(add1.outputs[0], add2.inputs[0])
        link(emission.outputs[0], add2.inputs[1])
        link(add2.outputs[0], n["Material Output"].inputs["Surface"])
        return mat

    def _airliner(self, o, material):
        verts, normals, faces = [], [], []
        for line in (SCENE.parent / o["file"]).read_text().splitlines():
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                verts.append(tuple(b([float(x) for x in w[1:4]])))
            elif w[0] == "vn":
                normals.append(tuple(b([float(x) for x in w[1:4]])))
            elif w[0] == "f":
                faces.append(tuple(int(x.split("/")[0]) - 1 for x in w[1:]))
        mesh = bpy.data.meshes.new("airliner")
        mesh.from_pydata(verts, [], faces)
        mesh.shade_smooth()
        assert len(normals) == len(verts), "the stand-in OBJ has one normal per vertex"
        mesh.normals_split_custom_set_from_vertices(normals)
        mesh.materials.append(material)
        ob = bpy.data.objects.new("airliner", mesh)
        self.sc.collection.objects.link(ob)
        ob.scale = (o["scale"],) * 3
        loc, vel = np.asarray(o["location"]), np.asarray(o.get("velocity", [0, 0, 0]))
        for f in (9.5, 10.5):
            ob.location = b(loc + vel * self.suite_time(f))
            ob.keyframe_insert("location", frame=f)
        linear(ob)
        ob.cycles.use_motion_blur = True
        ob.cycles.motion_steps = 1

    def suite_time(self, f):
        """Suite time at Cycles frame f (frame 10's shutter is [9.5, 10.5]), compensated."""
        s = (f - 9.5 - CYCLES_T0) / (CYCLES_T1 - CYCLES_T0)
        return self.t_open + s * self.frame_time

    def _camera(self, c):
        cam = bpy.data.cameras.new("cam")
        cam.sensor_fit = "AUTO"
        cam.angle = math.radians(c["fov"])
        cam.clip_start, cam.clip_end = 1e-2, 1e6
        co = bpy.data.objects.new("cam", cam)
        self.sc.collection.objects.link(co)
        co.rotation_mode = "QUATERNION"

        def at(name, t):
            return np.asarray(c[name]) + np.asarray(c.get(name + "_velocity", [0, 0, 0])) * t

        for k in range(CAMERA_KEYS):
            f = 9.5 + k / (CAMERA_KEYS - 1)
            t = self.suite_time(f)
            eye = at("location", t)
            fwd = unit(at("look_at", t) - eye)
            right = unit(np.cross(fwd, at("up", t)))
            up = np.cross(right, fwd)
            m = Matrix.Identity(4)
            for i, (r, u, bk, e) in enumerate(zip(b(right), b(up), b(-fwd), b(eye))):
                m[i][0], m[i][1], m[i][2], m[i][3] = r, u, bk, e
            co.matrix_world = m
            co.keyframe_insert("location", frame=f)
            co.keyframe_insert("rotation_quaternion", frame=f)
        linear(co)
        co.cycles.use_motion_blur = True
        co.cycles.motion_steps = CAMERA_STEPS
        self.sc.camera = co

    def _sun(self, light, towards):
        sun = bpy.data.lights.new("sun", "SUN")
        sun.color = light.get("color", [1, 1, 1])
        sun.energy = math.pi * light.get("intensity", 1.0)  # Cycles' diffuse is rho / pi E cos
        sun.angle = 0.0
        so = bpy.data.objects.new("sun", sun)
        so.rotation_mode = "QUATERNION"
        so.rotation_quaternion = b(towards).to_track_quat("Z", "Y")
        self.sc.collection.objects.link(so)

    def _shutter(self):
        sc = self.sc
        sc.frame_start = sc.frame_end = 10
        sc.render.fps = 10
        sc.frame_set(10)
        sc.render.use_motion_blur = True
        sc.render.motion_blur_shutter = 1.0
        sc.render.motion_blur_position = "CENTER"
        curve = sc.render.motion_blur_shutter_curve
        pts = curve.curves[0].points
        pts[0].location = (0.0, 0.0)
        pts[-1].location = (1.0, 0.0)
        pts.new(0.5, 1.0)
        for pt in pts:
            pt.handle_type = "VECTOR"
        curve.update()

    def render(self, spp, seed=0):
        """(CPU seconds of the render call, linear RGB image, rows top to bottom)."""
        cy = self.sc.cycles
        cy.samples = spp
        cy.seed = seed
        path = str(self.work / "cycles.exr")
        self.sc.render.filepath = path
        t = cpu()
        bpy.ops.render.render(write_still=True)
        dt = cpu() - t
        img = bpy.data.images.load(path, check_existing=False)
        px = np.array(img.pixels[:], dtype=np.float64).reshape(self.size, self.size, 4)
        bpy.data.images.remove(img)
        return dt, px[::-1, :, :3]


# ---------------------------------------------------------------- the comparison


def agreement(args, cyc, scene, raw, report):
    """Two converged references per renderer; returns (suite's, Cycles')."""
    refs_o = [ours(args, scene, args.ref_spp, 100 + k, raw)[1] for k in range(2)]
    refs_c = [cyc.render(args.cycles_ref_spp, 100 + k)[1] for k in range(2)]
    noise_o = np.mean((refs_o[0] - refs_o[1]) ** 2) / 2
    noise_c = np.mean((refs_c[0] - refs_c[1]) ** 2) / 2
    ref_o, ref_c = (refs_o[0] + refs_o[1]) / 2, (refs_c[0] + refs_c[1]) / 2
    report["agreement_mse_over_noise"] = float(np.mean((ref_o - ref_c) ** 2)
                                               / ((noise_o + noise_c) / 2))
    report["reference_noise_rms"] = {"suite": float(math.sqrt(noise_o)),
                                     "cycles": float(math.sqrt(noise_c))}
    report["mean_ratio_suite_over_cycles"] = float(ref_o.mean() / ref_c.mean())
    report["reference_rms_difference"] = rmse(ref_o, ref_c)
    np.save(args.cache / "ref_suite.npy", ref_o)
    np.save(args.cache / "ref_cycles.npy", ref_c)
    return ref_o, ref_c


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--bin", type=Path, required=True)
    p.add_argument("--cache", type=Path, required=True)
    p.add_argument("--size", type=int, default=192)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--ref-spp", type=int, default=4096)
    p.add_argument("--cycles-ref-spp", type=int, default=1024)
    p.add_argument("--cycles-spp", type=int, default=16)
    p.add_argument("--time-spp", type=int, default=64)
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--ref-threads", type=int, default=2, help="Cycles' references only")
    p.add_argument("--agreement-only", action="store_true")
    args = p.parse_args()
    args.cache.mkdir(parents=True, exist_ok=True)
    desc = json.loads(SCENE.read_text())
    scene = args.cache / "plane.json"
    suite_scene(desc, args.size, scene)
    raw = args.cache / "img.f32"
    report = {"machine": f"{platform.machine()}, {os.cpu_count()} CPUs, load average "
                         + " ".join(f"{x:.1f}" for x in os.getloadavg()),
              "bpy": bpy.app.version_string, "size": args.size, "frame": FRAME}

    cyc = Cycles(desc, args.size, args.cache, args.ref_threads)
    ref_o, ref_c = agreement(args, cyc, scene, raw, report)
    print(json.dumps(report), file=sys.stderr, flush=True)
    if args.agreement_only:
        print("\n" + json.dumps(report, indent=2), flush=True)
        return
    cyc.sc.render.threads = 1

    # Cost, interleaved, one thread each.
    t_o, t_c = [], []
    cyc.render(args.cycles_spp, 1)  # a first render before timing
    for rnd in range(args.rounds):
        t_o.append(ours(args, scene, args.time_spp, 1 + rnd)[0])
        t_c.append(cyc.render(args.cycles_spp, 1 + rnd)[0])
    px = args.size * args.size
    ns_o = statistics.median(t_o) / (px * args.time_spp) * 1e9
    budget = statistics.median(t_c)
    report["suite_ns_per_sample"] = ns_o
    report["cycles_ns_per_sample"] = budget / (px * args.cycles_spp) * 1e9
    report["suite_cpu_s"], report["cycles_cpu_s"] = t_o, t_c
    report["budget_cpu_s"] = budget

    # Equal time, against each reference and their mean.
    spp = max(1, int(budget / (ns_o * 1e-9 * px)))
    refs = {"suite": ref_o, "cycles": ref_c, "mean": (ref_o + ref_c) / 2}
    errs_c = {k: [] for k in refs}
    errs_o = {k: [] for k in refs}
    times = []
    for s in range(args.seeds):
        img_c = cyc.render(args.cycles_spp, 7 + s)[1]
        t, img_o = ours(args, scene, spp, 7 + s, raw)
        times.append(t)
        for k, r in refs.items():
            errs_c[k].append(rmse(img_c, r))
            errs_o[k].append(rmse(img_o, r))
    report["equal_time"] = {
        "cycles_spp": args.cycles_spp, "suite_spp": spp,
        "suite_cpu_s_over_budget": statistics.median(times) / budget,
        "rmse_cycles": {k: statistics.mean(v) for k, v in errs_c.items()},
        "rmse_suite": {k: statistics.mean(v) for k, v in errs_o.items()},
        "suite_over_cycles": {k: statistics.mean(errs_o[k]) / statistics.mean(errs_c[k])
                              for k in refs}}
    report["load_average_after"] = " ".join(f"{x:.1f}" for x in os.getloadavg())
    print("\n" + json.dumps(report, indent=2), flush=True)


if __name__ == "__main__":
    main()
