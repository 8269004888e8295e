"""Skeletons, batch forward kinematics, BVH files, import, IK and skinning from Python."""
import errno
import os
import subprocess
import threading
import sys

import numpy as np
import pytest

import dqkit
from conftest import CMU_BVH, MODELS, SIMPLE_SKIN, hamilton, need, random_rigid, rotation_matrix

EPS = np.finfo(np.float64).eps


def numpy_forward_kinematics(parents, local):
    """model[j] = model[parent] · local[j] with NumPy products over frames (the reference)."""
    model = np.empty_like(local)
    for j, p in enumerate(parents):
        if p < 0:
            model[:, j] = local[:, j]
            continue
        a, b = model[:, p], local[:, j]
        model[:, j, :4] = hamilton(a[:, :4], b[:, :4])
        model[:, j, 4:] = hamilton(a[:, :4], b[:, 4:]) + hamilton(a[:, 4:], b[:, :4])
    return model


def test_skeleton_built_from_python():
    raw = dqkit.RawSkeleton()
    root = raw.add("hips", -1)
    spine = raw.add("spine", root, dqkit.DualQuaternion.from_translation([0, 1, 0]))
    raw.add("head", spine, dqkit.DualQuaternion.from_translation([0, 0.5, 0]), end_site=True)
    s = dqkit.Skeleton(raw)
    assert len(s) == 3 and list(s.parents) == [-1, 0, 1] and s.names == ["hips", "spine", "head"]
    assert s.find("spine") == 1 and s.find("tail") == -1 and s.is_end_site(2)
    assert s.index("spine") == 1 and "spine" in s and "tail" not in s
    with pytest.raises(KeyError, match="no joint named 'tail'"):
        s.index("tail")  # never -1, which NumPy would take as the last joint
    model = dqkit.local_to_model(s, s.rest_pose)
    np.testing.assert_array_equal(dqkit.translation(model), [[0, 0, 0], [0, 1, 0], [0, 1.5, 0]])
    # threads: one pose, no frames and 40 frames on every hardware thread; counts that are no
    # thread count refused by name.
    np.testing.assert_array_equal(dqkit.local_to_model(s, s.rest_pose, threads=0), model)
    assert dqkit.local_to_model(s, np.zeros((0, 3, 8)), threads=0).shape == (0, 3, 8)
    np.testing.assert_array_equal(dqkit.local_to_model(s, np.array([s.rest_pose] * 40), threads=2), [model] * 40)
    # NumPy's integers are counts too (they have __index__), with the same range.
    np.testing.assert_array_equal(dqkit.local_to_model(s, np.array([s.rest_pose] * 40), threads=np.int64(2)), [model] * 40)
    for bad in (-1, 2**32, 2**64, -2**70, np.int64(-3), np.uint64(2**63)):
        with pytest.raises(ValueError, match=rf"threads: expected 0 \(every hardware thread\) or a number of threads up to 4294967295, got {bad}"):
            dqkit.local_to_model(s, s.rest_pose, threads=bad)
    for bad in (True, np.True_, 1.5, np.float64(2.0), "2", np.array([2])):
        with pytest.raises(TypeError):
            dqkit.local_to_model(s, s.rest_pose, threads=bad)
    bad = dqkit.RawSkeleton()
    bad.add("a", 3)
    with pytest.raises(dqkit.ReadError):
        dqkit.Skeleton(bad)


def test_batch_forward_kinematics_on_cmu():
    bvh = dqkit.read_bvh_file(str(need(CMU_BVH)))
    skeleton = dqkit.bvh_skeleton(bvh)
    anim = dqkit.bvh_animation(bvh, skeleton)
    local = anim.locals
    assert local.shape == (bvh.frame_count, len(skeleton), 8)
    model = dqkit.local_to_model(skeleton, local)
    ref = numpy_forward_kinematics(skeleton.parents, local)
    scale = np.abs(dqkit.translation(model.reshape(-1, 8))).max()
    np.testing.assert_allclose(model, ref, atol=64 * EPS * scale)
    # Against the scalar API for a few frames, bit for bit (the same product).
    for f in (0, 1, bvh.frame_count - 1):
        world = [None] * len(skeleton)
        for j, p in enumerate(skeleton.parents):
            world[j] = dqkit.DualQuaternion(local[f, j]) if p < 0 else world[p] * dqkit.DualQuaternion(local[f, j])
        np.testing.assert_array_equal(model[f], [np.asarray(w) for w in world])
    # One pose, float32, and parents given as a list.
    np.testing.assert_array_equal(dqkit.local_to_model(list(skeleton.parents), local[5]), model[5])
    # Frames run on the vector lanes, in place (dq::simd::local_to_model_frames_parallel), in both
    # dtypes: each frame as computed alone (the same product on scalars), bit for bit, 37 frames (no
    # multiple of any width); and the float64 result to float32 rounding: 64 ε of the translations'
    # scale for each level of the hierarchy (the inputs' rounding and a product's few roundings per level).
    np.testing.assert_array_equal(model[:37].view(np.uint64),
                                  np.array([dqkit.local_to_model(skeleton, local[f]) for f in range(37)]).view(np.uint64))
    local32 = local[:37].astype(np.float32)
    model32 = dqkit.local_to_model(skeleton, local32)
    assert model32.dtype == np.float32
    alone = np.array([dqkit.local_to_model(skeleton, local32[f]) for f in range(37)])
    np.testing.assert_array_equal(model32.view(np.uint32), alone.view(np.uint32))
    depth = [0] * len(skeleton)
    for j, p in enumerate(skeleton.parents):
        depth[j] = 1 if p < 0 else depth[p] + 1
    np.testing.assert_allclose(model32, model[:37], atol=64 * max(depth) * np.finfo(np.float32).eps * scale)
    # On threads (oneTBB's workers): the one-thread result bit for bit, in both dtypes, for batches
    # that are split (more than 256 frames) into ranges cut at multiples of 16 frames, the last one
    # partial (300 and 2749 frames).
    for frames in (local[:300], local[:-3]):
        for dtype in (np.float64, np.float32):
            x = frames.astype(dtype)
            one = dqkit.local_to_model(skeleton, x)
            for threads in (2, 0):
                many = dqkit.local_to_model(skeleton, x, threads=threads)
                assert many.dtype == dtype
                np.testing.assert_array_equal(many.view(np.uint8), one.view(np.uint8))
    # Parents must be signed integers, checked before narrowing: never truncated or wrapped.
    for bad, message in (([-1, 0.7], "J signed integers"), (np.array([0, 1], np.uint8), "J signed integers"),
                         ([-1, 2**40], "joint 1 has parent 1099511627776")):
        with pytest.raises(ValueError, match=message):
            dqkit.local_to_model(bad, local[5][:2])
    m32 = dqkit.local_to_model(skeleton, local.astype(np.float32))
    assert m32.dtype == np.float32
    # float32 world positions of a 30-joint chain: errors accumulate along the chain (≈ depth ×
    # a few ulps of the largest coordinate); 1e-3 of the skeleton's size bounds that with margin.
    np.testing.assert_allclose(dqkit.translation(m32.reshape(-1, 8)), dqkit.translation(model.reshape(-1, 8)), atol=1e-3 * scale)


def test_bvh_errors_name_file_and_line(tmp_path):
    bad = tmp_path / "bad.bvh"
    bad.write_text("HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 x\n")
    with pytest.raises(dqkit.ReadError, match=r"bad\.bvh:4: expected a finite number, found 'x'"):
        dqkit.read_bvh_file(str(bad))
    # Nothing there: FileNotFoundError, as open() raises (an OSError, with errno and filename).
    with pytest.raises(FileNotFoundError) as missing:
        dqkit.read_bvh_file(str(tmp_path / "missing.bvh"))
    assert missing.value.errno == errno.ENOENT and missing.value.filename == str(tmp_path / "missing.bvh")
    with pytest.raises(ValueError):  # ReadError is a ValueError
        dqkit.read_bvh_file(str(bad))
    with pytest.raises(dqkit.ReadError, match="mine.bvh:"):
        dqkit.read_bvh("HIERARCHY\nROOT\n", "mine.bvh")


def test_bvh_write_read_round_trip(tmp_path):
    bvh = dqkit.read_bvh_file(str(need(CMU_BVH)))
    out = tmp_path / "copy.bvh"
    dqkit.write_bvh_file(bvh, out)  # a pathlib.Path, as any os.PathLike
    with pytest.raises(dqkit.WriteError, match="copy.bvh: already exists; .*overwrite=True"):
        dqkit.write_bvh_file(bvh, str(out))  # never replaces a file unless told
    assert issubclass(dqkit.WriteError, OSError)
    again = dqkit.read_bvh_file(out)
    assert [j.name for j in again.joints] == [j.name for j in bvh.joints]
    np.testing.assert_array_equal(again.motion, bvh.motion)
    assert dqkit.write_bvh(again) == out.read_text()
    # Changing the motion from NumPy, and another rotation order that keeps the transforms.
    with pytest.raises(ValueError, match="read-only"):
        bvh.motion[0, 0] = 1.0  # would change only a copy
    motion = bvh.motion.copy()
    motion[:, 0] += 10
    bvh.motion = motion
    np.testing.assert_array_equal(bvh.motion[:, 0], again.motion[:, 0] + 10)
    # What would not read back is refused before anything is written, naming the frame and channel.
    motion[2, 4] = np.nan
    bvh.motion = motion
    before = out.read_text()
    with pytest.raises(ValueError, match=r"cannot write BVH: frame 2, joint 0 \('Hips'\) Yrotation: the value is not finite"):
        dqkit.write_bvh_file(bvh, out, overwrite=True)
    assert out.read_text() == before
    zyx = dqkit.with_rotation_order(again, dqkit.EulerOrder.ZYX)
    s1, s2 = dqkit.bvh_skeleton(again), dqkit.bvh_skeleton(zyx)
    w1 = dqkit.local_to_model(s1, dqkit.bvh_animation(again, s1).locals[:50])
    w2 = dqkit.local_to_model(s2, dqkit.bvh_animation(zyx, s2).locals[:50])
    # The file stores degrees with 6 decimals (BVH text): positions agree to that resolution.
    np.testing.assert_allclose(dqkit.translation(w1.reshape(-1, 8)), dqkit.translation(w2.reshape(-1, 8)), atol=1e-3)


def test_animation_sampling_and_load_motion():
    motion = dqkit.load_motion(str(need(CMU_BVH)))
    anim = motion.animation
    assert motion.format == "bvh" and motion.bvh is not None
    ft = anim.frame_time
    np.testing.assert_array_equal(dqkit.sample(anim, 3 * ft), anim.locals[3])
    mid = dqkit.sample(anim, 3.5 * ft, dqkit.Interpolation.screw)
    np.testing.assert_array_equal(mid, [np.asarray(dqkit.sclerp(dqkit.DualQuaternion(a), dqkit.DualQuaternion(b), 0.5))
                                        for a, b in zip(anim.locals[3], anim.locals[4])])
    rebuilt = dqkit.Animation(anim.locals, ft)
    assert rebuilt.frame_count == anim.frame_count and np.array_equal(rebuilt.locals, anim.locals)


def test_import_runs_the_packaged_worker_without_forking():
    scene = dqkit.import_scene(str(need(SIMPLE_SKIN))) if dqkit.HAVE_IMPORT else pytest.skip("built without Assimp")
    assert len(scene.skeleton) > 0 and scene.meshes and scene.animations
    assert os.path.exists(os.environ["DQKIT_IMPORT_WORKER"])
    with pytest.raises(FileNotFoundError, match="nothing.gltf"):
        dqkit.import_scene("/nonexistent/nothing.gltf")
    with pytest.raises(FileNotFoundError):
        dqkit.import_motion("/nonexistent/nothing.gltf")
    with pytest.raises(FileNotFoundError):
        dqkit.load_motion("/nonexistent/nothing.bvh")


def test_scene_skin_on_a_pool():
    # SceneSkin.skin on a pool of two with parts of 16 vertices and more: three meshes of 648 to
    # 1196 vertices in one call, cut into parts of 384 (from their 3,014 vertices), 2 to 4 a
    # mesh, that the threads claim; every mesh the one-thread result bit for bit.
    if not dqkit.HAVE_IMPORT:
        pytest.skip("built without Assimp")
    scene = dqkit.import_scene(str(need(MODELS / "X" / "BCN_Epileptic.X")))
    assert len(scene.meshes) == 3 and min(len(m.positions) for m in scene.meshes) > 32
    skin = dqkit.SceneSkin.build(scene)
    pool = dqkit.SkinningThreads(2, min_part=16)
    for time in (0.0, 0.4, 1.0):
        world = dqkit.pose_at(scene, 0, time)
        for method in (dqkit.SkinningMethod.lbs, dqkit.SkinningMethod.dqs):
            one, two = skin.skin(world, method), skin.skin(world, method, pool=pool)
            np.testing.assert_array_equal(two.positions.view(np.uint32), one.positions.view(np.uint32))
    # The positions' rows are the frame's vertices as the CSV writer gives them (%.9g: every
    # float32 exactly), written by C++ from the same component arrays.
    rows = dqkit.format_frame(two, dqkit.MeshFormat.csv).splitlines()[1:]
    csv = np.array([[float(x) for x in row.split(",")[1:]] for row in rows], dtype=np.float32)
    np.testing.assert_array_equal(csv.view(np.uint32), two.positions.view(np.uint32))


def test_import_motion_keeps_lights_and_cameras_when_asked():
    if not dqkit.HAVE_IMPORT:
        pytest.skip("built without Assimp")
    path = str(need(MODELS / "FBX" / "huesitos.fbx"))
    left_out = dqkit.import_motion(path)
    assert any("'Lamp' is not a joint" in w for w in left_out.warnings)
    options = dqkit.MotionOptions()
    options.lights_and_cameras = True
    kept = dqkit.import_motion(path, options)
    assert len(kept.skeleton) == len(left_out.skeleton) + 2  # the lamp and the camera
    assert not any("is not a joint" in w for w in kept.warnings)


def test_ik_reaches_a_target():
    model = dqkit.KinematicModel.arm7()
    n = model.parameters()
    q = np.zeros(n)
    effector = len(model.skeleton) - 1
    goal_q = np.full(n, 0.3)
    target = dqkit.translation(dqkit.model_transforms(model, goal_q)[effector])
    solver = dqkit.IkSolver(model)
    result = solver.solve([dqkit.IkTask.reach(effector, target)], q)
    assert result.status == dqkit.IkStatus.converged, result
    reached = dqkit.translation(dqkit.model_transforms(model, q)[effector])
    np.testing.assert_allclose(reached, target, atol=1e-9)  # IkOptions.position_tolerance is 1e-10
    assert model.within_limits(q)
    with pytest.raises(ValueError, match=r"q: expected a writable contiguous float64 array of shape \(7,\)"):
        solver.solve([dqkit.IkTask.reach(effector, target)], np.zeros(3))
    # Invalid input says what is wrong, also in the repr; errors print in %g, not as 0.000000.
    bad = solver.solve([dqkit.IkTask.reach(effector, target)], np.full(n, np.nan))
    assert bad.status == dqkit.IkStatus.invalid_input and bad.message == "q has a non-finite value"
    assert "message='q has a non-finite value'" in repr(bad)
    assert "position_error=0.000000" not in repr(result), repr(result)


def numpy_dqs(positions, bones, weights, bone_world_times_inverse_bind):
    """Dual quaternion skinning (Kavan et al. 2008) written with NumPy: blend the bones' dual
    quaternions (signs aligned to the pivot, the influence of largest weight, as docs/skinning.md
    specifies), normalize, transform."""
    out = np.empty_like(positions)
    for v, p in enumerate(positions):
        qs = bone_world_times_inverse_bind[bones[v]]
        pivot = qs[np.argmax(weights[v]), :4]
        signs = np.where(qs[:, :4] @ pivot < 0, -1.0, 1.0)
        b = (weights[v, :, None] * signs[:, None] * qs).sum(0)
        n = np.linalg.norm(b[:4])
        r, d = b[:4] / n, b[4:] / n
        t = 2 * hamilton(d, r * [1, -1, -1, -1])[1:]
        out[v] = rotation_matrix(r) @ p + t
    return out


def test_skin_vertices_against_numpy(rng):
    V, B, K = 200, 4, 3
    positions = rng.uniform(-1, 1, size=(V, 3))
    bones = np.stack([rng.choice(B, K, replace=False) for _ in range(V)])
    weights = rng.uniform(0.1, 1, size=(V, K))
    weights /= weights.sum(1, keepdims=True)
    inverse_bind = np.stack([np.eye(4)] * B)
    inverse_bind[:, :3, 3] = rng.uniform(-1, 1, size=(B, 3))  # rigid binds (translations)
    skin = dqkit.build_skin(positions, bones, weights, inverse_bind)
    assert skin.vertex_count == V and skin.bone_count == B
    world, _, _ = random_rigid(rng, B, scale=1.0)
    out = dqkit.skin_vertices(skin, world, dqkit.SkinningMethod.dqs)
    assert out.shape == (V, 3) and out.dtype == np.float32
    q = dqkit.compose(world, dqkit.from_matrix(inverse_bind))
    # The library skins in float32 (positions, palette): 1e-5 on unit-size coordinates is ~100 ulps.
    np.testing.assert_allclose(out, numpy_dqs(positions, bones, weights, q), atol=1e-5)
    lbs = dqkit.skin_vertices(skin, world, dqkit.SkinningMethod.lbs)
    m = dqkit.to_mat4(q)
    ref = np.einsum("vk,vkij,vj->vi", weights, m[bones], np.c_[positions, np.ones(V)])[:, :3]
    np.testing.assert_allclose(lbs, ref, atol=1e-5)
    with pytest.raises(ValueError, match=r"bone_world: expected shape \(4, 8\)"):
        dqkit.skin_vertices(skin, world[:3])
    with pytest.raises(ValueError, match="needs centres of rotation"):
        dqkit.skin_vertices(skin, world, dqkit.SkinningMethod.cor)
    # Bones must be rigid: LBS and DQS would read a scaled dual quaternion differently.
    for bad in (2 * world, np.zeros_like(world), np.full_like(world, np.nan)):
        with pytest.raises(ValueError, match="bone_world: bone 0 is not a unit dual quaternion"):
            dqkit.skin_vertices(skin, bad, dqkit.SkinningMethod.lbs)


def test_skin_vertices_into_out(rng):
    """`out=`: the rows written into the caller's array, which is returned; anything else refused before a write."""
    skin = small_skin(rng)
    world, _, _ = random_rigid(rng, skin.bone_count, scale=1.0)
    V = skin.vertex_count
    expected = dqkit.skin_vertices(skin, world, dqkit.SkinningMethod.dqs)
    pool = dqkit.SkinningThreads(2, min_part=16)
    for p in (None, pool):
        out = np.full((V, 3), np.nan, dtype=np.float32)
        assert dqkit.skin_vertices(skin, world, dqkit.SkinningMethod.dqs, pool=p, out=out) is out
        assert np.array_equal(out.view(np.uint32), expected.view(np.uint32))  # bit for bit
    wide = np.full((V, 6), np.nan, dtype=np.float32)
    read_only = np.full((V, 3), np.nan, dtype=np.float32)
    read_only.setflags(write=False)
    unaligned = np.frombuffer(bytearray(12 * V + 1), dtype=np.float32, offset=1).reshape(V, 3)
    assert unaligned.flags.writeable and not unaligned.flags.aligned
    refused = [np.zeros((V, 3)),  # float64
               np.zeros((V - 1, 3), dtype=np.float32), np.zeros((V, 4), dtype=np.float32), np.zeros(3 * V, dtype=np.float32),
               wide[:, ::2],  # every other column: not contiguous
               np.zeros((V, 3), dtype=np.float32)[::-1],  # rows backwards
               np.asfortranarray(np.zeros((V, 3), dtype=np.float32)), read_only, unaligned, [[0.0] * 3] * V]
    for bad in refused:
        with pytest.raises(ValueError, match=rf"out: expected a writable, aligned, C-contiguous float32 array of shape \({V}, 3\)"):
            dqkit.skin_vertices(skin, world, out=bad)
    assert np.isnan(wide).all() and np.isnan(read_only).all() and not unaligned.any()


def small_skin(rng, V=200, B=5, K=3):
    """A skin of V vertices with K influences among B bones, and triangles for CoR."""
    positions = rng.uniform(-1, 1, size=(V, 3))
    bones = np.stack([rng.choice(B, K, replace=False) for _ in range(V)])
    weights = rng.uniform(0.1, 1, size=(V, K))
    inverse_bind = np.stack([np.eye(4)] * B)
    inverse_bind[:, :3, 3] = rng.uniform(-1, 1, size=(B, 3))
    return dqkit.build_skin(positions, bones, weights, inverse_bind, triangles=np.arange(V - V % 3).reshape(-1, 3))


def test_skinning_pools_give_the_one_thread_result(rng):
    # A SkinningThreads pool cuts the vertices into parts of whole 16-vertex vectors, at most 4 per
    # thread and none but the last below min_part (200 vertices on 2 or 3 threads with min_part=16:
    # 6 parts of 32 and one of 8; with the default min_part, 4096, one part): every method bit for
    # bit the one-thread result. Python threads sharing one pool take turns on it, each with its
    # own result (joined with a timeout: a broken pool fails the test instead of hanging it).
    skin = small_skin(rng)
    worlds = [random_rigid(rng, 5, scale=1.0)[0] for _ in range(6)]
    methods = [dqkit.SkinningMethod.lbs, dqkit.SkinningMethod.dqs, dqkit.SkinningMethod.cor]
    one = [dqkit.skin_vertices(skin, w, m) for w in worlds for m in methods]
    for n, min_part, spin in ((2, 16, 100), (3, 0, 0), (0, 1, 7), (2, None, None)):
        pool = dqkit.SkinningThreads(n) if min_part is None else dqkit.SkinningThreads(n, min_part=min_part, spin_microseconds=spin)
        assert pool.size == (n or min(os.cpu_count(), 1024))
        assert pool.min_part == (4096 if min_part is None else 16)  # rounded up to a multiple of 16, at least 16
        automatic = 100 if pool.size <= len(os.sched_getaffinity(0)) else 0  # a CPU per thread, or no spin
        assert pool.spin_microseconds == (automatic if spin is None else spin)
        assert repr(pool) == f"SkinningThreads({pool.size}, min_part={pool.min_part}, spin_microseconds={pool.spin_microseconds})"
        got = [dqkit.skin_vertices(skin, w, m, pool=pool) for w in worlds for m in methods]
        for a, b in zip(got, one):
            np.testing.assert_array_equal(a.view(np.uint32), b.view(np.uint32))
    assert dqkit.SkinningThreads(2, min_part=4097).min_part == 4112
    pool = dqkit.SkinningThreads(2, min_part=16)
    results = [None] * len(one)

    def work(i):
        for _ in range(20):
            results[i] = dqkit.skin_vertices(skin, worlds[i // 3], methods[i % 3], pool=pool)

    threads = [threading.Thread(target=work, args=(i,), daemon=True) for i in range(len(one))]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=60)
        assert not t.is_alive(), "a call on the shared pool did not return"
    for a, b in zip(results, one):
        np.testing.assert_array_equal(a.view(np.uint32), b.view(np.uint32))
    for bad in (-1, 1025, 2**64, np.int32(-1)):
        with pytest.raises(ValueError, match=rf"threads: expected 0 \(every hardware thread\) or a number of threads up to 1024, got {bad}"):
            dqkit.SkinningThreads(bad)  # each a system thread, started at once
    assert dqkit.SkinningThreads(np.uint8(3)).size == 3
    with pytest.raises(TypeError):
        dqkit.SkinningThreads(True)
    with pytest.raises(ValueError, match="min_part: expected a count from 0 to 18446744073709551615, got -1"):
        dqkit.SkinningThreads(2, min_part=-1)
    for bad in (True, np.False_, 16.0):
        with pytest.raises(TypeError):
            dqkit.SkinningThreads(2, min_part=bad)
    assert dqkit.SkinningThreads(2, min_part=np.int16(40)).min_part == 48
    with pytest.raises(ValueError, match=r"spin_microseconds: expected at most 1000000 \(one second\), got 1000001"):
        dqkit.SkinningThreads(2, spin_microseconds=1_000_001)
    with pytest.raises(ValueError, match="spin_microseconds: expected a count from 0 to 18446744073709551615, got -1"):
        dqkit.SkinningThreads(2, spin_microseconds=-1)
    with pytest.raises(TypeError):
        dqkit.SkinningThreads(2, spin_microseconds=False)
    with pytest.raises(TypeError):
        dqkit.skin_vertices(skin, worlds[0], pool=2)  # a pool, not a count
    np.testing.assert_array_equal(dqkit.skin_vertices(skin, worlds[0], dqkit.SkinningMethod.lbs, pool=None), one[0])


POOL_SCRIPT = """
import os, resource, sys
import numpy as np
import dqkit
sys.path.insert(0, sys.argv[1])
from test_anim_io import small_skin
skin = small_skin(np.random.default_rng(1))
world = np.tile([1.0, 0, 0, 0, 0, 0, 0, 0], (5, 1))
pool = dqkit.SkinningThreads(2, min_part=16)  # 200 vertices: split, so the parent's check uses the worker
one = dqkit.skin_vertices(skin, world, pool=pool)
if sys.argv[2] == "fork":
    pid = os.fork()
    if pid == 0:  # the pool's threads are not in this process: refused, and left at exit
        try:
            dqkit.skin_vertices(skin, world, pool=pool)
        except RuntimeError as e:
            print("child:", e, flush=True)
            sys.exit(0)
        sys.exit(1)
    assert os.waitpid(pid, 0)[1] == 0
    assert np.array_equal(dqkit.skin_vertices(skin, world, pool=pool), one)  # the parent's pool still works
else:  # threads that cannot start: an error that says so, and no thread left running
    size = int(next(l for l in open("/proc/self/status") if l.startswith("VmSize")).split()[1]) * 1024
    resource.setrlimit(resource.RLIMIT_AS, (size + (256 << 20), resource.RLIM_INFINITY))
    try:
        dqkit.SkinningThreads(1024)
    except RuntimeError as e:
        print("error:", e)
    assert np.array_equal(dqkit.skin_vertices(skin, world, pool=dqkit.SkinningThreads(2)), one)
print("ok")
"""


@pytest.mark.parametrize("case", ["fork", "no threads"])
def test_skinning_pool_across_fork_and_without_threads(case):
    out = subprocess.run([sys.executable, "-c", POOL_SCRIPT, os.path.dirname(__file__), case], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    if case == "fork":
        assert "child: SkinningThreads: made in another process (before a fork)" in out.stdout
    else:
        assert "error: SkinningThreads(1024): could not start a thread: " in out.stdout
    assert out.stdout.endswith("ok\n")


def test_installed_module_imports_from_the_prefix(tmp_path):
    build = os.environ.get("DQKIT_PYTHON_BUILD_DIR")
    if not build:
        pytest.skip("DQKIT_PYTHON_BUILD_DIR (the CMake build directory) not set; scripts/test.sh sets it")
    prefix = tmp_path / "prefix"
    subprocess.run(["cmake", "--install", build, "--prefix", str(prefix), "--component", "python"], check=True,
                   stdout=subprocess.DEVNULL)
    site = next(prefix.rglob("dqkit/__init__.py")).parent.parent
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "DQKIT_IMPORT_WORKER")}
    env["PYTHONPATH"] = str(site)
    code = """if True:
        import dqkit, os, sys
        assert dqkit.__file__.startswith(sys.argv[1]), dqkit.__file__
        print(dqkit.DualQuaternion.from_translation([1, 2, 3]).translation())
        if dqkit.HAVE_IMPORT:  # the installed package's own worker, found without configuration
            assert os.environ["DQKIT_IMPORT_WORKER"].startswith(sys.argv[1]), os.environ["DQKIT_IMPORT_WORKER"]
            print(len(dqkit.import_scene(sys.argv[2]).skeleton))"""
    out = subprocess.run([sys.executable, "-c", code, str(site), str(need(SIMPLE_SKIN))], env=env, check=True,
                         capture_output=True, text=True, cwd=tmp_path).stdout.split("\n")
    assert out[0] == "[1. 2. 3.]"


def test_bvh_kinematics_and_fix_foot_sliding():
    bvh = dqkit.read_bvh_file(str(need(CMU_BVH)))
    k = dqkit.bvh_kinematics(bvh)
    skeleton = dqkit.bvh_skeleton(bvh)
    # The channel model reproduces the file's transforms (docs/ik.md), here for one frame.
    f = 200
    world = dqkit.model_transforms(k.model, k.to_parameters(bvh.motion[f]))
    ref = dqkit.local_to_model(skeleton, dqkit.bvh_animation(bvh, skeleton).locals[f])
    np.testing.assert_allclose(dqkit.translation(world), dqkit.translation(ref), atol=1e-9 * np.abs(dqkit.translation(ref)).max())
    short = dqkit.read_bvh(dqkit.write_bvh(bvh).split("Frames:")[0] + "Frames: 240\nFrame Time: 0.0083333\n" +
                           "\n".join(" ".join(f"{v:.6f}" for v in row) for row in bvh.motion[:240]) + "\n", "short.bvh")
    before = short.motion
    report = dqkit.fix_foot_sliding(short)
    assert report.leg_joints and report.max_other_joint_motion == 0
    changed = np.flatnonzero((short.motion != before).any(axis=0))
    legs = {j.name for j in short.joints} & set(report.leg_joints)
    leg_channels = {c for j in short.joints if j.name in legs for c in range(j.first_channel, j.first_channel + len(j.channels))}
    assert set(changed) <= leg_channels
