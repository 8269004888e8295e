#include "dq/anim/skeleton.hpp"

#include <cmath>
#include <unordered_map>

namespace dq {

int Skeleton::find(std::string_view name) const noexcept {
  for (std::size_t j = 0; j < names_.size(); ++j)
    if (names_[j] == name) return static_cast<int>(j);
  return -1;
}

namespace {
bool finite(const DualQuaternion<double>& q) {
  for (double v : {q.real.w, q.real.x, q.real.y, q.real.z, q.dual.w, q.dual.x, q.dual.y, q.dual.z})
    if (!std::isfinite(v)) return false;
  return true;
}
std::string joint_label(const RawSkeleton& raw, std::size_t i) {
  const std::string& n = raw.joints[i].name;
  return "joint " + std::to_string(i) + (n.empty() ? std::string() : " '" + n + "'");
}
}  // namespace

Expected<Skeleton> build_skeleton(const RawSkeleton& raw) {
  const std::size_t n = raw.joints.size();
  std::unordered_map<std::string, std::size_t> seen;
  std::vector<std::vector<int>> children(n);
  std::vector<int> roots;
  for (std::size_t i = 0; i < n; ++i) {
    const RawSkeleton::Joint& j = raw.joints[i];
    if (j.name.empty()) return Error{joint_label(raw, i) + ": empty name"};
    if (auto [it, inserted] = seen.emplace(j.name, i); !inserted)
      return Error{joint_label(raw, i) + ": duplicate name (also joint " + std::to_string(it->second) + ")"};
    if (j.parent < -1 || j.parent >= static_cast<int>(n) || j.parent == static_cast<int>(i))
      return Error{joint_label(raw, i) + ": parent index " + std::to_string(j.parent) + " out of range [-1, " +
                   std::to_string(n) + ") or itself"};
    if (!finite(j.rest)) return Error{joint_label(raw, i) + ": rest transform is not finite"};
    if (!j.rest.is_unit(1e-6)) return Error{joint_label(raw, i) + ": rest transform is not a unit dual quaternion"};
    if (j.parent < 0) {
      roots.push_back(static_cast<int>(i));
    } else {
      children[static_cast<std::size_t>(j.parent)].push_back(static_cast<int>(i));
    }
  }
  // Depth-first from the roots; joints never reached are on a cycle.
  Skeleton s;
  s.parents_.reserve(n);
  std::vector<int> runtime_of(n, -1);
  std::vector<std::pair<int, int>> stack;  // (raw index, runtime parent)
  for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.emplace_back(*r, -1);
  while (!stack.empty()) {
    const auto [raw_index, parent] = stack.back();
    stack.pop_back();
    const std::size_t ri = static_cast<std::size_t>(raw_index);
    runtime_of[ri] = static_cast<int>(s.parents_.size());
    s.parents_.push_back(parent);
    s.names_.push_back(raw.joints[ri].name);
    s.rest_.push_back(raw.joints[ri].rest);
    s.end_site_.push_back(raw.joints[ri].is_end_site ? 1 : 0);
    s.raw_index_.push_back(raw_index);
    const auto& kids = children[ri];
    for (auto c = kids.rbegin(); c != kids.rend(); ++c) stack.emplace_back(*c, runtime_of[ri]);
  }
  for (std::size_t i = 0; i < n; ++i)
    if (runtime_of[i] < 0) return Error{joint_label(raw, i) + ": part of a parent cycle (not reachable from a root)"};
  // Subtree ranges, from the leaves up: in depth-first order the subtree of j is [j, end), where
  // `end` is the first later joint whose parent lies before j; a joint whose parent is in the
  // range is a child of it, and its own subtree is skipped whole.
  s.subtree_end_.assign(s.parents_.size(), s.parents_.size());
  for (std::size_t j = s.parents_.size(); j-- > 0;) {
    std::size_t end = j + 1;
    while (end < s.parents_.size() && s.parents_[end] >= static_cast<int>(j)) end = s.subtree_end_[end];
    s.subtree_end_[j] = end;
  }
  return s;
}

}  // namespace dq
