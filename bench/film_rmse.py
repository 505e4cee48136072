#!/usr/bin/env python3
"""RMSE between two linear films written by `sample_cost --out` (little-endian f32, row-major
RGB), the share of pixels that differ at all, and the largest difference.

    python3 bench/film_rmse.py A.f32 B.f32
"""
import array
import math
import sys


def read(path):
    a = array.array("f")
    with open(path, "rb") as f:
        a.frombytes(f.read())
    if sys.byteorder != "little":
        a.byteswap()
    return a


def main():
    a, b = read(sys.argv[1]), read(sys.argv[2])
    if len(a) != len(b) or len(a) % 3:
        sys.exit(f"films differ in size: {len(a)} and {len(b)} floats")
    sq, differ, largest = 0.0, 0, 0.0
    for i in range(0, len(a), 3):
        d = [a[i + k] - b[i + k] for k in range(3)]
        if a[i] != b[i] or a[i + 1] != b[i + 1] or a[i + 2] != b[i + 2]:
            differ += 1
        sq += d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
        largest = max(largest, abs(d[0]), abs(d[1]), abs(d[2]))
    pixels = len(a) // 3
    mean = sum(a) / len(a)
    print(f"rmse {math.sqrt(sq / len(a)):.6g} mean_a {mean:.6g} pixels {pixels} "
          f"differ {differ} ({100 * differ / pixels:.3f}%) largest {largest:.6g}")


main()
