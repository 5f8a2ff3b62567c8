#pragma once
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace arphys::tracking {

// Marker families by name. apriltag's families are named as libapriltag names them
// ("tag36h11"); OpenCV's ArUco dictionaries by their enum name ("DICT_4X4_50").
// OpenCV's DICT_APRILTAG_36h11 (and 16h5, 25h9, 36h10) detect apriltag's families and
// report them under apriltag's names, so a scene declares its markers once.

// apriltag family names this build of libapriltag provides.
std::vector<std::string> apriltag_family_names();
bool is_apriltag_family(const std::string& family);

// The OpenCV predefined dictionary id for a family name (apriltag or DICT_* name);
// throws std::invalid_argument naming the family when OpenCV has none.
int aruco_dictionary_id(const std::string& family);
// Whether OpenCV has a dictionary for the family (aruco_dictionary_id does not throw).
bool has_aruco_dictionary(const std::string& family);

// The marker's image, one pixel per cell, 8-bit (0 black, 255 white), including a
// white quiet zone of one cell around the outer black border. side_cells_black
// receives the black square's side in cells (what a marker's size_m measures).
// Throws std::invalid_argument for an unknown family or an id outside it.
cv::Mat marker_cells_image(const std::string& family, int id, int* side_cells_black);

}  // namespace arphys::tracking
