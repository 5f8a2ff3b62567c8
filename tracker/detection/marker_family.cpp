#include "tracker/detection/marker_family.hpp"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h10.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagStandard41h12.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <stdexcept>

#include <opencv2/aruco.hpp>

#include "tracker/detection/apriltag_family_handle.hpp"

namespace arphys::tracking {

namespace {

const std::map<std::string, int>& aruco_dictionaries() {
  using namespace cv::aruco;
  static const std::map<std::string, int> table = {
      {"DICT_4X4_50", DICT_4X4_50},       {"DICT_4X4_100", DICT_4X4_100},
      {"DICT_4X4_250", DICT_4X4_250},     {"DICT_4X4_1000", DICT_4X4_1000},
      {"DICT_5X5_50", DICT_5X5_50},       {"DICT_5X5_100", DICT_5X5_100},
      {"DICT_5X5_250", DICT_5X5_250},     {"DICT_5X5_1000", DICT_5X5_1000},
      {"DICT_6X6_50", DICT_6X6_50},       {"DICT_6X6_100", DICT_6X6_100},
      {"DICT_6X6_250", DICT_6X6_250},     {"DICT_6X6_1000", DICT_6X6_1000},
      {"DICT_7X7_50", DICT_7X7_50},       {"DICT_7X7_100", DICT_7X7_100},
      {"DICT_7X7_250", DICT_7X7_250},     {"DICT_7X7_1000", DICT_7X7_1000},
      {"DICT_ARUCO_ORIGINAL", DICT_ARUCO_ORIGINAL},
      {"tag16h5", DICT_APRILTAG_16h5},    {"tag25h9", DICT_APRILTAG_25h9},
      {"tag36h10", DICT_APRILTAG_36h10},  {"tag36h11", DICT_APRILTAG_36h11},
  };
  return table;
}

// OpenCV's DICT_APRILTAG_* names are keyed by apriltag's family names.
std::string dictionary_key(const std::string& family) {
  return family.rfind("DICT_APRILTAG_", 0) == 0 ? "tag" + family.substr(14) : family;
}

}  // namespace

std::vector<std::string> apriltag_family_names() { return AprilTagFamilyHandle::names(); }

bool is_apriltag_family(const std::string& family) {
  const auto names = apriltag_family_names();
  return std::find(names.begin(), names.end(), family) != names.end();
}

bool has_aruco_dictionary(const std::string& family) { return aruco_dictionaries().count(dictionary_key(family)) > 0; }

int aruco_dictionary_id(const std::string& family) {
  if (!has_aruco_dictionary(family)) {
    throw std::invalid_argument("marker family '" + family +
                                "' is not an OpenCV ArUco dictionary (expected DICT_4X4_50 ... DICT_7X7_1000, "
                                "DICT_ARUCO_ORIGINAL, or tag16h5/tag25h9/tag36h10/tag36h11)");
  }
  return aruco_dictionaries().at(dictionary_key(family));
}

cv::Mat marker_cells_image(const std::string& family, int id, int* side_cells_black) {
  if (is_apriltag_family(family)) {
    AprilTagFamilyHandle handle(family);
    const apriltag_family_t* f = handle.get();
    if (id < 0 || id >= static_cast<int>(f->ncodes)) {
      throw std::invalid_argument("marker id " + std::to_string(id) + " is outside family " + family + " (0.." +
                                  std::to_string(f->ncodes - 1) + ")");
    }
    image_u8_t* im = apriltag_to_image(handle.get(), id);
    cv::Mat cells(im->height, im->width, CV_8UC1);
    for (int y = 0; y < im->height; ++y) {
      std::copy(im->buf + y * im->stride, im->buf + y * im->stride + im->width, cells.ptr<uint8_t>(y));
    }
    // image_u8_destroy lives in libapriltag-utils; the image is two malloc'd blocks.
    free(im->buf);
    free(im);
    if (side_cells_black) *side_cells_black = f->width_at_border;
    // apriltag's image already holds its quiet zone for the classic families
    // (total_width = width_at_border + 2); add one where it does not.
    const int margin = (f->total_width - f->width_at_border) / 2;
    if (margin < 1) cv::copyMakeBorder(cells, cells, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(255));
    return cells;
  }
  const int dictionary_id = aruco_dictionary_id(family);
  auto dictionary = cv::aruco::getPredefinedDictionary(dictionary_id);
  if (id < 0 || id >= dictionary->bytesList.rows) {
    throw std::invalid_argument("marker id " + std::to_string(id) + " is outside dictionary " + family);
  }
  const int black_cells = dictionary->markerSize + 2;
  cv::Mat cells;
  cv::aruco::drawMarker(dictionary, id, black_cells, cells, 1);
  cv::copyMakeBorder(cells, cells, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(255));
  if (side_cells_black) *side_cells_black = black_cells;
  return cells;
}

}  // namespace arphys::tracking
