"""The suite's shift and scramble against Blender Cycles on a matched motion-blurred scene
(run through scramble.sh; needs the bpy wheel, Python 3.13).

A 256 x 256 diffuse sphere (radius 1, kd 0.7) moving along x during a box shutter, above a
40 x 40 ground (kd 0.5), one directional light, direct light only, box pixel filter. The suite
renders it with the `sample_cost` example; Cycles (one thread, no bounces, next-event
estimation only, a sun of angle 0 and strength pi: its Lambert term is rho / pi E cos) the same
scene built here with bpy, the sphere a one-point point cloud (an analytic sphere) keyframed
linearly so that it sits at x = -TRAVEL/2 when the shutter opens and +TRAVEL/2 when it closes.

1. Agreement: two high-spp references per renderer, mean ratio and the squared difference of
   the two renderers' averaged references over their Monte Carlo noise (1 = agreement).
2. Cost: CPU time of one render per configuration (every suite point set under shift and
   scramble at --time-spp, every Cycles sampling pattern at --cycles-spp), interleaved rounds,
   medians. Cycles' CPU time is this process's (user + sys, all threads) over the render call.
3. Equal time: each suite configuration at the largest spp its measured cost per sample
   affords in Cycles' median CPU time at --cycles-spp (largest cube for stratified), against
   every Cycles pattern at --cycles-spp; RMSE against the average of the four references,
   mean over seeds.
"""

import argparse
import json
import math
import os
import platform
import statistics
import sys
from pathlib import Path

import numpy as np

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
# The matched scene's camera, light and albedos are the static comparison's (peers.py); the
# suite's side is timed and rendered as in scramble.py.
from peers import EYE, FOV, GROUND, SIZE, SPHERE, TARGET, TOWARDS, cpu, field, rmse  # noqa: E402
from scramble import POINT_SETS, RANDOMIZATIONS, affordable, ours, report_best, time_spp  # noqa: E402

SHUTTER = 0.1  # scene seconds; frame 0's shutter is [-SHUTTER/2, SHUTTER/2]
TRAVEL = 1.0  # units along x during the shutter
CYCLES_T0, CYCLES_T1 = 0.5 / 256, 254.5 / 256  # the part of the shutter Cycles samples (fitted)


def suite_scene(path):
    scene = {
        "format": "blurlab-scene/1",
        "description": "bench/peers: a diffuse sphere moving over a ground plane, one directional light",
        "materials": [
            {"name": "sphere", "diffuse": [SPHERE] * 3},
            {"name": "ground", "diffuse": [GROUND] * 3},
        ],
        "objects": [
            {"name": "ball", "type": "sphere", "radius": 1, "material": "sphere",
             "location": [0, 1, 0], "velocity": [TRAVEL / SHUTTER, 0, 0]},
            {"name": "floor", "type": "plane", "material": "ground", "half_extent": [20, 20]},
        ],
        "lights": [{"type": "directional", "direction": list(-TOWARDS), "intensity": 1.0}],
        "camera": {"location": EYE, "look_at": TARGET, "fov": FOV},
        "settings": {
            "start_time": -SHUTTER / 2, "frame_time": SHUTTER, "frames": 1, "width": SIZE,
            "height": SIZE, "max_depth": 0,
            "sampling": {"point_set": "sobol", "spp": 16, "time_filter": "box",
                         "spatial_filter": "box"},
        },
    }
    path.write_text(json.dumps(scene, indent=1))


# ---------------------------------------------------------------- Cycles

# The suite is y-up, Blender z-up: (x, y, z) -> (x, -z, y).
def b(v):
    return Vector((v[0], -v[2], v[1]))


class Cycles:
    def __init__(self, work, compensate=True):
        self.work = work
        bpy.ops.wm.read_factory_settings(use_empty=True)
        sc = bpy.context.scene
        self.sc = sc
        sc.render.engine = "CYCLES"
        cy = sc.cycles
        cy.device = "CPU"
        sc.render.threads_mode = "FIXED"
        sc.render.threads = 1
        sc.render.resolution_x = sc.render.resolution_y = SIZE
        sc.render.resolution_percentage = 100
        sc.render.pixel_aspect_x = sc.render.pixel_aspect_y = 1
        sc.render.use_persistent_data = False
        cy.use_denoising = False
        cy.use_adaptive_sampling = False
        cy.max_bounces = 0
        cy.diffuse_bounces = cy.glossy_bounces = cy.transmission_bounces = 0
        cy.volume_bounces = cy.transparent_max_bounces = 0
        cy.caustics_reflective = cy.caustics_refractive = False
        cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
        cy.light_sampling_threshold = 0.0
        cy.direct_light_sampling_type = "NEXT_EVENT_ESTIMATION"
        cy.pixel_filter_type = "BOX"
        cy.filter_width = 1.0
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

        world = bpy.data.worlds.new("black")
        world.use_nodes = True
        world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
        sc.world = world

        def diffuse(name, rho):
            m = bpy.data.materials.new(name)
            m.use_nodes = True
            bsdf = m.node_tree.nodes.new("ShaderNodeBsdfDiffuse")
            bsdf.inputs["Color"].default_value = (rho, rho, rho, 1.0)
            bsdf.inputs["Roughness"].default_value = 0.0
            out = m.node_tree.nodes["Material Output"]
            m.node_tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
            return m

        # Camera.
        cam = bpy.data.cameras.new("cam")
        cam.sensor_fit = "AUTO"
        cam.angle = math.radians(FOV)
        cam.clip_start, cam.clip_end = 1e-3, 1e4
        co = bpy.data.objects.new("cam", cam)
        sc.collection.objects.link(co)
        eye, target = b(EYE), b(TARGET)
        fwd = (target - eye).normalized()
        right = fwd.cross(Vector((0, 0, 1))).normalized()
        up = right.cross(fwd)
        m = Matrix.Identity(4)
        for i in range(3):
            m[i][0], m[i][1], m[i][2], m[i][3] = right[i], up[i], -fwd[i], eye[i]
        co.matrix_world = m
        sc.camera = co

        # Ground: a 40 x 40 plane at z = 0.
        mesh = bpy.data.meshes.new("floor")
        h = 20.0
        mesh.from_pydata([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [], [(0, 1, 2, 3)])
        mesh.materials.append(diffuse("ground", GROUND))
        fo = bpy.data.objects.new("floor", mesh)
        sc.collection.objects.link(fo)

        # Sphere: a one-point point cloud, radius 1, moving along x.
        pc = bpy.data.pointclouds.new("ball")
        pc.resize(1)
        pc.points[0].co = (0.0, 0.0, 0.0)
        pc.points[0].radius = 1.0
        pc.materials.append(diffuse("sphere", SPHERE))
        bo = bpy.data.objects.new("ball", pc)
        sc.collection.objects.link(bo)
        # Render frame 10, shutter 1 frame centred on it: open at 9.5, close at 10.5.
        sc.frame_start = sc.frame_end = 10
        sc.render.fps = 10
        # Cycles' box shutter was measured to sample the shutter's times over about
        # [T0, T1] = [0.5/256, 254.5/256] of it, not [0, 1] (a 256-entry shutter table, see
        # docs/benchmarks/scramble.md: uncompensated, its blur is about 0.8% shorter and
        # 0.2% early). With `compensate`, the keyframes put the sphere at -TRAVEL/2 at T0 and
        # +TRAVEL/2 at T1, so that the times Cycles samples see the suite's motion.
        t0, t1 = (CYCLES_T0, CYCLES_T1) if compensate else (0.0, 1.0)
        speed = TRAVEL / (t1 - t0)
        for frame, x in [(9.5, -TRAVEL / 2 - t0 * speed), (10.5, -TRAVEL / 2 + (1 - t0) * speed)]:
            bo.location = (x, 0.0, 1.0)
            bo.keyframe_insert("location", frame=frame)
        self._linear(bo)
        sc.frame_set(10)
        sc.render.use_motion_blur = True
        sc.render.motion_blur_shutter = 1.0
        sc.render.motion_blur_position = "CENTER"
        curve = sc.render.motion_blur_shutter_curve
        for p in curve.curves[0].points:
            p.location[1] = 1.0
        curve.update()
        if hasattr(bo, "cycles"):
            bo.cycles.use_motion_blur = True

        # Sun: light travels along -TOWARDS; its local -z is the direction of travel.
        sun = bpy.data.lights.new("sun", "SUN")
        sun.energy = math.pi  # irradiance, W/m^2: the suite's E = 1 in Cycles' units
        sun.angle = 0.0
        so = bpy.data.objects.new("sun", sun)
        so.rotation_mode = "QUATERNION"
        so.rotation_quaternion = b(TOWARDS).to_track_quat("Z", "Y")
        sc.collection.objects.link(so)

    @staticmethod
    def _linear(obj):
        """Linear interpolation for every keyframe, whatever the action API."""
        act = obj.animation_data.action
        curves = []
        if hasattr(act, "fcurves"):
            curves = list(act.fcurves)
        else:  # layered actions (Blender 4.4+)
            for layer in act.layers:
                for strip in layer.strips:
                    for bag in strip.channelbags:
                        curves += list(bag.fcurves)
        for fc in curves:
            for kp in fc.keyframe_points:
                kp.interpolation = "LINEAR"
            fc.extrapolation = "LINEAR"

    def patterns(self):
        found = []
        for p in ["AUTOMATIC", "TABULATED_SOBOL", "SOBOL_BURLEY", "BLUE_NOISE", "BLUE_NOISE_FIRST",
                  "BLUE_NOISE_ROUND"]:
            try:
                self.sc.cycles.sampling_pattern = p
                if self.sc.cycles.sampling_pattern == p:
                    found.append(p)
            except TypeError:
                pass
        return found

    def render(self, pattern, spp, seed=0):
        """(CPU seconds of the render call, linear RGB image, rows top to bottom)."""
        cy = self.sc.cycles
        cy.sampling_pattern = pattern
        cy.samples = spp
        cy.seed = seed
        path = str(self.work / "cycles.exr")
        self.sc.render.filepath = path
        t = cpu()
        bpy.ops.render.render(write_still=True)
        dt = cpu() - t
        img = bpy.data.images.load(path, check_existing=False)
        px = np.array(img.pixels[:], dtype=np.float64).reshape(SIZE, SIZE, 4)[::-1, :, :3]
        bpy.data.images.remove(img)
        return dt, px


# ---------------------------------------------------------------- the suite


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--bin", type=Path, required=True)
    p.add_argument("--cache", type=Path, required=True)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--ref-spp", type=int, default=256)
    p.add_argument("--time-spp", type=int, default=16)
    p.add_argument("--cycles-spp", type=int, default=16)
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--point-sets", default=",".join(POINT_SETS))
    p.add_argument("--agreement-only", action="store_true")
    p.add_argument("--save-refs", action="store_true")
    p.add_argument("--no-compensation", action="store_true",
                   help="keyframe the sphere over the whole shutter (Cycles' blur ~0.8%% short)")
    args = p.parse_args()
    point_sets = args.point_sets.split(",")
    work = args.cache / "cycles"
    work.mkdir(parents=True, exist_ok=True)
    scene = work / "moving.json"
    suite_scene(scene)
    raw = work / "img.f32"
    report = {"machine": f"{platform.machine()}, {os.cpu_count()} CPUs, load average "
                         + " ".join(f"{x:.1f}" for x in os.getloadavg()),
              "bpy": bpy.app.version_string, "rounds": args.rounds}
    cyc = Cycles(work, compensate=not args.no_compensation)
    report["cycles_shutter_compensation"] = not args.no_compensation
    patterns = cyc.patterns()
    report["cycles_patterns"] = patterns

    # 1. Agreement.
    refs_o = [ours(args, scene, args.ref_spp, "sobol", "scramble", 100 + k, raw)[1]
              for k in range(2)]
    refs_c = [cyc.render(patterns[0], args.ref_spp, 100 + k)[1] for k in range(2)]
    noise_o = np.mean((refs_o[0] - refs_o[1]) ** 2) / 2
    noise_c = np.mean((refs_c[0] - refs_c[1]) ** 2) / 2
    ref_o, ref_c = (refs_o[0] + refs_o[1]) / 2, (refs_c[0] + refs_c[1]) / 2
    report["agreement_mse_over_noise"] = float(np.mean((ref_o - ref_c) ** 2)
                                               / ((noise_o + noise_c) / 2))
    report["mean_ratio_suite_over_cycles"] = float(ref_o.mean() / ref_c.mean())
    # Where they differ: the sphere's blurred region against the rest.
    diff = (ref_o - ref_c).mean(axis=2)
    report["max_abs_pixel_difference"] = float(np.abs(diff).max())
    if args.save_refs:
        np.save(work / "ref_suite.npy", ref_o)
        np.save(work / "ref_cycles.npy", ref_c)
    print(json.dumps(report, indent=2), file=sys.stderr)
    if args.agreement_only:
        print("\n" + json.dumps(report, indent=2), flush=True)  # on its own lines: see scramble.sh
        return
    reference = (ref_o + ref_c) / 2

    # 2. Cost, interleaved.
    configs = [(ps, r) for ps in point_sets for r in RANDOMIZATIONS]
    t_o = {c: [] for c in configs}
    t_c = {pat: [] for pat in patterns}
    for pat in patterns:  # a first render per pattern before timing
        cyc.render(pat, args.cycles_spp, 1)
    for rnd in range(args.rounds):
        for c in configs:
            t_o[c].append(ours(args, scene, time_spp(c[0], args), c[0], c[1], 1 + rnd)[0])
        for pat in patterns:
            t_c[pat].append(cyc.render(pat, args.cycles_spp, 1 + rnd)[0])
    samples_c = SIZE * SIZE * args.cycles_spp
    ns = {c: statistics.median(t_o[c]) / (SIZE * SIZE * time_spp(c[0], args)) * 1e9
          for c in configs}
    budget = {pat: statistics.median(t_c[pat]) for pat in patterns}
    report["suite_ns_per_sample"] = {f"{c[0]} {c[1]}": ns[c] for c in configs}
    report["cycles_ns_per_sample"] = {pat: budget[pat] / samples_c * 1e9 for pat in patterns}
    report["cycles_cpu_s"] = budget
    # The budget: the cheapest pattern's median CPU time at --cycles-spp (patterns cost alike).
    t_budget = min(budget.values())
    report["budget_cpu_s"] = t_budget

    # 3. Equal-time RMSE.
    seeds = range(args.seeds)
    table = {}
    for pat in patterns:
        table["cycles " + pat] = {
            "spp": args.cycles_spp,
            "rmse": statistics.mean(rmse(cyc.render(pat, args.cycles_spp, 7 + s)[1], reference)
                                    for s in seeds)}
    for c in configs:
        spp = affordable(c[0], t_budget, ns[c])
        errs, times = [], []
        for s in seeds:
            t, img = ours(args, scene, spp, c[0], c[1], 7 + s, raw)
            errs.append(rmse(img, reference))
            times.append(t)
        table[f"suite {c[0]} {c[1]}"] = {"spp": spp, "rmse": statistics.mean(errs),
                                         "cpu_s_over_budget": statistics.median(times) / t_budget}
    report["equal_time"] = table
    report_best(report, table, "cycles")
    report["load_average_after"] = " ".join(f"{x:.1f}" for x in os.getloadavg())
    print("\n" + json.dumps(report, indent=2), flush=True)  # on its own lines: see scramble.sh


if __name__ == "__main__":
    main()
