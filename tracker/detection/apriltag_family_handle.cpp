#include "tracker/detection/apriltag_family_handle.hpp"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h10.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagCircle49h12.h>
#include <apriltag/tagCustom48h12.h>
#include <apriltag/tagStandard41h12.h>
#include <apriltag/tagStandard52h13.h>

#include <stdexcept>

namespace arphys::tracking {

namespace {

struct FamilyEntry {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

const FamilyEntry kFamilies[] = {
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tag36h10", tag36h10_create, tag36h10_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
    {"tagCircle49h12", tagCircle49h12_create, tagCircle49h12_destroy},
    {"tagCustom48h12", tagCustom48h12_create, tagCustom48h12_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
    {"tagStandard52h13", tagStandard52h13_create, tagStandard52h13_destroy},
};

}  // namespace

AprilTagFamilyHandle::AprilTagFamilyHandle(const std::string& name) : name_(name) {
  for (const auto& entry : kFamilies) {
    if (name == entry.name) {
      family_ = entry.create();
      destroy_ = entry.destroy;
      // Debian loads the large families' codes from /usr/share/apriltag at run time.
      if (!family_) throw std::runtime_error("libapriltag could not create family " + name);
      return;
    }
  }
  std::string known;
  for (const auto& entry : kFamilies) known += std::string(known.empty() ? "" : ", ") + entry.name;
  throw std::invalid_argument("unknown apriltag family '" + name + "' (expected one of " + known + ")");
}

AprilTagFamilyHandle::~AprilTagFamilyHandle() {
  if (family_) destroy_(family_);
}

AprilTagFamilyHandle::AprilTagFamilyHandle(AprilTagFamilyHandle&& other) noexcept
    : name_(std::move(other.name_)), family_(other.family_), destroy_(other.destroy_) {
  other.family_ = nullptr;
}

std::vector<std::string> AprilTagFamilyHandle::names() {
  std::vector<std::string> names;
  for (const auto& entry : kFamilies) names.push_back(entry.name);
  return names;
}

}  // namespace arphys::tracking
