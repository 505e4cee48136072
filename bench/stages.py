#!/usr/bin/env python3
"""Split a callgrind profile of `blurlab` into the render's stages (docs/benchmarks/profile.md).

    valgrind --tool=callgrind --dump-instr=yes --cache-sim=yes --LL=8388608,16,64 \\
        --callgrind-out-file=OUT blurlab render scene SCENE --spp 4 --frames 93 --exr --out DIR
    python3 bench/stages.py OUT BLURLAB SAMPLES [TOP]

Each instruction of the binary is given to the innermost frame of its inline chain
(`addr2line -i`) that lies in the renderer's own source, not counting the lane types' operations
(`simd/`) and the lane math's building blocks (`math/vcl.rs`), and that file (or the function)
names its stage; instructions of other objects (libm's powf, libc's memcpy) go to the instruction
that called them. Prints, per stage, instructions and simulated D1 / LL read misses, in
total and per camera sample (SAMPLES: pixels x spp), and with TOP the TOP costliest source
lines (file:line, function) of each stage.
"""
import collections
import re
import subprocess
import sys

STAGES = [
    # (stage, patterns on "file:line:function" of the innermost renderer frame, its file relative
    # to renderer/src; other crates' code is named by its whole inline chain of absolute paths)
    ("files (PNG, EXR)", [r"^frame_io/", r"exr_bytes", r"png_bytes", r"^render/pipeline", r"/exr-", r"/png-", r"fdeflate", r"crc32", r"adler"]),
    ("film and filter", [r"^film\.rs", r"^render/mod\.rs"]),
    ("sky lookup", [r"^environment/lanes", r"^environment\.rs:.*(radiance|bilinear)", r"^environment/texels\.rs:.*(gather|get|decode)", r"^math/inverse_trig"]),
    ("scene load (once)", [r"^scene/", r"^environment", r"^geometry/obj", r"^geometry/mesh\.rs:.*new", r"assets", r"^bvh/wide", r"^procedural", r"/image-", r"/obvhs-", r"/tobj-", r"serde", r"bufreader"]),
    ("traversal", [r"^accel/", r"^bvh/", r"^geometry/"]),
    ("shading", [r"^shading/", r"^light\.rs", r"^material\.rs", r"^math/pow"]),
    ("camera and sampling", [r"^render/", r"^sampling/", r"^camera\.rs", r"^math/", r"^shared/hash"]),
]


HELPERS = r"renderer/src/(simd/|math/vcl\.rs)"


def stage_of(where):
    for name, patterns in STAGES:
        if any(re.search(p, where) for p in patterns):
            return name
    return "other (runtime, std, rayon)"


own_cost = {}
calls_cost = {}


def parse(path):
    """Exclusive costs per (object, address), and per calling (object, address) the inclusive
    costs of calls into another object. Returns the event names."""
    events, ob, call_ob, in_call, last = None, None, None, False, 0
    names = {}
    for raw in open(path):
        line = raw.rstrip("\n")
        if line.startswith("events:"):
            events = line.split()[1:]
            continue
        m = re.match(r"(c?ob)=\((\d+)\)(?: (.*))?$", line)
        if m:
            if m.group(3):
                names[m.group(2)] = m.group(3)
            if m.group(1) == "ob":
                ob = names[m.group(2)]
            else:
                call_ob = names[m.group(2)]
            continue
        if line.startswith("calls="):
            in_call = True
            continue
        if not line or not (line[0] in "+-*" or line.startswith("0x")):
            continue
        parts = line.split()
        a = parts[0]
        last = int(a, 16) if a.startswith("0x") else last if a == "*" else last + int(a)
        costs = [int(c) for c in parts[2:]]
        costs += [0] * (len(events) - len(costs))
        if in_call:
            target = call_ob or ob
            if target != ob:
                add(calls_cost, (ob, last), costs)
            in_call, call_ob = False, None
        else:
            add(own_cost, (ob, last), costs)
    return events


def add(table, key, costs):
    prev = table.get(key)
    table[key] = costs if prev is None else [x + y for x, y in zip(prev, costs)]


def main():
    out, binary, samples = sys.argv[1], sys.argv[2], float(sys.argv[3])
    top = int(sys.argv[4]) if len(sys.argv) > 4 else 0
    events = parse(out)
    mine = lambda ob: ob is not None and ob.endswith("/" + binary.split("/")[-1])
    totals = collections.defaultdict(lambda: [0] * len(events))
    spots = collections.defaultdict(collections.Counter)
    addrs = sorted({a for (ob, a) in list(own_cost) + list(calls_cost) if mine(ob)})
    where = resolve(binary, addrs)
    for source in (own_cost, calls_cost):
        for (ob, a), c in source.items():
            if not mine(ob):
                continue
            w = where.get(a, "")
            s = stage_of(w)
            totals[s] = [x + y for x, y in zip(totals[s], c)]
            spots[s][re.sub(r"\[.*|<.*", "", w)[:110]] += c[0]
    show = ["Ir", "D1mr", "DLmr"]
    idx = [events.index(e) for e in show]
    grand = [sum(t[i] for t in totals.values()) for i in range(len(events))]
    print(f"{'stage':30} " + " ".join(f"{e:>14} {e + '/sample':>12}" for e in show) + "   share of Ir")
    for s, t in sorted(totals.items(), key=lambda kv: -kv[1][0]):
        print(f"{s:30} " + " ".join(f"{t[i]:>14,} {t[i] / samples:>12.2f}" for i in idx) + f"   {t[0] / grand[0]:.1%}")
    print(f"{'total':30} " + " ".join(f"{grand[i]:>14,} {grand[i] / samples:>12.2f}" for i in idx))
    for s, t in sorted(totals.items(), key=lambda kv: -kv[1][0]):
        if top:
            print(f"\n{s}:")
            for w, ir in spots[s].most_common(top):
                print(f"  {ir / samples:9.2f} Ir/sample  {w}")


def resolve(binary, addrs):
    """Address -> "file:function" of the innermost inline frame in renderer/src."""
    proc = subprocess.run(
        ["addr2line", "-f", "-i", "-C", "-e", binary],
        input="\n".join(f"{a:x}\n0" for a in addrs) + "\n",
        capture_output=True,
        text=True,
        check=True,
    )
    result = {}
    blocks = proc.stdout.split("??\n??:0\n")
    for a, block in zip(addrs, blocks):
        lines = block.strip("\n").split("\n")
        frames = list(zip(lines[0::2], lines[1::2]))
        own = [f for f in frames if "renderer/src/" in f[1]]
        # The lane type's operations and the lane math's building blocks go to their caller.
        pick = next((f for f in own if not re.search(HELPERS, f[1])), own[0] if own else None)
        if pick is None:
            # Another crate's function: named by its whole chain ("exr-1.74.2/...").
            result[a] = " ".join(f"{loc}:{fn}" for fn, loc in frames)
        else:
            fn, loc = pick
            result[a] = re.sub(r".*renderer/src/", "", loc) + ":" + fn
    return result


if __name__ == "__main__":
    main()
