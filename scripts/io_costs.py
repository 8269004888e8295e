#!/usr/bin/env python3
"""Measures the time and peak memory of reading and writing BVH with the dqkit tool as functions of
joints, frames and depth (docs/reliability.md, "Measured costs"). Usage:
    scripts/io_costs.py path/to/dqkit [scale]
Each file is generated (3 rotation channels per joint, the root also 3 positions); each command runs
in its own process and its peak resident memory comes from wait4. "read" is `dqkit info` (the reader,
the skeleton and the whole animation in memory); "convert" reads, changes the rotation order and
writes BVH; "fk csv" reads, computes world transforms of every joint in every frame and streams CSV."""
import os, subprocess, sys, tempfile, time

tool = sys.argv[1]
scale = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0


def capture(path, joints, frames, chain):
    """chain: every joint the child of the previous (depth = joints); else all children of the root."""
    with open(path, "w") as f:
        f.write("HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n")
        for j in range(1, joints):
            f.write(f"JOINT j{j}\n{{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n")
            if not chain:
                f.write("}\n")
        f.write("}\n" * (joints if chain else 1))
        f.write(f"MOTION\nFrames: {frames}\nFrame Time: 0.01\n")
        values = [f"{(k * 7919 % 3600) / 10 - 180:.2f}" for k in range(3 * joints + 3)]
        line = " ".join(values) + "\n"
        for _ in range(frames):
            f.write(line)


def run(args):
    start = time.perf_counter()
    p = subprocess.Popen([tool] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    elapsed = time.perf_counter() - start
    if status != 0:
        sys.exit(f"{args}: failed: {p.stderr.read().decode()}")
    return elapsed, usage.ru_maxrss / 1024  # s, MB


def sweep(title, cases, chain):
    print(f"\n{title}")
    print("| joints | depth | frames | file MB | read s | read MB | convert s | convert MB | fk csv s | fk csv MB | csv MB |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    with tempfile.TemporaryDirectory() as d:
        for joints, frames in cases:
            src, out, csv = os.path.join(d, "in.bvh"), os.path.join(d, "out.bvh"), os.path.join(d, "out.csv")
            capture(src, joints, frames, chain)
            r = run(["info", src])
            c = run(["convert", src, out, "--rotation-order", "XYZ", "--force"])
            k = run(["fk", src, "--all", "-o", csv, "--force"])
            depth = joints if chain else 2
            print(f"| {joints} | {depth} | {frames} | {os.path.getsize(src) / 1e6:.1f} | {r[0]:.2f} | {r[1]:.0f} | {c[0]:.2f} | {c[1]:.0f} "
                  f"| {k[0]:.2f} | {k[1]:.0f} | {os.path.getsize(csv) / 1e6:.0f} |")


s = lambda n: max(1, int(n * scale))
sweep("Joints (flat: every joint a child of the root), 200 frames", [(s(j), 200) for j in (2500, 5000, 10000, 20000)], chain=False)
sweep("Frames, 50 joints", [(50, s(f)) for f in (10000, 20000, 40000, 80000)], chain=False)
sweep("Depth (a chain: depth = joints), 20 frames", [(s(j), 20) for j in (8000, 16000, 32000, 64000)], chain=True)
