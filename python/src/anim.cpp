// Skeletons, animations and forward kinematics (single pose and (F, J, 8) batches), BVH and
// motion files, model import.
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "batch.hpp"
#include "dq/anim/animation.hpp"
#include "dq/anim/forward_kinematics.hpp"
#include "dq/anim/skeleton.hpp"
#include "dq/io/bvh.hpp"
#include "dq/io/file.hpp"
#include "dq/io/motion.hpp"
#include "dq/simd/pose_blocks.hpp"
#ifdef DQKIT_PY_HAVE_IMPORT
#include "dq/io/scene.hpp"
#endif

namespace dqpy {
namespace {

using DQd = dq::DualQuaternion<double>;

/// Parents from a Skeleton or a sequence of ints, checked (parent[j] < j, ≥ −1).
std::vector<int> parents_of(py::handle obj) {
  if (py::isinstance<dq::Skeleton>(obj)) {
    const auto p = obj.cast<const dq::Skeleton&>().parents();
    return {p.begin(), p.end()};
  }
  // Checked in 64 bits before narrowing, so that 2**40 is not read as another parent.
  const auto values = as_integers(obj, 1, "parents: expected a Skeleton or J signed integers (−1 marks a root), shape (J,)", true);
  std::vector<int> p(static_cast<std::size_t>(values.size()));
  for (std::size_t j = 0; j < p.size(); ++j) {
    const std::int64_t v = values.data()[j];
    if (v < -1 || v >= static_cast<std::int64_t>(j))
      throw py::value_error("parents: joint " + std::to_string(j) + " has parent " + std::to_string(v) +
                            "; every parent must be −1 or come before its child");
    p[j] = static_cast<int>(v);
  }
  return p;
}

/// A joint index as Python takes one: −1 is the last joint; IndexError outside the skeleton.
std::size_t joint_index(const dq::Skeleton& s, py::ssize_t j) {
  const auto n = static_cast<py::ssize_t>(s.size());
  if (j < -n || j >= n) throw py::index_error("joint " + std::to_string(j) + " of a skeleton of " + std::to_string(n) + " joints");
  return static_cast<std::size_t>(j < 0 ? j + n : j);
}

/// A frame time as the library reads one: a positive number of seconds.
double frame_time_checked(double t) {
  if (!(t > 0 && std::isfinite(t))) throw py::value_error("frame_time: expected a positive number of seconds, got " + py::str(py::float_(t)).cast<std::string>());
  return t;
}

void bind_skeleton(py::module_& m) {
  py::class_<dq::RawSkeleton>(m, "RawSkeleton", "A skeleton as built or imported: joints with parents and rest transforms.")
      .def(py::init<>())
      .def("add", &dq::RawSkeleton::add, py::arg("name"), py::arg("parent"), py::arg("rest") = DQd{}, py::arg("end_site") = false,
           "Appends a joint (parent −1 for a root) and returns its index.")
      .def("__len__", [](const dq::RawSkeleton& r) { return r.joints.size(); });
  py::class_<dq::Skeleton>(m, "Skeleton", "The runtime skeleton: parents before children, immutable.")
      .def(py::init([](const dq::RawSkeleton& raw) { return unwrap(dq::build_skeleton(raw)); }), py::arg("raw"),
           "build_skeleton(raw); raises ReadError naming the joint when invalid.")
      .def("__len__", &dq::Skeleton::size)
      .def("size", &dq::Skeleton::size)
      .def_property_readonly("parents", [](const dq::Skeleton& s) {
        return read_only(py::array_t<int>(static_cast<py::ssize_t>(s.size()), s.parents().data()));
      }, "(J,) parent of each joint, −1 for a root (read-only).")
      .def_property_readonly("names", [](const dq::Skeleton& s) { return std::vector<std::string>(s.names().begin(), s.names().end()); })
      .def_property_readonly("rest_pose", [](const dq::Skeleton& s) {
        return read_only(dual_quaternions_to_numpy(s.rest_pose(), {static_cast<py::ssize_t>(s.size()), 8}));
      }, "(J, 8) local rest transforms (read-only).")
      .def("is_end_site", [](const dq::Skeleton& s, py::ssize_t j) { return s.is_end_site(joint_index(s, j)); }, py::arg("j"),
           "Whether joint j is a leaf without animation channels (a BVH End Site).")
      .def("find", &dq::Skeleton::find, py::arg("name"), "The joint's index, or −1 (as str.find; index() raises instead).")
      .def("index", [](const dq::Skeleton& s, const std::string& name) {
        const int j = s.find(name);
        if (j < 0) throw py::key_error("no joint named '" + name + "' (the names are in Skeleton.names)");
        return j;
      }, py::arg("name"), "The joint's index; KeyError if there is none (safe as a NumPy index, where −1 is the last joint).")
      .def("__contains__", [](const dq::Skeleton& s, const std::string& name) { return s.find(name) >= 0; }, py::arg("name"))
      .def("subtree_end", [](const dq::Skeleton& s, py::ssize_t j) { return s.subtree_end(joint_index(s, j)); }, py::arg("j"),
           "One past the last joint of j's subtree.")
      .def("__repr__", [](const dq::Skeleton& s) { return "Skeleton(" + std::to_string(s.size()) + " joints)"; });
  m.def("build_skeleton", [](const dq::RawSkeleton& raw) { return unwrap(dq::build_skeleton(raw)); }, py::arg("raw"),
        "The runtime Skeleton of a RawSkeleton (parents before children); ReadError naming the joint when invalid.");

  Enum<dq::Interpolation>(m, "Interpolation")
      .value("screw", dq::Interpolation::screw)
      .value("dual_quaternion_linear", dq::Interpolation::dual_quaternion_linear)
      .value("decoupled", dq::Interpolation::decoupled)
      .value("matrix", dq::Interpolation::matrix);
  Enum<dq::WrapMode>(m, "WrapMode").value("clamp", dq::WrapMode::clamp).value("loop", dq::WrapMode::loop);
  py::class_<dq::Animation>(m, "Animation", "Local joint transforms per frame, frame-major.")
      .def(py::init([](py::handle locals, double frame_time) {
             auto a = as_float64(locals, {-1, -1, 8}, "locals", {"F", "J"});
             dq::Animation anim;
             anim.frame_time = frame_time_checked(frame_time);
             anim.frame_count = static_cast<std::size_t>(a.shape(0));
             anim.joint_count = static_cast<std::size_t>(a.shape(1));
             anim.locals = dual_quaternions_from_numpy(a.reshape({a.shape(0) * a.shape(1), py::ssize_t{8}}), "locals");
             return anim;
           }),
           py::arg("locals"), py::arg("frame_time"))
      .def_property("frame_time", [](const dq::Animation& a) { return a.frame_time; },
                    [](dq::Animation& a, double t) { a.frame_time = frame_time_checked(t); }, "Seconds per frame (positive).")
      .def_readonly("frame_count", &dq::Animation::frame_count)
      .def_readonly("joint_count", &dq::Animation::joint_count)
      .def("duration", &dq::Animation::duration)
      .def_property_readonly("locals", [](const dq::Animation& a) {
        return read_only(
            dual_quaternions_to_numpy(a.locals, {static_cast<py::ssize_t>(a.frame_count), static_cast<py::ssize_t>(a.joint_count), 8}));
      }, "(F, J, 8) local transforms (a read-only copy; make a new Animation to change them).")
      .def("__repr__", [](const dq::Animation& a) {
        return "Animation(" + std::to_string(a.frame_count) + " frames, " + std::to_string(a.joint_count) + " joints)";
      });
  m.def("sample", [](const dq::Animation& anim, double time, dq::Interpolation mode, dq::WrapMode wrap) {
          std::vector<DQd> out(anim.joint_count);
          dq::sample<double>(anim, time, mode, wrap, out);
          return dual_quaternions_to_numpy(out, {static_cast<py::ssize_t>(out.size()), 8});
        },
        py::arg("animation"), py::arg("time"), py::arg("mode") = dq::Interpolation::screw, py::arg("wrap") = dq::WrapMode::clamp,
        "(J, 8) local transforms at `time` seconds.");
  m.def("interpolate", [](const DQd& a, const DQd& b, double u, dq::Interpolation mode) { return dq::interpolate(a, b, u, mode); },
        py::arg("a"), py::arg("b"), py::arg("u"), py::arg("mode"),
        "Between two keys at fraction u, as the Interpolation says (screw: sclerp; dual_quaternion_linear: dlb; decoupled; matrix).");

  m.def("local_to_model", [](py::handle parents_obj, ArrayLike local, const IntegerArg& threads_obj) {
    const std::vector<int> parents = parents_of(parents_obj);
    const auto joints = std::to_string(parents.size());
    const unsigned threads = thread_count(threads_obj, std::numeric_limits<unsigned>::max());
    return with_dtype(call_dtype(local, "local"), [&]<class T>() -> py::array {
      const BatchInput in = batch_input(local, {"F", "J", "8"}, dtype_of_v<T>, "local", true);
      const py::ssize_t j_axis = in.array.ndim() - 2;
      if (static_cast<std::size_t>(in.array.shape(j_axis)) != parents.size())
        throw py::value_error("local: expected shape (F, " + joints + ", 8) or (" + joints + ", 8) for a skeleton of " + joints +
                              " joints, got J = " + std::to_string(in.array.shape(j_axis)));
      std::vector<py::ssize_t> shape(in.array.shape(), in.array.shape() + in.array.ndim());
      py::array_t<T> out(shape);
      const std::size_t frames = in.single ? 1 : static_cast<std::size_t>(in.array.shape(0));
      const auto* x = as_values<dq::DualQuaternion<T>>(data_of<T>(in));
      auto* o = as_values<dq::DualQuaternion<T>>(out.mutable_data());
      const std::size_t n = parents.size();
      py::gil_scoped_release release;
      // Frames on the vector lanes, float32 and float64 (validated above: parents_of, the shape); on
      // oneTBB's workers unless threads == 1.
      const dq::Status s = dq::simd::local_to_model_frames_parallel(parents, std::span(x, frames * n), std::span(o, frames * n), threads);
      if (!s) throw std::logic_error("local_to_model: " + s.error().message);
      return out;
    });
  }, py::arg("skeleton"), py::arg("local"), py::arg("threads") = 1,
     "Forward kinematics: model[j] = model[parent(j)] · local[j] for (F, J, 8) or (J, 8) local poses; "
     "`skeleton` is a Skeleton or the (J,) parents. threads: 1 (this thread), n, or 0 (every hardware thread); "
     "the result is the same bit for bit.");
}

void bind_files(py::module_& m) {
  Enum<dq::BvhChannel>(m, "BvhChannel")
      .value("Xposition", dq::BvhChannel::Xposition).value("Yposition", dq::BvhChannel::Yposition)
      .value("Zposition", dq::BvhChannel::Zposition).value("Xrotation", dq::BvhChannel::Xrotation)
      .value("Yrotation", dq::BvhChannel::Yrotation).value("Zrotation", dq::BvhChannel::Zrotation);
  py::class_<dq::BvhJoint>(m, "BvhJoint")
      .def_readonly("name", &dq::BvhJoint::name)
      .def_readonly("parent", &dq::BvhJoint::parent)
      .def_readonly("offset", &dq::BvhJoint::offset)
      .def_readonly("channels", &dq::BvhJoint::channels)
      .def_readonly("end_site", &dq::BvhJoint::end_site)
      .def_readonly("first_channel", &dq::BvhJoint::first_channel)
      .def("__repr__", [](const dq::BvhJoint& j) { return "BvhJoint('" + j.name + "', parent=" + std::to_string(j.parent) + ")"; });
  py::class_<dq::BvhFile>(m, "BvhFile", "A BVH file as written: hierarchy, channels and the motion values (degrees).")
      .def_readonly("joints", &dq::BvhFile::joints)
      .def_readonly("frame_count", &dq::BvhFile::frame_count)
      .def_readonly("frame_time", &dq::BvhFile::frame_time)
      .def_readonly("warnings", &dq::BvhFile::warnings)
      .def("channel_count", &dq::BvhFile::channel_count)
      .def_property("motion",
                    [](const dq::BvhFile& b) {
                      // Read-only, so that an element assignment (b.motion[0, 0] = 1) fails instead of changing a copy.
                      py::array_t<double> a({static_cast<py::ssize_t>(b.frame_count), static_cast<py::ssize_t>(b.channel_count())}, b.motion.data());
                      a.attr("setflags")(py::arg("write") = false);
                      return a;
                    },
                    [](dq::BvhFile& b, py::handle values) {
                      const auto a = as_float64(values, {static_cast<py::ssize_t>(b.frame_count), static_cast<py::ssize_t>(b.channel_count())}, "motion");
                      b.motion.assign(a.data(), a.data() + a.size());
                    },
                    "(frames, channels) values as in the file: a read-only copy; assign a whole array of the same shape to change them.")
      .def("__repr__", [](const dq::BvhFile& b) {
        return "BvhFile(" + std::to_string(b.joints.size()) + " joints, " + std::to_string(b.frame_count) + " frames)";
      });
  m.def("read_bvh_file", [](const std::filesystem::path& path) {
    require_existing(path);
    dq::Expected<dq::BvhFile> r = [&] { py::gil_scoped_release release; return dq::read_bvh_file(path); }();
    return unwrap(std::move(r));
  }, py::arg("path"), "Reads a BVH file; raises ReadError with 'file:line: what'.");
  m.def("read_bvh", [](const std::string& text, const std::string& source) { return unwrap(dq::read_bvh(text, source)); },
        py::arg("text"), py::arg("source") = "<bvh>", "Parses BVH text; errors name `source` and the line.");
  m.def("write_bvh", [](const dq::BvhFile& b) { return writable(dq::write_bvh(b)); }, py::arg("bvh"),
        "The BVH text; ValueError where it would not read back (a non-finite value, a bad name: the message says which).");
  m.def("write_bvh_file", [](const dq::BvhFile& b, const std::filesystem::path& path, bool overwrite) {
    const std::string text = writable(dq::write_bvh(b));
    check_written(dq::write_file_atomically(path, text, overwrite ? dq::Overwrite::allow : dq::Overwrite::refuse));
  }, py::arg("bvh"), py::arg("path"), py::arg("overwrite") = false,
        "Writes atomically; refuses an existing file unless overwrite (WriteError); ValueError as write_bvh.");
  m.def("with_rotation_order", [](const dq::BvhFile& b, dq::EulerOrder o) { return unwrap(dq::with_rotation_order(b, o)); },
        py::arg("bvh"), py::arg("order"),
        "The file with every joint's rotation channels in another order, each frame's rotations unchanged (to rounding).");
  m.def("bvh_skeleton", [](const dq::BvhFile& b) { return unwrap(dq::bvh_skeleton(b)); }, py::arg("bvh"),
        "The skeleton of a BVH file (its joint order, End Sites included).");
  m.def("bvh_animation", [](const dq::BvhFile& b, const dq::Skeleton& s) {
    if (!dq::is_skeleton_of(s, b))
      throw py::value_error("skeleton: not the skeleton of this BVH file (" + std::to_string(s.size()) + " joints against its " +
                            std::to_string(b.joints.size()) + ", or other names): use bvh_skeleton(bvh)");
    return dq::bvh_animation(b, s);
  }, py::arg("bvh"), py::arg("skeleton"), "Every frame's local transforms; `skeleton` is bvh_skeleton(bvh).");
  m.def("bvh_local_transform", [](const dq::BvhFile& b, py::ssize_t joint, py::ssize_t frame) {
    if (joint < 0 || static_cast<std::size_t>(joint) >= b.joints.size())
      throw py::index_error("joint " + std::to_string(joint) + " of a file of " + std::to_string(b.joints.size()) + " joints");
    if (frame < 0 || static_cast<std::size_t>(frame) >= b.frame_count)
      throw py::index_error("frame " + std::to_string(frame) + " of a file of " + std::to_string(b.frame_count) + " frames");
    return dq::bvh_local_transform(b, static_cast<std::size_t>(joint), static_cast<std::size_t>(frame));
  }, py::arg("bvh"), py::arg("joint"), py::arg("frame"), "The local transform of a joint (index into BvhFile.joints) in a frame.");
  m.def("to_bvh", [](const dq::Skeleton& s, const dq::Animation& a, dq::EulerOrder o) { return unwrap(dq::to_bvh(s, a, o)); },
        py::arg("skeleton"), py::arg("animation"), py::arg("order") = dq::EulerOrder::ZXY,
        "A BVH file of a skeleton and its animation (rotation channels in `order`); ValueError for another character's animation.");

  py::class_<dq::MotionOptions>(m, "MotionOptions")
      .def(py::init<>())
      .def_readwrite("animation", &dq::MotionOptions::animation)
      .def_readwrite("sample_rate", &dq::MotionOptions::sample_rate)
      .def_readwrite("import_timeout", &dq::MotionOptions::import_timeout)
      .def_readwrite("memory_limit_mb", &dq::MotionOptions::memory_limit_mb)
      .def_readwrite("lights_and_cameras", &dq::MotionOptions::lights_and_cameras);
  py::class_<dq::Motion>(m, "Motion", "A skeleton and its animation, from a BVH file or an imported model.")
      .def_readonly("format", &dq::Motion::format)
      .def_readonly("skeleton", &dq::Motion::skeleton)
      .def_readonly("animation", &dq::Motion::animation)
      .def_readonly("bvh", &dq::Motion::bvh)
      .def_readonly("animation_count", &dq::Motion::animation_count)
      .def_readonly("warnings", &dq::Motion::warnings);
  m.def("load_motion", [](const std::filesystem::path& path, const dq::MotionOptions& o) {
    require_existing(path);
    dq::Expected<dq::Motion> r = [&] { py::gil_scoped_release release; return dq::load_motion(path, o); }();
    return unwrap(std::move(r));
  }, py::arg("path"), py::arg("options") = dq::MotionOptions{}, "A BVH file's motion (other formats: import_motion).");
}

#ifdef DQKIT_PY_HAVE_IMPORT
void bind_import(py::module_& m) {
  py::class_<dq::ImportOptions>(m, "ImportOptions")
      .def(py::init<>())
      .def_readwrite("sample_rate", &dq::ImportOptions::sample_rate)
      .def_readwrite("meshes", &dq::ImportOptions::meshes)
      .def_readwrite("lights_and_cameras", &dq::ImportOptions::lights_and_cameras)
      .def_readwrite("isolate", &dq::ImportOptions::isolate)
      .def_readwrite("timeout_seconds", &dq::ImportOptions::timeout_seconds)
      .def_readwrite("cpu_limit_seconds", &dq::ImportOptions::cpu_limit_seconds)
      .def_readwrite("memory_limit_mb", &dq::ImportOptions::memory_limit_mb)
      .def_readwrite("result_limit_mb", &dq::ImportOptions::result_limit_mb)
      .def_property("worker_path", [](const dq::ImportOptions& o) { return o.worker_path.string(); },
                    [](dq::ImportOptions& o, const std::filesystem::path& p) { o.worker_path = p; });
  py::class_<dq::ImportedMesh>(m, "ImportedMesh")
      .def_readonly("name", &dq::ImportedMesh::name)
      .def_property_readonly("positions", [](const dq::ImportedMesh& me) {
        return read_only(py::array_t<float>({static_cast<py::ssize_t>(me.positions.size()), py::ssize_t{3}}, &me.positions.data()->x));
      }, "(V, 3) float32 bind-pose positions (a read-only copy).")
      .def_property_readonly("triangles", [](const dq::ImportedMesh& me) {
        return read_only(py::array_t<std::uint32_t>({static_cast<py::ssize_t>(me.indices.size() / 3), py::ssize_t{3}}, me.indices.data()));
      }, "(T, 3) vertex indices (a read-only copy).")
      .def_readonly("bone_joints", &dq::ImportedMesh::bone_joints)
      .def_readonly("node_joint", &dq::ImportedMesh::node_joint);
  py::class_<dq::ImportedAnimation>(m, "ImportedAnimation")
      .def_readonly("name", &dq::ImportedAnimation::name)
      .def_readonly("animation", &dq::ImportedAnimation::animation);
  py::class_<dq::ImportedScene>(m, "ImportedScene", "A model through Assimp: skeleton (every node), meshes and skins, animations.")
      .def_readonly("skeleton", &dq::ImportedScene::skeleton)
      .def_readonly("joint_scale", &dq::ImportedScene::joint_scale)
      .def_readonly("meshes", &dq::ImportedScene::meshes)
      .def_readonly("animations", &dq::ImportedScene::animations)
      .def_readonly("warnings", &dq::ImportedScene::warnings);
  // Imports run in the spawned dqkit-import-worker (posix_spawn, never a fork of the interpreter);
  // the package points DQKIT_IMPORT_WORKER at its own copy (dqkit/__init__.py).
  m.def("import_scene", [](const std::filesystem::path& path, const dq::ImportOptions& o) {
    require_existing(path);
    dq::Expected<dq::ImportedScene> r = [&] { py::gil_scoped_release release; return dq::import_scene(path, o); }();
    return unwrap(std::move(r));
  }, py::arg("path"), py::arg("options") = dq::ImportOptions{}, "Imports a model (glTF, FBX, Collada, X, ...) in the isolated worker.");
  m.def("import_motion", [](const std::filesystem::path& path, const dq::MotionOptions& o) {
    require_existing(path);
    dq::Expected<dq::Motion> r = [&] { py::gil_scoped_release release; return dq::import_motion(path, o); }();
    return unwrap(std::move(r));
  }, py::arg("path"), py::arg("options") = dq::MotionOptions{}, "The motion of any importable file (BVH through load_motion).");
  m.attr("HAVE_IMPORT") = true;
}
#endif

}  // namespace

void bind_anim(py::module_& m) {
  bind_skeleton(m);
}

void bind_io(py::module_& m) {
  bind_files(m);
#ifdef DQKIT_PY_HAVE_IMPORT
  bind_import(m);
#else
  m.attr("HAVE_IMPORT") = false;
#endif
}

}  // namespace dqpy
