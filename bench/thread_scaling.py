#!/usr/bin/env python3
"""Summarise bench/thread_scaling.sh's runs: per scene and build, the median over rounds of
wall(1 thread) / wall(2 threads), the medians of both walls, and how busy the two cores were in
the 2-thread runs ((user + sys) / (2 x wall)).

    python3 bench/thread_scaling.py runs.txt [more.txt ...]
"""
import statistics
import sys
from collections import defaultdict


def main(paths):
    runs = defaultdict(list)
    for path in paths:
        with open(path) as f:
            for line in f:
                fields = line.split()
                if len(fields) != 6:
                    continue
                scene, build, threads, wall, user, sys_s = fields
                runs[(scene, build, threads)].append((float(wall), float(user) + float(sys_s)))
    for scene, build in sorted({(s, b) for s, b, _ in runs}):
        one, two = runs[(scene, build, "1")], runs[(scene, build, "2")]
        pairs = [a[0] / b[0] for a, b in zip(one, two)]
        busy = [cpu / (2 * wall) for wall, cpu in two]
        print(
            f"{scene} {build}: rounds {len(pairs)}, scaling median {statistics.median(pairs):.3f} "
            f"(range {min(pairs):.2f}-{max(pairs):.2f}, {sum(p >= 1.85 for p in pairs)} >= 1.85), "
            f"wall 1 / 2 threads {statistics.median(w for w, _ in one):.3f} / "
            f"{statistics.median(w for w, _ in two):.3f} s, 2-thread cores busy "
            f"{statistics.median(busy):.3f}"
        )


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
