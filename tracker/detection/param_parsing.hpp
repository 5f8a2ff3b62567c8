#pragma once
#include <string>

namespace arphys::tracking {

// Text-to-value for detector parameters set by name (command line, tracker-control
// messages). Each throws std::invalid_argument naming the parameter, the text and
// the expected range.
double parse_param_double(const std::string& name, const std::string& text, double min_value, double max_value);
int parse_param_int(const std::string& name, const std::string& text, int min_value, int max_value);
bool parse_param_bool(const std::string& name, const std::string& text);

}  // namespace arphys::tracking
