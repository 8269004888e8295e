"""Bad input from Python: a clear exception (TypeError, ValueError, IndexError, MemoryError, the
module's ReadError), never a crash, a silent wrong answer, or a write that is silently lost. Each
case here crashed the interpreter or answered wrongly in a user's trial before it was fixed."""
import numpy as np
import pytest

import dqkit
from conftest import CMU_BVH, random_rigid


def need(path):
    if not path.exists():
        pytest.skip(f"{path} not installed (Debian assimp-testmodels)")
    return path


IDENTITY = [1.0, 0, 0, 0, 0, 0, 0, 0]


@pytest.mark.parametrize("call", [
    lambda: dqkit.transform_points(IDENTITY, [["a", "b", "c"]]),
    lambda: dqkit.sclerp(IDENTITY, [1, 0, 0, 0, 0, 0, 0, "x"], 0.5),
    lambda: dqkit.from_euler(dqkit.EulerOrder.XYZ, dqkit.EulerFrame.intrinsic, [[1, 2, "a"]]),
    lambda: dqkit.build_skin(np.zeros((1, 3)), [[0]], [[1.0]], np.eye(4)[None], triangles=[["a", "b", "c"]]),
])
def test_values_that_are_not_numbers_raise_value_error(call):
    # array_t::ensure returned null for them, and the null array was read: a segmentation fault.
    with pytest.raises(ValueError, match="expected"):
        call()


def test_a_copy_too_large_for_memory_raises_memory_error():
    # A broadcast view costs nothing until it is made contiguous.
    # Beyond the 2**47 bytes of a process's address space, so that no overcommit setting lets the
    # allocation start (and fill the machine's memory): MemoryError on every machine.
    huge = np.broadcast_to(np.array(IDENTITY), (10**13, 8))
    with pytest.raises(MemoryError):
        dqkit.normalized(huge)
    with pytest.raises(MemoryError):
        dqkit.local_to_model(np.broadcast_to(np.array([-1]), (10**14,)), np.array([IDENTITY]))


def test_indices_outside_the_skeleton_or_the_file_raise_index_error():
    bvh = dqkit.read_bvh_file(str(need(CMU_BVH)))
    skeleton = dqkit.bvh_skeleton(bvh)
    joints, frames = len(bvh.joints), bvh.frame_count
    for joint, frame in ((0, frames), (0, 100000), (joints, 0), (2**40, 0), (-1, 0), (0, -1)):
        with pytest.raises(IndexError):
            dqkit.bvh_local_transform(bvh, joint, frame)
    last = dqkit.bvh_local_transform(bvh, joints - 1, frames - 1)
    assert last.is_unit(1e-12)
    n = len(skeleton)
    for j in (n, 10**9, -n - 1):
        with pytest.raises(IndexError):
            skeleton.subtree_end(j)
        with pytest.raises(IndexError):
            skeleton.is_end_site(j)
    # Python indexing: −1 is the last joint, a leaf.
    assert skeleton.subtree_end(-1) == n and skeleton.is_end_site(-1) == skeleton.is_end_site(n - 1)


def test_a_skeleton_or_animation_of_another_character_is_refused():
    bvh = dqkit.read_bvh_file(str(need(CMU_BVH)))
    arm = dqkit.KinematicModel.arm7().skeleton
    small = dqkit.to_bvh(arm, dqkit.Animation(np.tile(IDENTITY, (3, len(arm), 1)), 0.1))
    with pytest.raises(ValueError, match="not the skeleton of this BVH file"):
        dqkit.bvh_animation(small, dqkit.bvh_skeleton(bvh))
    with pytest.raises(ValueError, match="not the skeleton of this BVH file"):
        dqkit.bvh_animation(bvh, arm)
    with pytest.raises(ValueError, match=r"the animation has 8 joints .* the skeleton 38"):
        dqkit.to_bvh(dqkit.bvh_skeleton(bvh), dqkit.Animation(np.tile(IDENTITY, (3, 8, 1)), 0.1))


def test_enum_values_outside_the_enumeration_are_refused():
    for enum, value in ((dqkit.EulerOrder, 99), (dqkit.EulerFrame, 7), (dqkit.SkinningMethod, 7), (dqkit.Path, 5),
                        (dqkit.IkMethod, 17), (dqkit.TaskKind, 42), (dqkit.DofType, 9), (dqkit.Interpolation, 9)):
        with pytest.raises(ValueError, match=f"{value} is not a {enum.__name__}"):
            enum(value)
    assert dqkit.EulerOrder(int(dqkit.EulerOrder.ZYX)) == dqkit.EulerOrder.ZYX
    # Nor through pickle, whose state is the integer.
    import pickle
    assert pickle.loads(pickle.dumps(dqkit.EulerOrder.XZY)) == dqkit.EulerOrder.XZY
    forged = dqkit.EulerOrder.__new__(dqkit.EulerOrder)  # what unpickling does, with a state of 99
    with pytest.raises(ValueError, match="99 is not a EulerOrder"):
        forged.__setstate__(99)


def test_interpolation_parameter_as_list_number_or_zero_d_array(rng):
    q, _, _ = random_rigid(rng, 5)
    p = q[::-1].copy()
    t = [0, 0.25, 0.5, 0.75, 1]
    np.testing.assert_array_equal(dqkit.sclerp(q, p, t), dqkit.sclerp(q, p, np.array(t)))
    q32, p32 = q.astype(np.float32), p.astype(np.float32)
    np.testing.assert_array_equal(dqkit.sclerp(q32, p32, np.array(0.5)), dqkit.sclerp(q32, p32, 0.5))
    np.testing.assert_array_equal(dqkit.sclerp(q32, p32, np.float64(0.5)), dqkit.sclerp(q32, p32, 0.5))
    for bad in (None, "a", object(), 1j, np.complex128(1), np.array("x"), np.array(0.5j)):
        with pytest.raises(TypeError, match="t: expected a real number"):
            dqkit.sclerp(q, p, bad)


def test_values_are_sequences_and_scalars_multiply_them():
    q = dqkit.DualQuaternion(np.arange(1.0, 9.0))
    r = dqkit.Quaternion(1.0, 2.0, 3.0, 4.0)
    assert len(q) == 8 and len(r) == 4
    assert (q[0], q[-1], r[1]) == (1.0, 8.0, 2.0)
    with pytest.raises(IndexError):
        q[8]
    stacked = np.array([q, q])
    assert stacked.shape == (2, 8) and (stacked[1] == np.arange(1.0, 9.0)).all()
    np.testing.assert_array_equal(dqkit.normalized([q, q]), dqkit.normalized(stacked))
    # A NumPy scalar on the left defers to the value's own product (it made an ndarray), and
    # ufuncs still read the components.
    assert isinstance(np.float64(2) * q, dqkit.DualQuaternion) and np.float64(2) * q == q * 2.0
    assert isinstance(np.float32(2) * r, dqkit.Quaternion)
    np.testing.assert_array_equal(np.abs(-q), np.arange(1.0, 9.0))
    assert np.sum(r) == 10.0


def test_messages_with_file_names_that_are_not_utf8_keep_their_text(tmp_path):
    name = bytes(tmp_path) + b"/\xff\xfe.bvh"
    with open(name, "wb") as f:
        f.write(b"HIERARCHY\nROOT\n")
    with pytest.raises(dqkit.ReadError) as error:  # its message was empty
        dqkit.read_bvh_file(name)
    assert "\\xff\\xfe.bvh:2:" in str(error.value)
    with pytest.raises(FileNotFoundError):
        dqkit.read_bvh_file(bytes(tmp_path) + b"/\xff.bvh")


def test_copies_returned_by_properties_are_read_only():
    bvh = dqkit.read_bvh_file(str(need(CMU_BVH)))
    skeleton = dqkit.bvh_skeleton(bvh)
    animation = dqkit.bvh_animation(bvh, skeleton)
    task = dqkit.IkTask.reach(3, [1.0, 2.0, 3.0])
    for array in (animation.locals, skeleton.parents, skeleton.rest_pose, bvh.joints[1].offset, task.point):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 99
    # Results of functions stay writable, and a field is changed by assigning it whole.
    dqkit.translation(animation.locals[0])[0, 0] = 1
    task.point = [4.0, 5.0, 6.0]
    np.testing.assert_array_equal(task.point, [4, 5, 6])


def test_parameters_out_of_range_are_refused():
    with pytest.raises(ValueError, match="frame_time: expected a positive number"):
        dqkit.Animation(np.tile(IDENTITY, (2, 1, 1)), -0.1)
    a = dqkit.Animation(np.tile(IDENTITY, (2, 1, 1)), 0.1)
    with pytest.raises(ValueError, match="frame_time"):
        a.frame_time = float("nan")
    with pytest.raises(ValueError, match=r"locals: expected shape \(F, J, 8\)"):
        dqkit.Animation(np.zeros((2, 3, 7)), 0.1)
    with pytest.raises(ValueError, match="max_iterations: expected 1 or more"):
        dqkit.dib([dqkit.DualQuaternion()], [1.0], max_iterations=0)
    with pytest.raises(ValueError, match="bones: expected integers"):
        dqkit.build_skin(np.zeros((1, 3)), [[0.0]], [[1.0]], np.eye(4)[None])
    with pytest.raises(ValueError, match="triangles: triangle 0 names vertex 5 of 1"):
        dqkit.build_skin(np.zeros((1, 3)), [[0]], [[1.0]], np.eye(4)[None], triangles=[[0, 0, 5]])
    with pytest.raises(ValueError, match=r"beyond 2\*\*63 - 1"):  # not wrapped to −1
        dqkit.build_skin(np.zeros((1, 3)), np.array([[2**64 - 1]], np.uint64), [[1.0]], np.eye(4)[None])
    model = dqkit.KinematicModel.arm7()
    options = dqkit.IkOptions()
    options.max_iterations = -1
    result = dqkit.IkSolver(model, options).solve([dqkit.IkTask.reach(len(model.skeleton) - 1, [0.1, 0, 0])],
                                                    np.zeros(model.parameters()))
    assert result.status == dqkit.IkStatus.invalid_input and "max_iterations" in result.message


def test_motion_capture_options_and_frames_are_checked():
    bvh = dqkit.read_bvh_file(str(need(CMU_BVH)))
    k = dqkit.bvh_kinematics(bvh)
    with pytest.raises(ValueError, match=f"frame: expected the file's {bvh.channel_count()} channel values, got 500"):
        k.to_parameters(np.zeros(500))
    options = dqkit.FixFeetOptions()
    options.height = float("nan")
    with pytest.raises(dqkit.ReadError, match="height and speed must be numbers below infinity"):
        dqkit.fix_foot_sliding(bvh, options)
    options = dqkit.FixFeetOptions()
    options.feet = ["NoSuchToe"]
    with pytest.raises(dqkit.ReadError) as error:
        dqkit.fix_foot_sliding(bvh, options)
    assert "no joint named 'NoSuchToe'" in str(error.value) and "--feet" not in str(error.value)


def test_batch_from_matrix_takes_three_by_four(rng):
    q, _, _ = random_rigid(rng, 6)
    m = dqkit.to_mat4(q)
    np.testing.assert_array_equal(dqkit.from_matrix(m[:, :3, :]), dqkit.from_matrix(m))
    # Lists of integers, as every batch input: float64 (they were refused as int64).
    turns = [[[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]] * 2
    np.testing.assert_array_equal(dqkit.from_matrix(turns), dqkit.from_matrix(np.array(turns, float)))


def test_a_dangling_link_is_a_missing_file(tmp_path):
    (tmp_path / "gone.bvh").symlink_to(tmp_path / "nothing.bvh")
    with pytest.raises(FileNotFoundError):
        dqkit.read_bvh_file(str(tmp_path / "gone.bvh"))
