// Inverse kinematics (dq::IkSolver over KinematicModel and IkTask) and skinning (Skin, SceneSkin,
// batch skinning of (V, 3) vertices).
#include <pthread.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <system_error>
#include <thread>

#include "common.hpp"
#include "dq/ik/kinematic_model.hpp"
#include "dq/ik/motion_capture.hpp"
#include "dq/ik/solver.hpp"
#include "dq/simd/batch.hpp"
#include "dq/skin/scene_skin.hpp"
#include "dq/skin/skin.hpp"
#include "dq/skin/skinning.hpp"

namespace dqpy {
namespace {

using DQd = dq::DualQuaternion<double>;
using Vd = dq::Vec3<double>;

/// A writable, contiguous float64 vector of `n` values, taken in place (IkSolver.solve writes q).
std::span<double> inout_vector(py::array& a, std::size_t n, const char* name) {
  if (!py::isinstance<py::array_t<double>>(a) || a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != n ||
      !(a.flags() & py::array::c_style) || !a.writeable())
    throw py::value_error(std::string(name) + ": expected a writable contiguous float64 array of shape (" + std::to_string(n) + ",)");
  return {static_cast<double*>(a.mutable_data()), n};
}

/// A writable, aligned, C-contiguous float32 array of shape (rows, 3), taken in place
/// (skin_vertices writes its rows; an unaligned one, np.frombuffer at an odd offset, is refused).
py::array_t<float> inout_rows(py::handle obj, std::size_t rows, const char* name) {
  if (py::isinstance<py::array_t<float>>(obj)) {
    auto a = py::reinterpret_borrow<py::array_t<float>>(obj);
    const bool aligned = py::detail::array_proxy(a.ptr())->flags & py::detail::npy_api::NPY_ARRAY_ALIGNED_;
    if (a.ndim() == 2 && static_cast<std::size_t>(a.shape(0)) == rows && a.shape(1) == 3 && (a.flags() & py::array::c_style) &&
        a.writeable() && aligned)
      return a;
  }
  throw py::value_error(std::string(name) + ": expected a writable, aligned, C-contiguous float32 array of shape (" + std::to_string(rows) +
                        ", 3), one row per vertex");
}

/// A worker's longest spin that Python may ask for: more is most likely seconds taken for microseconds.
constexpr std::size_t kMaxSpinMicroseconds = 1'000'000;
/// The most threads a Python SkinningThreads starts: each is a system thread, started at once.
constexpr unsigned kMaxPoolThreads = 1024;

/// Forks of this process so far, as seen by this process: a child counts one more than its parent
/// at the moment of the fork (a pthread_atfork handler; getpid() would be a system call per call,
/// 1.4 µs on the machine of docs/python.md).
std::atomic<unsigned long> forks{0};

/// The count of forks so far, the handler that counts them registered first (once).
unsigned long forks_so_far() {
  static const int registered = pthread_atfork(nullptr, nullptr, [] { forks.fetch_add(1); });
  if (registered != 0) throw std::runtime_error("SkinningThreads: cannot watch for forks (pthread_atfork: " + std::string(std::strerror(registered)) + ")");
  return forks.load();
}

/// dq::SkinningThreads for Python: its threads started once; `busy_` held while a job runs on it
/// (SkinningThreads::run is not reentrant, and Python threads may share a pool). A process forked
/// from the one that made it (multiprocessing's default on Linux) has none of its threads: there
/// the pool refuses to run, and is left undestroyed (joining threads that are not there would hang).
class SkinningPool {
 public:
  SkinningPool(unsigned threads, std::size_t min_part, unsigned spin)
      : pool_(std::make_unique<dq::SkinningThreads>(threads, min_part, spin)) {}
  ~SkinningPool() {
    if (forked()) (void)pool_.release();
  }
  SkinningPool(const SkinningPool&) = delete;
  SkinningPool& operator=(const SkinningPool&) = delete;
  unsigned size() const noexcept { return pool_->size(); }
  std::size_t min_part() const noexcept { return pool_->min_part(); }
  unsigned spin_microseconds() const noexcept { return pool_->worker_spin_microseconds(); }
  /// f(pool) while no other call runs on the pool. The caller has released the GIL, or holds it
  /// (SceneSkin.skin): a caller that holds `busy_` never waits for the GIL, so neither can deadlock.
  template <class F>
  dq::Status run(F f) {
    if (forked())
      throw std::runtime_error("SkinningThreads: made in another process (before a fork), which has its threads; make a new one here");
    std::lock_guard lock(busy_);
    return f(*pool_);
  }

 private:
  bool forked() const noexcept { return forks.load(std::memory_order_relaxed) != forks_at_start_; }
  unsigned long forks_at_start_ = forks_so_far();  // before the threads start: a fork meanwhile is seen
  std::unique_ptr<dq::SkinningThreads> pool_;
  std::mutex busy_;
};

void bind_ik_types(py::module_& m) {
  Enum<dq::DofType>(m, "DofType")
      .value("revolute", dq::DofType::revolute).value("prismatic", dq::DofType::prismatic)
      .value("ball", dq::DofType::ball).value("free", dq::DofType::free);
  py::class_<dq::Dof>(m, "Dof", "A degree of freedom of a joint (revolute/prismatic about an axis of any non-zero length, normalized by KinematicModel.build; ball: 3, free: 6 parameters).")
      .def(py::init([](int joint, dq::DofType type, const Vd& axis, std::string name) { return dq::Dof{joint, type, axis, std::move(name)}; }),
           py::arg("joint"), py::arg("type"), py::arg("axis") = Vd{1, 0, 0}, py::arg("name") = "")
      .def_readwrite("joint", &dq::Dof::joint).def_readwrite("type", &dq::Dof::type)
      .def_readwrite("axis", &dq::Dof::axis).def_readwrite("name", &dq::Dof::name);
  py::class_<dq::ParameterLimits>(m, "ParameterLimits")
      .def(py::init([](double lo, double hi) { return dq::ParameterLimits{lo, hi}; }), py::arg("lower"), py::arg("upper"))
      .def_readwrite("lower", &dq::ParameterLimits::lower).def_readwrite("upper", &dq::ParameterLimits::upper);
  py::class_<dq::KinematicModel>(m, "KinematicModel", "A skeleton with degrees of freedom and limits: the model IK solves over.")
      .def_static("build", [](const dq::Skeleton& s, std::vector<dq::Dof> dofs, std::vector<dq::ParameterLimits> limits) {
        return unwrap(dq::KinematicModel::build(s, std::move(dofs), std::move(limits)));
      }, py::arg("skeleton"), py::arg("dofs"), py::arg("limits") = std::vector<dq::ParameterLimits>{})
      .def_static("ball_joints", &dq::KinematicModel::ball_joints, py::arg("skeleton"), "Ball joints everywhere, free roots.")
      .def_static("biped", &dq::KinematicModel::biped, py::return_value_policy::copy, "The 16-link, 36-DOF biped.")
      .def_static("arm7", &dq::KinematicModel::arm7, py::return_value_policy::copy, "The 7-DOF arm of the IK benchmark.")
      .def_property_readonly("skeleton", &dq::KinematicModel::skeleton, py::return_value_policy::reference_internal)
      .def_property_readonly("dofs", [](const dq::KinematicModel& k) { return std::vector<dq::Dof>(k.dofs().begin(), k.dofs().end()); })
      .def("parameters", &dq::KinematicModel::parameters, "The number of parameters q.")
      .def_property_readonly("limits", [](const dq::KinematicModel& k) {
        return std::vector<dq::ParameterLimits>(k.limits().begin(), k.limits().end());
      })
      .def("find_parameter", &dq::KinematicModel::find_parameter, py::arg("name"))
      .def("within_limits", [](const dq::KinematicModel& k, py::handle q, double slack) {
        const auto a = as_float64(q, {static_cast<py::ssize_t>(k.parameters())}, "q");
        return k.within_limits(std::span(a.data(), k.parameters()), slack);
      }, py::arg("q"), py::arg("slack") = 0.0);
  m.def("model_transforms", [](const dq::KinematicModel& k, py::handle q) {
    const auto a = as_float64(q, {static_cast<py::ssize_t>(k.parameters())}, "q");
    std::vector<DQd> world(k.skeleton().size());
    dq::model_transforms<DQd, double>(k, std::span(a.data(), k.parameters()), world);
    return dual_quaternions_to_numpy(world, {static_cast<py::ssize_t>(world.size()), 8});
  }, py::arg("model"), py::arg("q"), "(J, 8) world transforms of the joints for parameters q.");

  Enum<dq::TaskKind>(m, "TaskKind")
      .value("position", dq::TaskKind::position).value("orientation", dq::TaskKind::orientation)
      .value("pose", dq::TaskKind::pose).value("aim", dq::TaskKind::aim).value("point_on_line", dq::TaskKind::point_on_line);
  py::class_<dq::IkTask>(m, "IkTask", "A goal for one effector joint, with a weight and a priority level.")
      .def(py::init<>())
      .def_readwrite("kind", &dq::IkTask::kind).def_readwrite("joint", &dq::IkTask::joint)
      .def_readwrite("point", &dq::IkTask::point).def_readwrite("target", &dq::IkTask::target)
      .def_readwrite("axis", &dq::IkTask::axis).def_readwrite("location", &dq::IkTask::location)
      .def_readwrite("weight", &dq::IkTask::weight).def_readwrite("priority", &dq::IkTask::priority)
      .def_static("reach", &dq::IkTask::reach, py::arg("joint"), py::arg("target"), py::arg("point") = Vd{})
      .def_static("frame", &dq::IkTask::frame, py::arg("joint"), py::arg("target"), py::arg("point") = Vd{})
      .def_static("rotation", &dq::IkTask::rotation, py::arg("joint"), py::arg("target"))
      .def_static("aim_at", &dq::IkTask::aim_at, py::arg("joint"), py::arg("local_axis"), py::arg("target"), py::arg("point") = Vd{})
      .def_static("onto_line", &dq::IkTask::onto_line, py::arg("joint"), py::arg("line_point"), py::arg("direction"), py::arg("point") = Vd{});
  Enum<dq::IkMethod>(m, "IkMethod")
      .value("levenberg_marquardt", dq::IkMethod::levenberg_marquardt)
      .value("newton", dq::IkMethod::newton)
      .value("gauss_seidel", dq::IkMethod::gauss_seidel);
  py::class_<dq::IkOptions>(m, "IkOptions")
      .def(py::init<>())
      .def_readwrite("method", &dq::IkOptions::method).def_readwrite("max_iterations", &dq::IkOptions::max_iterations)
      .def_readwrite("max_restarts", &dq::IkOptions::max_restarts)
      .def_readwrite("position_tolerance", &dq::IkOptions::position_tolerance)
      .def_readwrite("orientation_tolerance", &dq::IkOptions::orientation_tolerance)
      .def_readwrite("initial_damping", &dq::IkOptions::initial_damping).def_readwrite("rest_weight", &dq::IkOptions::rest_weight)
      .def_readwrite("seed", &dq::IkOptions::seed).def_readwrite("max_rows", &dq::IkOptions::max_rows);
  Enum<dq::IkStatus>(m, "IkStatus")
      .value("converged", dq::IkStatus::converged).value("unreachable", dq::IkStatus::unreachable)
      .value("iteration_limit", dq::IkStatus::iteration_limit).value("invalid_input", dq::IkStatus::invalid_input);
  py::class_<dq::IkResult>(m, "IkResult")
      .def_readonly("status", &dq::IkResult::status).def_readonly("iterations", &dq::IkResult::iterations)
      .def_readonly("restarts", &dq::IkResult::restarts).def_readonly("position_error", &dq::IkResult::position_error)
      .def_readonly("orientation_error", &dq::IkResult::orientation_error)
      .def_property_readonly("message", [](const dq::IkResult& r) { return std::string(r.message); })
      .def("__repr__", [](const dq::IkResult& r) {
        // Errors in %.3g: a converged solve's 1e-12 would print as 0.000000 in %f.
        char errors[96];
        std::snprintf(errors, sizeof errors, ", position_error=%.3g, orientation_error=%.3g", r.position_error, r.orientation_error);
        return "IkResult(status=" + py::str(py::cast(r.status)).cast<std::string>() + ", iterations=" + std::to_string(r.iterations) +
               errors + (*r.message ? ", message='" + std::string(r.message) + "'" : std::string()) + ")";
      });
  // A solver owns a workspace: solve() keeps the GIL, so one solver is safe from several threads
  // (one at a time); solvers of their own let threads solve in turn without sharing anything.
  py::class_<dq::IkSolver>(m, "IkSolver", "Damped least squares / Newton / Gauss-Seidel IK over dual quaternions.")
      .def(py::init<const dq::KinematicModel&, const dq::IkOptions&>(), py::arg("model"), py::arg("options") = dq::IkOptions{},
           py::keep_alive<1, 2>())
      .def("solve", [](dq::IkSolver& s, const std::vector<dq::IkTask>& tasks, py::array q, py::object rest) {
        const std::size_t n = s.model().parameters();
        const std::span<double> qs = inout_vector(q, n, "q");
        std::vector<double> r;
        if (!rest.is_none()) {
          const auto a = as_float64(rest, {static_cast<py::ssize_t>(n)}, "rest");
          r.assign(a.data(), a.data() + n);
        }
        // The GIL stays held: the solver's workspace (and q) must not be used by two threads at once.
        return s.solve(tasks, qs, r);
      }, py::arg("tasks"), py::arg("q"), py::arg("rest") = py::none(),
         "Solves in place: q (float64, shape (parameters,)) is the initial pose and receives the solution.")
      .def("set_free_parameters", [](dq::IkSolver& s, const std::vector<bool>& free) {
        if (!free.empty() && free.size() != s.model().parameters())
          throw py::value_error("set_free_parameters: expected no flags or " + std::to_string(s.model().parameters()));
        const std::vector<std::uint8_t> f(free.begin(), free.end());
        s.set_free_parameters(f);
      }, py::arg("free"))
      .def_property_readonly("model", &dq::IkSolver::model, py::return_value_policy::reference_internal);
}

void bind_motion_capture(py::module_& m) {
  py::class_<dq::BvhKinematics>(m, "BvhKinematics", "The channel model of a BVH file: a KinematicModel and each parameter's channel.")
      .def_readonly("model", &dq::BvhKinematics::model)
      .def_readonly("channel_of", &dq::BvhKinematics::channel_of)
      .def("to_parameters", [](const dq::BvhKinematics& k, py::handle frame) {
        const auto f = as_float64(frame, {-1}, "frame");
        py::array_t<double> q(static_cast<py::ssize_t>(k.channel_of.size()));
        const std::size_t channels = k.channel_of.size();  // every channel of the file is a parameter
        if (static_cast<std::size_t>(f.shape(0)) != channels)
          throw py::value_error("frame: expected the file's " + std::to_string(channels) + " channel values, got " + std::to_string(f.shape(0)));
        k.to_parameters(std::span(f.data(), static_cast<std::size_t>(f.shape(0))), std::span(q.mutable_data(), k.channel_of.size()));
        return q;
      }, py::arg("frame"), "A frame's channel values (degrees, as in BvhFile.motion[f]) as model parameters (radians).");
  m.def("bvh_kinematics", [](const dq::BvhFile& b) { return unwrap(dq::bvh_kinematics(b)); }, py::arg("bvh"),
        "The channel model of a BVH file: one model parameter per channel (IK over the file's own channels).");
  py::class_<dq::FixFeetOptions>(m, "FixFeetOptions")
      .def(py::init<>())
      .def_readwrite("feet", &dq::FixFeetOptions::feet).def_readwrite("height", &dq::FixFeetOptions::height)
      .def_readwrite("speed", &dq::FixFeetOptions::speed)
      .def_readwrite("min_contact_frames", &dq::FixFeetOptions::min_contact_frames)
      .def_readwrite("merge_gap_frames", &dq::FixFeetOptions::merge_gap_frames)
      .def_readwrite("blend_frames", &dq::FixFeetOptions::blend_frames);
  py::class_<dq::FootContactReport>(m, "FootContactReport")
      .def_readonly("joint", &dq::FootContactReport::joint).def_readonly("contacts", &dq::FootContactReport::contacts)
      .def_readonly("slide_before", &dq::FootContactReport::slide_before).def_readonly("slide_after", &dq::FootContactReport::slide_after);
  py::class_<dq::FixFeetReport>(m, "FixFeetReport")
      .def_readonly("feet", &dq::FixFeetReport::feet).def_readonly("leg_joints", &dq::FixFeetReport::leg_joints)
      .def_readonly("max_other_joint_motion", &dq::FixFeetReport::max_other_joint_motion)
      .def_readonly("max_pin_error", &dq::FixFeetReport::max_pin_error)
      .def_readonly("unconverged_frames", &dq::FixFeetReport::unconverged_frames);
  m.def("fix_foot_sliding", [](dq::BvhFile& b, const dq::FixFeetOptions& o) { return unwrap(dq::fix_foot_sliding(b, o)); },
        py::arg("bvh"), py::arg("options") = dq::FixFeetOptions{}, "Removes foot sliding in place (only the leg channels change).");
}

void bind_skin_types(py::module_& m) {
  Enum<dq::SkinningMethod>(m, "SkinningMethod", "Linear blend, dual quaternion, or centre-of-rotation skinning.")
      .value("lbs", dq::SkinningMethod::lbs).value("dqs", dq::SkinningMethod::dqs).value("cor", dq::SkinningMethod::cor);
  Enum<dq::WeightPolicy>(m, "WeightPolicy").value("normalize", dq::WeightPolicy::normalize).value("reject", dq::WeightPolicy::reject);
  py::class_<dq::SkinOptions>(m, "SkinOptions")
      .def(py::init<>())
      .def_readwrite("weights", &dq::SkinOptions::weights)
      .def_readwrite("weight_tolerance", &dq::SkinOptions::weight_tolerance)
      .def_readwrite("centers_of_rotation", &dq::SkinOptions::centers_of_rotation)
      .def_readwrite("cor_sigma", &dq::SkinOptions::cor_sigma);
  py::class_<dq::Skin>(m, "Skin", "A validated skin: vertices, influences and the bones' bind transforms.")
      .def_property_readonly("vertex_count", &dq::Skin::vertex_count)
      .def_property_readonly("bone_count", &dq::Skin::bone_count)
      .def_property_readonly("renormalized_vertices", &dq::Skin::renormalized_vertices);
  m.def("build_skin", [](py::handle positions, py::handle bones, py::handle weights, py::handle inverse_bind, py::object triangles,
                         const dq::SkinOptions& options) {
    const auto p = as_float64(positions, {-1, 3}, "positions", {"V"});
    const auto w = as_float64(weights, {p.shape(0), -1}, "weights", {"K"});
    const auto b = as_integers(bones, 2, "bones: expected integers of shape (V, K), the shape of weights");
    if (b.shape(0) != w.shape(0) || b.shape(1) != w.shape(1))
      throw py::value_error("bones: expected integers of shape (V, K), the shape of weights (" + std::to_string(w.shape(0)) + ", " +
                            std::to_string(w.shape(1)) + "), got (" + std::to_string(b.shape(0)) + ", " + std::to_string(b.shape(1)) + ")");
    const auto ib = as_float64(inverse_bind, {-1, 4, 4}, "inverse_bind");
    dq::RawSkin raw;
    const auto vertices = static_cast<std::size_t>(p.shape(0)), slots = static_cast<std::size_t>(w.shape(1));
    for (std::size_t v = 0; v < vertices; ++v) {
      raw.positions.push_back({static_cast<float>(p.at(v, 0)), static_cast<float>(p.at(v, 1)), static_cast<float>(p.at(v, 2))});
      raw.influence_offsets.push_back(static_cast<std::uint32_t>(raw.influences.size()));
      for (std::size_t k = 0; k < slots; ++k) {
        const double wk = w.at(v, k);
        if (wk == 0) continue;
        const auto bone = b.at(v, k);
        if (bone < 0 || bone >= ib.shape(0))
          throw py::value_error("bones: vertex " + std::to_string(v) + " names bone " + std::to_string(bone) + " of " + std::to_string(ib.shape(0)));
        raw.influences.push_back({static_cast<std::uint32_t>(bone), static_cast<float>(wk)});
      }
    }
    raw.influence_offsets.push_back(static_cast<std::uint32_t>(raw.influences.size()));
    for (py::ssize_t i = 0; i < ib.shape(0); ++i) {
      dq::Mat4<double> mat;
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) mat(r, c) = ib.at(i, r, c);
      raw.inverse_bind.push_back(mat);
    }
    if (!triangles.is_none()) {
      const auto t = as_integers(triangles, 2, "triangles: expected vertex indices of shape (T, 3)");
      if (t.shape(1) != 3) throw py::value_error("triangles: expected vertex indices of shape (T, 3), got (" + std::to_string(t.shape(0)) + ", " + std::to_string(t.shape(1)) + ")");
      for (py::ssize_t i = 0; i < t.size(); ++i) {
        const std::int64_t v = t.data()[i];
        if (v < 0 || v >= p.shape(0))
          throw py::value_error("triangles: triangle " + std::to_string(i / 3) + " names vertex " + std::to_string(v) + " of " + std::to_string(p.shape(0)));
        raw.triangles.push_back(static_cast<std::uint32_t>(v));
      }
    }
    dq::SkinOptions o = options;
    if (raw.triangles.empty()) o.centers_of_rotation = false;
    return unwrap(dq::build_skin(raw, o));
  }, py::arg("positions"), py::arg("bones"), py::arg("weights"), py::arg("inverse_bind"), py::arg("triangles") = py::none(),
     py::arg("options") = dq::SkinOptions{},
     "A skin from (V, 3) positions, (V, K) bone indices and weights (zero weights ignored), (B, 4, 4) inverse bind matrices "
     "and optional (T, 3) triangles (needed for SkinningMethod.cor).");
  py::class_<SkinningPool>(m, "SkinningThreads",
                           "Threads for skinning, started once and kept for every call given this pool; one call at a time. "
                           "A call cuts its vertices into parts that the threads claim, of min_part vertices or more but the last, "
                           "so a call of at most min_part vertices runs on the calling thread alone. A worker watches for the "
                           "next call for spin_microseconds before it sleeps.")
      .def(py::init([](const IntegerArg& threads, const IntegerArg& min_part_obj, const std::optional<IntegerArg>& spin_obj) {
             const std::size_t min_part = size_count(min_part_obj, "min_part");
             const std::size_t spin = spin_obj ? size_count(*spin_obj, "spin_microseconds") : dq::SkinningThreads::kAutomaticWorkerSpin;
             if (spin_obj && spin > kMaxSpinMicroseconds)
               throw py::value_error("spin_microseconds: expected at most " + std::to_string(kMaxSpinMicroseconds) + " (one second), got " + std::to_string(spin));
             const unsigned n = thread_count(threads, kMaxPoolThreads);
             const unsigned total = n == 0 ? std::clamp(std::thread::hardware_concurrency(), 1u, kMaxPoolThreads) : n;
             try {
               return std::make_unique<SkinningPool>(total, min_part, static_cast<unsigned>(spin));
             } catch (const std::system_error& e) {
               throw std::runtime_error("SkinningThreads(" + std::to_string(total) + "): could not start a thread: " + e.what());
             }
           }),
           py::arg("threads"), py::arg("min_part") = IntegerArg{py::int_(dq::SkinningThreads::kDefaultMinPart)},
           py::arg("spin_microseconds") = py::none(),
           "threads: the total, the calling thread included (at most 1024); 0: every hardware thread. "
           "min_part: the fewest vertices in a part but the last, rounded up to a multiple of 16. "
           "spin_microseconds: how long a worker watches for the next call, using its core, before it sleeps "
           "(at most one second); None: 100 if the process may run on as many CPUs as the pool has threads, else 0.")
      .def_property_readonly("size", &SkinningPool::size, "Threads, the calling thread included.")
      .def_property_readonly("min_part", &SkinningPool::min_part, "The fewest vertices in a part but the last (a multiple of 16).")
      .def_property_readonly("spin_microseconds", &SkinningPool::spin_microseconds, "How long a worker watches for the next call before it sleeps.")
      .def("__repr__", [](const SkinningPool& p) {
        return "SkinningThreads(" + std::to_string(p.size()) + ", min_part=" + std::to_string(p.min_part()) +
               ", spin_microseconds=" + std::to_string(p.spin_microseconds()) + ")";
      });
  m.def("skin_vertices", [](const dq::Skin& skin, py::handle bone_world, dq::SkinningMethod method, std::optional<SkinningPool*> pool,
                            py::handle out_obj) {
    const auto bw = dual_quaternions_from_numpy(bone_world, "bone_world");
    if (bw.size() != skin.bone_count())
      throw py::value_error("bone_world: expected shape (" + std::to_string(skin.bone_count()) + ", 8), one per bone");
    for (std::size_t b = 0; b < bw.size(); ++b)  // LBS would read a scaled one as a scale, DQS normalize it: refused
      if (!bw[b].is_unit(1e-4))                   // (float32 input rounds to about 1e-7)
        throw py::value_error("bone_world: bone " + std::to_string(b) + " is not a unit dual quaternion (a rigid transform); "
                              "normalize it first (dqkit.normalized)");
    if (method == dq::SkinningMethod::cor && !skin.has_centers())
      throw py::value_error("SkinningMethod.cor needs centres of rotation: build the skin with triangles");
    const std::size_t n = skin.vertex_count();
    // A new array, or the caller's, written in place (a frame's buffer reused: no allocation).
    auto out = out_obj.is_none() ? py::array_t<float>({static_cast<py::ssize_t>(n), py::ssize_t{3}}) : inout_rows(out_obj, n, "out");
    {
      py::gil_scoped_release release;
      dq::SkinPalette palette(skin.bone_count());
      dq::update_palette(skin, bw, palette);
      dq::SkinningJob job{&skin, &palette, method, {.positions = {out.mutable_data(), 3 * n}}, 0, n};  // written as rows
      if (pool) {
        check((*pool)->run([&](dq::SkinningThreads& threads) { return threads.run(job); }));  // validates first
      } else {
        check(job.validate());
        job.run();
      }
    }
    return out;
  }, py::arg("skin"), py::arg("bone_world"), py::arg("method") = dq::SkinningMethod::dqs, py::arg("pool") = py::none(),
     py::arg("out") = py::none(),
     "(V, 3) float32 skinned positions for (B, 8) bone world transforms; on `pool` (a SkinningThreads) if given, "
     "with the same result bit for bit. `out`: a writable, aligned, C-contiguous float32 (V, 3) array to write them into "
     "(and return) instead of a new one.");

  py::class_<dq::SkinnedFrame>(m, "SkinnedFrame")
      .def_property_readonly("positions", [](const dq::SkinnedFrame& f) {
        py::array_t<float> a({static_cast<py::ssize_t>(f.size()), py::ssize_t{3}});
        dq::simd::from_rows({f.px.data(), f.py.data(), f.pz.data()}, {as_values<dq::Vec3<float>>(a.mutable_data()), f.size()});
        return read_only(a);
      }, "(V, 3) float32 positions (a read-only copy).")
      .def_property_readonly("triangles", [](const dq::SkinnedFrame& f) {
        return read_only(py::array_t<std::uint32_t>({static_cast<py::ssize_t>(f.triangles.size() / 3), py::ssize_t{3}}, f.triangles.data()));
      }, "(T, 3) vertex indices (a read-only copy).");
  Enum<dq::MeshFormat>(m, "MeshFormat")
      .value("csv", dq::MeshFormat::csv).value("obj", dq::MeshFormat::obj).value("ply", dq::MeshFormat::ply).value("gltf", dq::MeshFormat::gltf);
  m.def("format_frame", [](const dq::SkinnedFrame& f, dq::MeshFormat fmt) { return unwrap(dq::format_frame(f, fmt)); },
        py::arg("frame"), py::arg("format"), "The frame as CSV, OBJ, PLY or glTF text.");
#ifdef DQKIT_PY_HAVE_IMPORT
  py::class_<dq::SceneSkin>(m, "SceneSkin", "Every skinned mesh of an imported scene.")
      .def_static("build", [](const dq::ImportedScene& s, const dq::SkinOptions& o) { return unwrap(dq::SceneSkin::build(s, o)); },
                  py::arg("scene"), py::arg("options") = dq::SkinOptions{})
      .def_property_readonly("vertex_count", &dq::SceneSkin::vertex_count)
      .def_property_readonly("joint_count", &dq::SceneSkin::joint_count)
      .def("skin", [](dq::SceneSkin& s, py::handle joint_world, dq::SkinningMethod method, std::optional<SkinningPool*> pool) {
        const auto jw = dual_quaternions_from_numpy(joint_world, "joint_world");
        if (jw.size() != s.joint_count())
          throw py::value_error("joint_world: expected shape (" + std::to_string(s.joint_count()) + ", 8), one per joint");
        dq::SkinnedFrame frame = s.make_frame();
        // The GIL stays held: skin() updates the scene skin's palettes, shared by every caller.
        if (pool) {
          check((*pool)->run([&](dq::SkinningThreads& threads) { return s.skin(jw, method, threads, frame); }));
        } else {
          dq::SkinningThreads one(1);
          check(s.skin(jw, method, one, frame));
        }
        return frame;
      }, py::arg("joint_world"), py::arg("method") = dq::SkinningMethod::dqs, py::arg("pool") = py::none(),
      "Skins every mesh with the (J, 8) joint world transforms, on `pool` (a SkinningThreads) if given.");
  m.def("pose_at", [](const dq::ImportedScene& s, std::size_t animation, double time) {
    std::vector<DQd> world;
    check(dq::pose_at(s, animation, time, world));
    return dual_quaternions_to_numpy(world, {static_cast<py::ssize_t>(world.size()), 8});
  }, py::arg("scene"), py::arg("animation"), py::arg("time"), "(J, 8) world transforms of the scene's joints at `time` seconds.");
#endif
}

}  // namespace

void bind_ik(py::module_& m) {
  bind_ik_types(m);
  bind_motion_capture(m);
}
void bind_skin(py::module_& m) { bind_skin_types(m); }

}  // namespace dqpy
