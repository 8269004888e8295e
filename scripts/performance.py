#!/usr/bin/python3
"""Runs the benchmark suite and regenerates docs/performance.md and docs/performance.png.

    /usr/bin/python3 scripts/performance.py [BUILD_DIR]      (default build/release, configured)
    /usr/bin/python3 scripts/performance.py --from-json      (the page and plot again from docs/performance.json)
    /usr/bin/python3 scripts/performance.py --only KEY [BUILD_DIR]   (one binary again: bench_batch, bench_core,
                                                     bench_core_avx2, bench_skin or bench_ik; the others' results kept)

It builds bench_batch, bench_core, bench_skin and bench_ik in BUILD_DIR first, and bench_core with
-mavx2 -mfma in build/bench-avx2.

Each benchmark binary runs once, with 3 repetitions; the page shows medians, and every ratio is
taken between two cases of the same run (these machines are shared and noisy). The raw results are
kept in docs/performance.json. The page says which CPU, which dispatch target, and the command.
"""
import json
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ARGS = ["--benchmark_repetitions=3", "--benchmark_report_aggregates_only=true", "--benchmark_format=json"]


def quiet(command):
    """Runs a command with its output kept back unless it fails; then prints it and stops."""
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"performance.py: {' '.join(command)} failed:\n{done.stdout}{done.stderr}")
    return done.stdout


def run(build, name, extra=()):
    return json.loads(quiet([os.path.join(build, "bench", name)] + ARGS + list(extra)))


def medians(result):
    return {b["run_name"]: b for b in result["benchmarks"] if b.get("aggregate_name") == "median"}


def fmt(x, unit=""):
    x = float(f"{x:.3g}")  # rounded first, so that 999.6 M is 1 G rather than 1e+03 M
    for scale, suffix in ((1e9, " G"), (1e6, " M"), (1e3, " k")):
        if abs(x) >= scale:
            return f"{x / scale:.3g}{suffix}{unit}"
    return f"{x:.3g} {unit}".rstrip()


def ns(cases, name):
    return cases[name]["real_time"] * {"ns": 1, "us": 1e3, "ms": 1e6, "s": 1e9}[cases[name]["time_unit"]]


# One-at-a-time cases: dqkit's first, then its peers; each row's ratio is its time over the
# fastest peer's (not dqkit's own) in the same run.
ONE_AT_A_TIME = (
    ("compose, throughput (out[i] = a[i] * b[i])", ["ComposeDualQuaternion<float>"],
     ["ComposeGlmDualquat<float>", "ComposeGlmMat4<float>", "ComposeEigenMatrix4<float>", "ComposeEigenIsometry<float>"]),
    ("compose, latency chain (x = x * a[i])", ["ChainDualQuaternion"],
     ["ChainGlmDualquat", "ChainGlmMat4", "ChainEigenMatrix4", "ChainEigenMatrix4TwoBuffers"]),
    ("compose, latency chain prepending (x = a[i] * x)", ["PrependChainDualQuaternion"],
     ["PrependChainGlmDualquat", "PrependChainGlmMat4", "PrependChainEigenMatrix4", "PrependChainEigenMatrix4TwoBuffers"]),
    ("compose in double, throughput", ["ComposeDualQuaternion<double>"], ["ComposeGlmMat4<double>", "ComposeEigenIsometry<double>"]),
    ("transform a point", ["PointDualQuaternion", "PointMat34"], ["PointEigenIsometry", "PointGlmMat4", "PointGlmDualquat"]),
    ("slerp", ["SlerpDqkit"], ["SlerpEigen", "SlerpGlm"]),
)


def one_at_a_time(add, c, build):
    add("")
    add(f"### One at a time, {build} (bench_core, 1024 operations per case)")
    add("| operation | case | median per 1024 | × the fastest peer's time |")
    add("| --- | --- | ---: | ---: |")
    for operation, ours, peers in ONE_AT_A_TIME:
        best = min(ns(c, name) for name in peers)
        for name in ours + peers:
            add(f"| {operation} | {name} | {ns(c, name):.0f} ns | {ns(c, name) / best:.2f} |")


def build_avx2():
    """bench_core built with -mavx2 -mfma (the one-at-a-time types must stay fast there too)."""
    build = os.path.join(ROOT, "build", "bench-avx2")
    quiet(["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_CXX_FLAGS=-mavx2 -mfma", "-DDQKIT_BUILD_TESTS=OFF",
           "-DDQKIT_BUILD_PYTHON=OFF", "-DDQKIT_BUILD_DEMOS=OFF", "-DDQKIT_BUILD_TOOLS=OFF", "-DDQKIT_BUILD_EXAMPLES=OFF"])
    quiet(["cmake", "--build", build, "-j", str(os.cpu_count() or 2), "--target", "bench_core"])
    return build


SKINNING = (("dqkit LBS", "dqkit_skinning/lbs"), ("**dqkit DQS**", "dqkit_skinning/dqs"), ("dqkit CoR", "dqkit_skinning/cor"),
            ("GLM `mat4` LBS", "glm_lbs"), ("GLM `dualquat` DQS", "glm_dqs"), ("GLM `quat` CoR", "glm_cor"))

STREAMS = (("DQS's 80 bytes a vertex alone, the skin's 20 streams", "skin_streams/separate"),
           ("the same bytes in blocks of 16 vertices (AoSoA)", "skin_streams/interleaved"))


def skinning_tables(add, s, context):
    """bench_skin: each method's rate, its fraction of the triad of the same thread count, and the ratios
    the performance issue sets targets for."""
    add("")
    add(f"### Skinning, {int(context['vertices']):,} vertices × 4 influences, positions and normals (bench_skin)")
    add("The GLM peers are the plain per-vertex loops over arrays of structures, each checked once against "
        "dqkit's result outside the timing; bytes per vertex: 80, 92 for CoR (its centre); the triad is measured "
        "by bench_skin itself before the cases (the median of five passes after an untimed one), so it can differ "
        "from the Triad cases of the limits table above, which are timed separately (docs/skinning.md, "
        "\"The two-thread triad\")." + (
            " The one-thread table's last two rows move DQS's bytes with no arithmetic, prefetched as the kernels "
            "prefetch: what the memory allows a kernel with those streams (docs/skinning.md, \"The memory side\")."
            if any(f"{name}/real_time" in s for _, name in STREAMS) else ""))
    for threads in (1, 2):
        def case(name):
            return s[f"{name}/{threads}/real_time"]
        triad = float(context[f"triad_GBps_{threads}thread"]) * 1e9
        lbs_time, glm_lbs, glm_dqs = ns(s, f"dqkit_skinning/lbs/{threads}/real_time"), case("glm_lbs"), case("glm_dqs")
        add("")
        add(f"| {threads} thread{'s' if threads > 1 else ''} | time per frame | vertices/s | bytes/s | ÷ triad ({fmt(triad, 'B/s')}) | "
            "× GLM `mat4` LBS | × GLM `dualquat` DQS | time ÷ dqkit LBS |")
        add("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        for label, name in SKINNING:
            r, t = case(name), ns(s, f"{name}/{threads}/real_time")
            row = f"| {label} | {t / 1e6:.1f} ms | {fmt(r['vertices_per_s'])} |"
            if name.startswith("dqkit"):
                row += (f" {fmt(r['bytes_per_second'], 'B/s')} | {r['bytes_per_second'] / triad:.2f} | "
                        f"{r['vertices_per_s'] / glm_lbs['vertices_per_s']:.2f} | {r['vertices_per_s'] / glm_dqs['vertices_per_s']:.2f} | "
                        f"{t / lbs_time:.2f} |")
            else:
                row += " | | | | |"
            add(row)
        # The memory side alone (one thread): DQS's bytes with no arithmetic, the most its streams allow.
        if threads == 1:
            for label, name in STREAMS:
                if f"{name}/real_time" in s:
                    r = s[f"{name}/real_time"]
                    add(f"| {label} | {ns(s, f'{name}/real_time') / 1e6:.1f} ms | {fmt(r['vertices_per_s'])} | "
                        f"{fmt(r['bytes_per_second'], 'B/s')} | {r['bytes_per_second'] / triad:.2f} | | | |")
    on_target_table(add, s, "dqkit_skinning_on_target", "### Skinning with each instruction set forced (one thread, the same skin, vertices per second)",
                    "vertices_per_s", "/real_time")


IK = (("ArmDualQuaternionLM", "dqkit LM, dual quaternions, 7-DOF arm"), ("ArmMatrixLM", "dqkit LM, 4x4 matrices, arm"),
      ("ArmDualQuaternionNewtonHyperDual", "dqkit Newton (hyper-dual Hessian), arm"),
      ("ArmDualQuaternionGaussSeidel", "dqkit projected Gauss–Seidel, arm"),
      ("ArmKdlLMA", "KDL `ChainIkSolverPos_LMA`, arm"), ("ArmKdlNRJL", "KDL `ChainIkSolverPos_NR_JL`, arm"),
      ("BipedFourEffectors<IkSolver>", "dqkit LM, 36-DOF biped, four pose effectors, dual quaternions"),
      ("BipedFourEffectors<MatrixIkSolver>", "dqkit LM, biped, 4x4 matrices"))


def ik_case(k, prefix):
    """The case of bench_ik whose name starts with `prefix` and its argument ("ArmKdlLMA/iterations:2000")."""
    return next(r for name, r in k.items() if name.startswith(prefix + "/"))


def ik_table(add, k):
    """bench_ik: solves per second and success, dqkit's solvers against KDL's on the same targets (docs/ik.md)."""
    add("")
    add("### Inverse kinematics (bench_ik, random interleaving; success within 1e-9 m and rad and the limits, docs/ik.md)")
    add("| solver | solves/s | median µs per solve | iterations | success (1e-9) | × KDL LMA solves/s |")
    add("| --- | ---: | ---: | ---: | ---: | ---: |")
    lma = ik_case(k, "ArmKdlLMA")["solves_per_s"]
    for prefix, label in IK:
        r = ik_case(k, prefix)
        iterations = f"{r['iterations']:.1f}" if r["iterations"] > 0 else "—"  # KDL's NR_JL does not report them
        add(f"| {label} | {r['solves_per_s']:,.0f} | {r['median_us']:.1f} | {iterations} | "
            f"{100 * r['success_rate']:.1f} % | {r['solves_per_s'] / lma:.2f} |")


def on_target_table(add, cases, prefix, title, counter, suffix=""):
    """The cases prefix/ROW/TARGET+suffix (each kernel with each instruction set forced), where the run
    has them: a row per kernel, a column per target, and the widest target's rate over the scalar path's."""
    names = [name[len(prefix) + 1:len(name) - len(suffix)] for name in cases if name.startswith(prefix + "/") and name.endswith(suffix)]
    if not names:
        return
    rows = list(dict.fromkeys(name.split("/")[0] for name in names))
    targets = list(dict.fromkeys(name.split("/")[1] for name in names))
    add("")
    add(title)
    add("| | " + " | ".join(targets) + f" | {targets[-1]} ÷ {targets[0]} |")
    add("| --- |" + " ---: |" * (len(targets) + 1))
    for row in rows:
        if any(f"{prefix}/{row}/{target}{suffix}" not in cases for target in targets):
            continue  # a filtered run: not every target of this row
        rate = [cases[f"{prefix}/{row}/{target}{suffix}"][counter] for target in targets]
        add(f"| `{row}` | " + " | ".join(fmt(r) for r in rate) + f" | {rate[-1] / rate[0]:.2f} |")


def measure(build, key):
    """Runs one binary of the suite, brought up to date first (a binary older than the sources would be
    measured as if it were them); `key` is its entry in docs/performance.json."""
    if key == "bench_core_avx2":
        return run(build_avx2(), "bench_core")
    quiet(["cmake", "--build", build, "-j", str(os.cpu_count() or 2), "--target", key])
    return run(build, key, ["--benchmark_enable_random_interleaving=true"] if key == "bench_ik" else [])


def save(results):
    with open(os.path.join(ROOT, "docs", "performance.json"), "w") as f:
        json.dump(results, f, indent=1)
    return results


def run_suite(build):
    """Runs every benchmark binary and keeps the raw results in docs/performance.json. bench_skin
    (GLM) and bench_ik (KDL) are left out where the build has no such target."""
    targets = quiet(["cmake", "--build", build, "--target", "help"])
    optional = [name for name in ("bench_skin", "bench_ik") if name in targets.split()]
    return save({key: measure(build, key) for key in ("bench_batch", "bench_core", "bench_core_avx2", *optional)})


def rerun(build, key):
    """Runs one binary again and replaces its results in docs/performance.json; the others stay."""
    with open(os.path.join(ROOT, "docs", "performance.json")) as f:
        results = json.load(f)
    if key not in results:
        sys.exit(f"performance.py: --only takes one of {', '.join(results)}, not {key}")
    results[key] = measure(build, key)
    return save(results)


LLC_SOURCE = {"sysfs": "sysfs", "cpuid": "CPUID: this machine's sysfs has no cache entries; a virtual machine may be told the "
              "whole socket's cache, so the 4 × LLC arrays are then larger than they need be",
              "assumed": "nowhere: assumed"}


def main(results):
    batch, core, core_avx2, skin, ik = (results.get(k) for k in ("bench_batch", "bench_core", "bench_core_avx2", "bench_skin", "bench_ik"))
    b, c, c_avx2 = medians(batch), medians(core), medians(core_avx2)
    s, k = (medians(r) if r else None for r in (skin, ik))
    ctx = batch["context"]
    copy1 = b["Copy/1/real_time"]["bytes_per_second"]

    lines = []
    add = lines.append
    add(f"Machine: {ctx['cpu_model']}, {ctx['num_cpus']} cores, last-level cache {ctx['llc_MB']} MB (read from {LLC_SOURCE.get(ctx.get('llc_source'), 'sysfs')}); widest dispatch "
        f"target: {ctx['simd_target']}; GCC 12, Release, portable flags (no `-march`). Command: "
        "`/usr/bin/python3 scripts/performance.py` (runs `bench_batch`, `bench_core`, `bench_skin` and `bench_ik` with 3 "
        "repetitions, medians, and `bench_core` again built with `-mavx2 -mfma` in build/bench-avx2; raw results in "
        "`docs/performance.json`). Each binary's run began (UTC): " +
        ", ".join(f"{key} {r['context']['date'][:16].replace('T', ' ')}" for key, r in results.items()) + ".")
    add("")
    add("### The machine's limits (same run)")
    add("| measure | 1 thread | 2 threads |")
    add("| --- | ---: | ---: |")
    for case in ("Copy", "Triad"):
        add(f"| {case.lower()} bandwidth, arrays of 4 × LLC | {fmt(b[case + '/1/real_time']['bytes_per_second'], 'B/s')} | "
            f"{fmt(b[case + '/2/real_time']['bytes_per_second'], 'B/s')} |")
    add(f"| peak AVX2 FMA | {fmt(b['PeakFma']['flops'], 'FLOP/s')} | |")
    add("")
    add("### Forward kinematics, 64-joint skeletons (float)")
    add("| case | joints/s | bytes/s | × Eigen `Isometry3f` pose by pose | × Eigen `Matrix4f` pose by pose | fraction of the 1-thread copy roofline |")
    add("| --- | ---: | ---: | ---: | ---: | ---: |")
    eigen = b["FkEigenPerPose/10000/real_time"]["joints_per_s"]
    eigen4 = b["FkEigenMatrix4fPerPose/10000/real_time"]["joints_per_s"]
    for name, label in (
        ("FkBlocksDispatched/10000/1/real_time", "10,000 skeletons, dqkit pose blocks, dispatched, 1 thread"),
        ("FkBlocksDispatched/10000/2/real_time", "10,000 skeletons, dqkit pose blocks, dispatched, 2 threads"),
        ("FkBlocksStreaming/10000/1/real_time", "10,000 skeletons, dqkit pose blocks, streaming stores, 1 thread"),
        ("FkBlocksStreaming/10000/2/real_time", "10,000 skeletons, dqkit pose blocks, streaming stores, 2 threads"),
        ("FkDispatched/10000/1/real_time", "10,000 skeletons, dqkit joint-major, dispatched, 1 thread"),
        ("FkDispatched/10000/2/real_time", "10,000 skeletons, dqkit joint-major, dispatched, 2 threads"),
        ("FkScalarJob/10000/real_time", "10,000 skeletons, dqkit joint-major job, auto-vectorized"),
        ("FkEigenPerPose/10000/real_time", "10,000 skeletons, Eigen `Isometry3f` pose by pose"),
        ("FkEigenMatrix4fPerPose/10000/real_time", "10,000 skeletons, Eigen `Matrix4f` pose by pose (`noalias()`)"),
        ("FkBlocksDispatched/100000/1/real_time", "100,000 skeletons, dqkit pose blocks, dispatched, 1 thread"),
        ("FkBlocksDispatched/100000/2/real_time", "100,000 skeletons, dqkit pose blocks, dispatched, 2 threads"),
        ("FkBlocksStreaming/100000/1/real_time", "100,000 skeletons, dqkit pose blocks, streaming stores, 1 thread"),
        ("FkBlocksStreaming/100000/2/real_time", "100,000 skeletons, dqkit pose blocks, streaming stores, 2 threads"),
        ("FkDispatched/100000/1/real_time", "100,000 skeletons, dqkit joint-major, dispatched, 1 thread"),
        ("FkDispatched/100000/2/real_time", "100,000 skeletons, dqkit joint-major, dispatched, 2 threads"),
        ("FkScalarJob/100000/real_time", "100,000 skeletons, dqkit joint-major job, auto-vectorized"),
        ("FkFramesDispatched/1024/1/real_time", "1024 frames one after another (NumPy's (F, J, 8)), `local_to_model_frames`, 1 thread"),
        ("FkFramesPerFrame/1024/real_time", "1024 frames one after another, `dq::local_to_model` frame by frame"),
        ("FkFramesDispatched/100000/1/real_time", "100,000 frames one after another, `local_to_model_frames`, 1 thread"),
        ("FkFramesDispatched/100000/2/real_time", "100,000 frames one after another, `local_to_model_frames_parallel`, 2 threads"),
    ):
        if name not in b:
            continue  # a run of the suite before the case existed
        r = b[name]
        add(f"| {label} | {fmt(r['joints_per_s'])} | {fmt(r['bytes_per_second'], 'B/s')} | {r['joints_per_s'] / eigen:.2f} | "
            f"{r['joints_per_s'] / eigen4:.2f} | {r['bytes_per_second'] / copy1:.2f} |")
    one_dq, one_eigen = b["FkOneSkeletonDualQuaternion"]["joints_per_s"], b["FkOneSkeletonEigenIsometry3f"]["joints_per_s"]
    one_eigen4 = b["FkOneSkeletonEigenMatrix4f"]["joints_per_s"]
    for label, rate in (("dqkit `DualQuaternion<float>`", one_dq), ("Eigen `Isometry3f`", one_eigen), ("Eigen `Matrix4f`", one_eigen4)):
        add(f"| one skeleton at a time, {label} | {fmt(rate)} | | {rate / one_eigen:.2f} | {rate / one_eigen4:.2f} | |")
    if "FkFramesDoubleDispatched/1024/1/real_time" in b:  # runs of the suite since 2026-12-07
        add("")
        add("### Forward kinematics in double, frames one after another (64 joints; 128 bytes a joint, 64 read and 64 written)")
        add("| case | joints/s | bytes/s | × Eigen `Isometry3d` frame by frame | ÷ copy (1 thread) |")
        add("| --- | ---: | ---: | ---: | ---: |")
        eigen_d = b["FkFramesEigenIsometry3d/1024/real_time"]["joints_per_s"]
        for name, label in (
            ("FkFramesDoubleDispatched/1024/1/real_time", "1024 frames, `local_to_model_frames`, 1 thread"),
            ("FkFramesDoublePerFrame/1024/real_time", "1024 frames, `dq::local_to_model` frame by frame"),
            ("FkFramesEigenIsometry3d/1024/real_time", "1024 frames, Eigen `Isometry3d` frame by frame"),
            ("FkFramesDoubleDispatched/100000/1/real_time", "100,000 frames, `local_to_model_frames`, 1 thread"),
            ("FkFramesDoubleDispatched/100000/2/real_time", "100,000 frames, `local_to_model_frames_parallel`, 2 threads"),
        ):
            r = b[name]
            add(f"| {label} | {fmt(r['joints_per_s'])} | {fmt(r['bytes_per_second'], 'B/s')} | {r['joints_per_s'] / eigen_d:.2f} | "
                f"{r['bytes_per_second'] / copy1:.2f} |")
    add("")
    add("### Points and compositions (one transform per element; hot: 4096 elements, DRAM: arrays of 4 × LLC)")
    add("| case | hot, per second | DRAM, per second | × peer (hot / DRAM) |")
    add("| --- | ---: | ---: | ---: |")
    tp = (b["TransformPointsDispatched/0"]["points_per_s"], b["TransformPointsDispatched/1"]["points_per_s"])
    te = (b["TransformPointsEigenIsometry3f/0"]["points_per_s"], b["TransformPointsEigenIsometry3f/1"]["points_per_s"])
    add(f"| transform points, dqkit dispatched | {fmt(tp[0])} | {fmt(tp[1])} | {tp[0] / te[0]:.2f} / {tp[1] / te[1]:.2f} × Eigen |")
    add(f"| transform points, Eigen `Isometry3f` | {fmt(te[0])} | {fmt(te[1])} | 1.00 |")
    cd = (b["ComposeDispatched/0"]["per_s"], b["ComposeDispatched/1"]["per_s"])
    cg = (b["ComposeGlmDualquat/0"]["per_s"], b["ComposeGlmDualquat/1"]["per_s"])
    ce = (b["ComposeEigenIsometry3f/0"]["per_s"], b["ComposeEigenIsometry3f/1"]["per_s"])
    ce4 = (b["ComposeEigenMatrix4f/0"]["per_s"], b["ComposeEigenMatrix4f/1"]["per_s"])
    add(f"| compose, dqkit dispatched | {fmt(cd[0])} | {fmt(cd[1])} | {cd[0] / cg[0]:.2f} / {cd[1] / cg[1]:.2f} × GLM `dualquat` |")
    add(f"| compose, GLM `dualquat` | {fmt(cg[0])} | {fmt(cg[1])} | 1.00 |")
    add(f"| compose, Eigen `Isometry3f` | {fmt(ce[0])} | {fmt(ce[1])} | {ce[0] / cg[0]:.2f} / {ce[1] / cg[1]:.2f} |")
    add(f"| compose, Eigen `Matrix4f` (`noalias()`) | {fmt(ce4[0])} | {fmt(ce4[1])} | {ce4[0] / cg[0]:.2f} / {ce4[1] / cg[1]:.2f} |")
    sd, se = b["SlerpDispatched"]["per_s"], b["SlerpEigen"]["per_s"]
    add(f"| slerp over arrays, dqkit dispatched (no failure case) | {fmt(sd)} | | {sd / se:.2f} × Eigen per element |")
    add(f"| slerp, Eigen `Quaternionf::slerp` per element | {fmt(se)} | | 1.00 |")
    add("")
    add("### More kernels over arrays (4096 elements, hot in cache; t = 0.3)")
    add("| kernel | dqkit dispatched, per second | peer | peer, per second | dqkit ÷ peer |")
    add("| --- | ---: | --- | ---: | ---: |")
    for kernel, peers in (
        ("Inverse", (("InverseGlmDualquat", "GLM `inverse(dualquat)`"),)),
        ("TransformDirections", (("TransformDirectionsGlmMat4", "GLM `mat4 * vec4(v, 0)`"),
                                 ("TransformDirectionsEigenIsometry3f", "Eigen `Isometry3f::linear() * v`"))),
        ("ToMatrices", (("ToMatricesGlmDualquat", "GLM `mat3x4_cast(dualquat)`"),)),
        ("Normalize", (("NormalizeGlmDualquat", "GLM `normalize(dualquat)` (leaves q_r · q_d ≠ 0)"),)),
        ("Dlb", (("DlbGlmDualquat", "GLM `normalize(lerp(a, b, t))`"),)),
        ("Sclerp", (("SclerpScalar", "dqkit's scalar `dq::sclerp` per element (no peer has sclerp)"),)),
        ("ToRows", (("ToRowsLoop", "the loop users write, component by component"),)),
        ("FromRows", (("FromRowsLoop", "the loop users write, component by component"),)),
    ) + tuple((kernel + layout, peers) for layout in ("", "Records") for kernel, peers in (
        ("ComposeDouble", (("ComposeDoubleScalar", "dqkit's `DualQuaternion<double>` product per element"),
                           ("ComposeDoubleEigenIsometry3d", "Eigen `Isometry3d` per element"))),
        ("TransformPointsDouble", (("TransformPointsDoubleScalar", "dqkit's `DualQuaternion<double>::transform_point` per element"),
                                   ("TransformPointsDoubleEigenIsometry3d", "Eigen `Isometry3d * v` per element"))))):
        if kernel + "Dispatched" not in b:
            continue  # a run of the suite before the kernel existed
        mine = b[kernel + "Dispatched"]["per_s"]
        for peer, label in peers:
            theirs = b[peer]["per_s"]
            add(f"| `{kernel[0].lower() + ''.join('_' + ch.lower() if ch.isupper() else ch for ch in kernel[1:])}` | {fmt(mine)} | {label} | {fmt(theirs)} | {mine / theirs:.2f} |")
    if "RowsDram/0/real_time" in b:  # a run of the suite before the case existed has none
        add("")
        add("### The layout conversions over arrays of 4 × LLC (32 bytes read and 32 written per dual quaternion)")
        add("| conversion | per second | bytes/s | fraction of the 1-thread copy roofline |")
        add("| --- | ---: | ---: | ---: |")
        for arg, name in (("0", "`to_rows`"), ("1", "`from_rows`")):
            r = b[f"RowsDram/{arg}/real_time"]
            add(f"| {name}, dispatched | {fmt(r['per_s'])} | {fmt(r['bytes_per_second'], 'B/s')} | {r['bytes_per_second'] / copy1:.2f} |")
    on_target_table(add, b, "OnTarget", "### Each kernel on each instruction set (the target forced; 4096 elements hot in cache, per second)", "per_s")
    add("")
    one_at_a_time(add, c, "portable build")
    one_at_a_time(add, c_avx2, "built with `-mavx2 -mfma`")
    if s:
        skinning_tables(add, s, skin["context"])
    if k:
        ik_table(add, k)

    page = os.path.join(ROOT, "docs", "performance.md")
    text = open(page).read()
    begin, end = "<!-- generated by scripts/performance.py: begin -->", "<!-- generated by scripts/performance.py: end -->"
    new = begin + "\n" + "\n".join(lines) + "\n" + end
    if begin in text:
        text = text[: text.index(begin)] + new + text[text.index(end) + len(end):]
    else:
        text = text.rstrip() + "\n\n## The batch kernels and the suite against the peers\n" + new + "\n"
    open(page, "w").write(text)

    fig, ax = plt.subplots(1, 3, figsize=(19, 5.5), layout="constrained")
    names = ["10k ×64\n1 thread", "10k ×64\n2 threads", "100k ×64\n1 thread", "100k ×64\n2 threads"]
    cases = ["10000/1/real_time", "10000/2/real_time", "100000/1/real_time", "100000/2/real_time"]
    at = range(len(names))
    ax[0].bar([x - 0.27 for x in at], [b["FkBlocksStreaming/" + k]["bytes_per_second"] / copy1 for k in cases], 0.27,
              label="pose blocks, streaming stores")
    ax[0].bar(list(at), [b["FkBlocksDispatched/" + k]["bytes_per_second"] / copy1 for k in cases], 0.27, label="pose blocks")
    ax[0].bar([x + 0.27 for x in at], [b["FkDispatched/" + k]["bytes_per_second"] / copy1 for k in cases], 0.27, label="joint-major")
    ax[0].set_xticks(list(at), names)
    ax[0].set_ylim(0, 1.3 * ax[0].get_ylim()[1])  # room for the legend above the bars
    ax[0].legend(loc="upper right", fontsize="small")
    ax[0].axhline(1.0, color="grey", linestyle=":")
    ax[0].set_ylabel("fraction of the 1-thread copy bandwidth")
    ax[0].set_title("Batch forward kinematics against the memory roofline")
    ratios = {"FK 10k (pose blocks) vs Eigen Isometry3f": b["FkBlocksDispatched/10000/1/real_time"]["joints_per_s"] / eigen,
              "FK 10k (pose blocks) vs Eigen Matrix4f": b["FkBlocksDispatched/10000/1/real_time"]["joints_per_s"] / eigen4,
              "one skeleton vs Eigen Isometry3f": one_dq / one_eigen, "one skeleton vs Eigen Matrix4f": one_dq / one_eigen4,
              "points vs Eigen (hot)": tp[0] / te[0], "points vs Eigen (DRAM)": tp[1] / te[1],
              "compose vs GLM dq (hot)": cd[0] / cg[0], "slerp arrays vs Eigen": sd / se,
              "slerp one at a time vs Eigen": ns(c, "SlerpEigen") / ns(c, "SlerpDqkit"),
              "inverse vs GLM dq": b["InverseDispatched"]["per_s"] / b["InverseGlmDualquat"]["per_s"],
              "directions vs Eigen": b["TransformDirectionsDispatched"]["per_s"] / b["TransformDirectionsEigenIsometry3f"]["per_s"],
              "to 3x4 matrices vs GLM dq": b["ToMatricesDispatched"]["per_s"] / b["ToMatricesGlmDualquat"]["per_s"],
              "normalize vs GLM dq": b["NormalizeDispatched"]["per_s"] / b["NormalizeGlmDualquat"]["per_s"],
              "dlb vs GLM dq": b["DlbDispatched"]["per_s"] / b["DlbGlmDualquat"]["per_s"],
              "sclerp arrays vs scalar sclerp": b["SclerpDispatched"]["per_s"] / b["SclerpScalar"]["per_s"]}
    if s:
        dqs = s["dqkit_skinning/dqs/1/real_time"]["vertices_per_s"]
        ratios["DQS skinning vs GLM mat4 LBS"] = dqs / s["glm_lbs/1/real_time"]["vertices_per_s"]
        ratios["DQS skinning vs GLM dualquat DQS"] = dqs / s["glm_dqs/1/real_time"]["vertices_per_s"]
    if k:
        ratios["IK LM vs KDL LMA (solves/s)"] = ik_case(k, "ArmDualQuaternionLM")["solves_per_s"] / ik_case(k, "ArmKdlLMA")["solves_per_s"]
    ax[1].barh(list(ratios), list(ratios.values()))
    ax[1].axvline(1.0, color="grey", linestyle=":")
    ax[1].set_xscale("log")
    ax[1].set_xlabel("dqkit speed ÷ peer speed (same run)")
    ax[1].set_title("Ratios to the peers")
    methods = (("LBS", "lbs"), ("DQS", "dqs"), ("CoR", "cor"))
    for i, threads in enumerate((1, 2) if s else ()):
        triad = float(skin["context"][f"triad_GBps_{threads}thread"]) * 1e9
        ax[2].bar([m + (i - 0.5) * 0.38 for m in range(len(methods))],
                  [s[f"dqkit_skinning/{name}/{threads}/real_time"]["bytes_per_second"] / triad for _, name in methods], 0.38,
                  label=f"{threads} thread{'s' if threads > 1 else ''}")
    ax[2].set_xticks(range(len(methods)), [label for label, _ in methods])
    ax[2].axhline(1.0, color="grey", linestyle=":")
    ax[2].axhline(0.7, color="tab:red", linestyle="--", label="target for DQS (0.7)")
    ax[2].set_ylabel("fraction of the triad bandwidth, same thread count")
    ax[2].set_title("Skinning, 4 influences, positions and normals" if s else "Skinning: bench_skin not built (needs GLM)")
    ax[2].set_ylim(0, 1.5 * max(1.0, ax[2].get_ylim()[1]))  # room for the legend above the bars
    ax[2].legend(loc="upper left", fontsize="small")
    fig.savefig(os.path.join(ROOT, "docs", "performance.png"), dpi=80)


if __name__ == "__main__":
    args = sys.argv[1:]
    if args == ["--from-json"]:
        with open(os.path.join(ROOT, "docs", "performance.json")) as f:
            main(json.load(f))
    elif args[:1] == ["--only"] and len(args) in (2, 3):
        main(rerun(args[2] if len(args) == 3 else os.path.join(ROOT, "build", "release"), args[1]))
    elif len(args) <= 1 and not args[:1] == ["--only"]:
        main(run_suite(args[0] if args else os.path.join(ROOT, "build", "release")))
    else:
        sys.exit(__doc__)
