// The Jacobian of a kinematic model in screw form: for every parameter, the twist it gives the
// joints below it, as the joint's screw axis in the world frame.
//
// A twist Ξ = (0, ω) + ε (0, v) holds the angular velocity ω and the velocity v of the point at the
// world origin; a point x of a moving body then moves at v + ω × x. For a unit dual quaternion Q
// of a joint moved by parameter q_i, the derivative is dQ/dq_i = ½ Ξ_i Q (docs/ik.md derives it):
// this is the "dual quaternion form" of the Jacobian, checked in the tests against Dual<T>
// forward-mode derivatives of forward kinematics and against finite differences.
//   revolute about world axis ω through point p:  Ξ = (ω, p × ω)
//   prismatic along world axis a:                  Ξ = (0, a)
//   ball with rotation vector r at frame F:        ω_k = R_F J_l(r) e_k, through F's origin, where
//                                                  J_l(r) = I + ((1 − cos θ)/θ²)[r]× + ((θ − sin θ)/θ³)[r]×²
//                                                  is the left Jacobian of SO(3) (θ = |r|)
#pragma once

#include <span>

#include "dq/core/series.hpp"
#include "dq/ik/kinematic_model.hpp"

namespace dq {

template <class T>
struct Twist {
  Vec3<T> angular{};  ///< ω
  Vec3<T> linear{};   ///< velocity of the point at the world origin
  /// Velocity of the world point x carried by this twist.
  constexpr Vec3<T> velocity_at(const Vec3<T>& x) const noexcept { return linear + cross(angular, x); }
  /// As a pure dual quaternion (0, ω) + ε (0, v).
  constexpr DualQuaternion<T> as_dual_quaternion() const noexcept {
    return {Quaternion<T>::pure(angular), Quaternion<T>::pure(linear)};
  }
};

namespace detail {
/// J_l(r) e_k for k = 0, 1, 2 (the columns of the left Jacobian of SO(3)).
template <class T>
std::array<Vec3<T>, 3> left_jacobian_columns(const Vec3<T>& r) {
  using std::sin;
  const T x = dot(r, r);
  auto theta = [&] { return norm(r); };
  // (1 − cos θ)/θ² = ½ sinc²(θ/2): no cancellation.
  const T half_sinc = sinc_of_squared(x / T(4), [&] { return theta() / T(2); });
  const T a = half_sinc * half_sinc / T(2);
  const T b = one_minus_sinc_over_squared(x, theta);
  std::array<Vec3<T>, 3> out{};
  for (int k = 0; k < 3; ++k) {
    Vec3<T> e{T(0), T(0), T(0)};
    e[k] = T(1);
    const Vec3<T> re = cross(r, e);
    out[static_cast<std::size_t>(k)] = e + re * a + cross(r, re) * b;
  }
  return out;
}
}  // namespace detail

/// Forward kinematics with the screw Jacobian: `world` gets every joint's model transform and
/// `columns` every parameter's twist (world frame); `frames`, if not empty, the world frame each
/// DOF acts in (before its own motion). Preconditions: q has model.parameters() values, world one
/// entry per joint, columns one per parameter, frames none or one per DOF.
template <class X, class T>
void screw_jacobian(const KinematicModel& model, std::span<const T> q, std::span<X> world, std::span<Twist<T>> columns,
                    std::span<X> frames = {}) {
  using Ops = TransformOps<X>;
  const std::size_t joints = model.skeleton().size();
  DQ_PRECONDITION(q.size() == model.parameters() && world.size() == joints && columns.size() == model.parameters(),
                  "screw_jacobian needs model.parameters() values and columns and one transform per joint");
  DQ_PRECONDITION(frames.empty() || frames.size() == model.dofs().size(), "screw_jacobian: frames must be empty or one per DOF");
  const auto parents = model.skeleton().parents();
  const auto dofs = model.dofs();
  for (std::size_t j = 0; j < joints; ++j) {
    X frame = Ops::from(model.skeleton().rest_pose()[j]);
    if (parents[j] >= 0) frame = world[static_cast<std::size_t>(parents[j])] * frame;
    for (std::size_t d = model.joint_dofs_begin(j); d < model.joint_dofs_begin(j + 1); ++d) {
      const Dof& dof = dofs[d];
      const T* p = q.data() + model.offset(d);
      if (!frames.empty()) frames[d] = frame;
      Twist<T>* col = columns.data() + model.offset(d);
      auto rotational = [&](const Vec3<T>& local_axis) {
        const Vec3<T> w = Ops::rotate(frame, local_axis);
        return Twist<T>{w, cross(Ops::origin(frame), w)};
      };
      auto ball = [&](const T* r) {
        const auto c = detail::left_jacobian_columns(Vec3<T>{r[0], r[1], r[2]});
        for (std::size_t k = 0; k < 3; ++k) col[k] = rotational(c[k]);
      };
      switch (dof.type) {
        case DofType::revolute: col[0] = rotational(detail::axis_as<T>(dof.axis)); break;
        case DofType::prismatic: col[0] = {{T(0), T(0), T(0)}, Ops::rotate(frame, detail::axis_as<T>(dof.axis))}; break;
        case DofType::ball: ball(p); break;
        case DofType::free:
          for (int k = 0; k < 3; ++k) {
            Vec3<T> e{T(0), T(0), T(0)};
            e[k] = T(1);
            col[k] = {{T(0), T(0), T(0)}, Ops::rotate(frame, e)};
          }
          frame = frame * Ops::translation({p[0], p[1], p[2]});
          col += 3;
          ball(p + 3);
          frame = Ops::rotated(frame, Quaternion<T>::from_rotation_vector({p[3], p[4], p[5]}));
          continue;
      }
      frame = then_dof(frame, dof, p);
    }
    world[j] = frame;
  }
}

/// Whether parameter i (of DOF d, at joint j) moves joint e: j is e or one of its ancestors.
inline bool moves(const KinematicModel& model, std::size_t dof, std::size_t joint) {
  const auto j = static_cast<std::size_t>(model.dofs()[dof].joint);
  return j <= joint && joint < model.skeleton().subtree_end(j);
}

}  // namespace dq
