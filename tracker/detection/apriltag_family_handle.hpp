#pragma once
#include <string>
#include <vector>

struct apriltag_family;

namespace arphys::tracking {

// Owns one libapriltag family instance (apriltag says: one instance per detector).
class AprilTagFamilyHandle {
 public:
  // Throws std::invalid_argument naming the family and the known ones when unknown.
  explicit AprilTagFamilyHandle(const std::string& name);
  ~AprilTagFamilyHandle();
  AprilTagFamilyHandle(const AprilTagFamilyHandle&) = delete;
  AprilTagFamilyHandle& operator=(const AprilTagFamilyHandle&) = delete;
  AprilTagFamilyHandle(AprilTagFamilyHandle&& other) noexcept;

  apriltag_family* get() const { return family_; }
  const std::string& name() const { return name_; }

  static std::vector<std::string> names();

 private:
  std::string name_;
  apriltag_family* family_ = nullptr;
  void (*destroy_)(apriltag_family*) = nullptr;
};

}  // namespace arphys::tracking
