// Skeletons: an editable raw skeleton (what importers produce) and the flat runtime skeleton the
// builder makes from it (validated, parents before children). Runtime code never parses files.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "dq/core/dual_quaternion.hpp"
#include "dq/util/expected.hpp"

namespace dq {

/// An editable joint tree, in any order: each joint names its parent by index (−1 for a root).
struct RawSkeleton {
  struct Joint {
    std::string name;
    int parent = -1;
    DualQuaternion<double> rest{};  ///< local rest transform (relative to the parent)
    bool is_end_site = false;       ///< a leaf with no animation channels (BVH "End Site")
  };
  std::vector<Joint> joints;

  /// Appends a joint and returns its index.
  int add(std::string name, int parent, const DualQuaternion<double>& rest = {}, bool end_site = false) {
    joints.push_back({std::move(name), parent, rest, end_site});
    return static_cast<int>(joints.size()) - 1;
  }
};

/// The runtime skeleton: flat arrays, parents before children (parent[j] < j), immutable.
class Skeleton {
 public:
  std::size_t size() const noexcept { return parents_.size(); }
  std::span<const int> parents() const noexcept { return parents_; }
  std::span<const std::string> names() const noexcept { return names_; }
  std::span<const DualQuaternion<double>> rest_pose() const noexcept { return rest_; }
  std::span<const std::uint8_t> end_sites() const noexcept { return end_site_; }
  bool is_end_site(std::size_t j) const noexcept { return end_site_[j] != 0; }
  /// Index of the joint with this name, or −1.
  int find(std::string_view name) const noexcept;
  /// For each runtime joint, the index it had in the raw skeleton.
  std::span<const int> raw_indices() const noexcept { return raw_index_; }
  /// One past the last joint of the subtree rooted at j (the subtree is the range [j, end)).
  std::size_t subtree_end(std::size_t j) const noexcept { return subtree_end_[j]; }

 private:
  friend Expected<Skeleton> build_skeleton(const RawSkeleton& raw);
  std::vector<int> parents_;
  std::vector<std::string> names_;
  std::vector<DualQuaternion<double>> rest_;
  std::vector<std::uint8_t> end_site_;
  std::vector<int> raw_index_;
  std::vector<std::size_t> subtree_end_;
};

/// Validates a raw skeleton and builds the runtime one, depth-first so that every subtree is a
/// contiguous range. Errors (each names the joint): empty or duplicate name, parent index out of
/// range, a cycle, non-finite rest transform, rest transform not unit (|q_r| − 1 or q_r · q_d
/// beyond 1e-6).
Expected<Skeleton> build_skeleton(const RawSkeleton& raw);

}  // namespace dq
