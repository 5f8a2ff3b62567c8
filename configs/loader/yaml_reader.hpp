#pragma once
// The YAML reading every config loader shares: typed reads that fail with the file,
// line, key path, the bad value and what was expected (ConfigError).
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>

#include <Eigen/Core>

#include "configs/loader/config_error.hpp"
#include "configs/loader/scene_config.hpp"
#include "simulator/geometry/pose.hpp"

namespace arphys::config {

// Walks a YAML document keeping the key path and file for error messages.
class Reader {
 public:
  Reader(std::string file, std::filesystem::path base_dir) : file_(std::move(file)), base_dir_(std::move(base_dir)) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& problem) const {
    const int line = (node.IsDefined() && node.Mark().line >= 0) ? node.Mark().line + 1 : 0;
    throw ConfigError(file_, line, key, problem);
  }

  static std::string shown(const YAML::Node& node) {
    if (!node.IsDefined() || node.IsNull()) return "nothing";
    if (node.IsScalar()) return "'" + node.Scalar() + "'";
    if (node.IsSequence()) return node.size() == 0 ? "an empty list" : "a list of " + std::to_string(node.size());
    return "a map";
  }

  // Rejects keys the schema does not know: a typo must not silently become a default.
  void only_keys(const YAML::Node& map, const std::string& key, std::initializer_list<const char*> known) const {
    if (!map.IsMap()) fail(map, key, "got " + shown(map) + ", expected a map");
    std::set<std::string> allowed(known.begin(), known.end());
    for (const auto& entry : map) {
      const std::string name = key_name(entry.first, key);
      if (!allowed.count(name)) {
        std::string list;
        for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
        fail(entry.first, join(key, name), "unknown key (expected one of: " + list + ")");
      }
    }
  }

  // A map key as a plain name (YAML allows lists and maps as keys; no schema here does).
  std::string key_name(const YAML::Node& key_node, const std::string& parent) const {
    if (!key_node.IsScalar()) fail(key_node, parent, "a key is " + shown(key_node) + ", expected a plain name");
    return key_node.Scalar();
  }

  static std::string join(const std::string& parent, const std::string& child) {
    return parent.empty() ? child : parent + "." + child;
  }

  YAML::Node required(const YAML::Node& map, const std::string& parent, const char* name) const {
    YAML::Node node = map[name];
    if (!node.IsDefined() || node.IsNull()) fail(map, join(parent, name), "missing (required)");
    return node;
  }

  std::string string(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar() || node.Scalar().empty()) fail(node, key, "got " + shown(node) + ", expected a non-empty string");
    return node.Scalar();
  }

  double number(const YAML::Node& node, const std::string& key, const std::string& expected = "a number") const {
    double value = 0;
    if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value)) {
      fail(node, key, "got " + shown(node) + ", expected " + expected);
    }
    return value;
  }

  double positive(const YAML::Node& node, const std::string& key, const std::string& what) const {
    const double value = number(node, key, what);
    if (!(value > 0)) fail(node, key, "got " + node.Scalar() + ", expected " + what);
    return value;
  }

  int integer(const YAML::Node& node, const std::string& key, const std::string& expected) const {
    int value = 0;
    if (!node.IsScalar() || !YAML::convert<int>::decode(node, value)) {
      fail(node, key, "got " + shown(node) + ", expected " + expected);
    }
    return value;
  }

  Eigen::VectorXd vector(const YAML::Node& node, const std::string& key, int size, const std::string& what) const {
    if (!node.IsSequence() || static_cast<int>(node.size()) != size) {
      fail(node, key, "got " + shown(node) + ", expected a list of " + std::to_string(size) + " numbers (" + what + ")");
    }
    Eigen::VectorXd out(size);
    for (int i = 0; i < size; ++i) out[i] = number(node[i], key + "[" + std::to_string(i) + "]", what);
    return out;
  }

  geometry::Pose pose(const YAML::Node& node, const std::string& key) const {
    only_keys(node, key, {"position_m", "orientation_wxyz"});
    const Eigen::Vector3d p = vector(required(node, key, "position_m"), join(key, "position_m"), 3, "metres");
    const YAML::Node qn = required(node, key, "orientation_wxyz");
    const Eigen::Vector4d q = vector(qn, join(key, "orientation_wxyz"), 4, "a unit quaternion w, x, y, z");
    const double norm = q.norm();
    if (std::abs(norm - 1.0) > 1e-6) {
      std::ostringstream s;
      s << "quaternion (" << q.transpose() << ") has norm " << norm
        << ", expected a unit quaternion (|norm - 1| <= 1e-6; write at least 7 significant digits)";
      fail(qn, join(key, "orientation_wxyz"), s.str());
    }
    return geometry::make_pose(p, q, key);
  }

  std::string path(const YAML::Node& node, const std::string& key, const std::string& what) const {
    const std::string given = string(node, key);
    std::filesystem::path p(given);
    if (p.is_relative()) p = base_dir_ / p;
    p = p.lexically_normal();
    std::error_code error;  // a name too long for the file system is "not found", not a throw
    if (!std::filesystem::is_regular_file(p, error)) {
      fail(node, key, what + " '" + given + "' not found (looked for " + p.string() +
                          "; relative paths are relative to the scene file)");
    }
    return p.string();
  }

  ShapeConfig shape(const YAML::Node& node, const std::string& key) const {
    only_keys(node, key, {"shape", "size_m", "radius_m", "mesh", "pieces", "scale"});
    ShapeConfig out;
    const YAML::Node type_node = required(node, key, "shape");
    const std::string type = string(type_node, join(key, "shape"));
    const auto refuse = [&](const char* name, const std::string& shapes) {
      if (node[name].IsDefined())
        fail(node[name], join(key, name), "'" + std::string(name) + "' is a key of " + shapes + ", not of a " + type);
    };
    if (type != "mesh" && type != "convex_set") {
      refuse("mesh", "mesh and convex_set shapes");
      refuse("scale", "mesh and convex_set shapes");
    }
    if (type != "convex_set") refuse("pieces", "convex_set shapes");
    if (type == "plane") {
      out.type = ShapeType::kPlane;
    } else if (type == "box") {
      out.type = ShapeType::kBox;
      const YAML::Node size = required(node, key, "size_m");
      const std::string size_key = join(key, "size_m");
      const Eigen::Vector3d s = vector(size, size_key, 3, "side lengths in metres");
      for (int i = 0; i < 3; ++i) {
        if (!(s[i] > 0)) fail(size[i], size_key + "[" + std::to_string(i) + "]",
                              "got " + size[i].Scalar() + ", expected a positive length in metres");
      }
      out.size_m = s;
    } else if (type == "sphere") {
      out.type = ShapeType::kSphere;
      out.radius_m = positive(required(node, key, "radius_m"), join(key, "radius_m"), "a positive radius in metres");
    } else if (type == "mesh" || type == "convex_set") {
      if (type == "mesh") {
        out.type = ShapeType::kMesh;
        out.mesh_path = path(required(node, key, "mesh"), join(key, "mesh"), "mesh file");
      } else {
        out.type = ShapeType::kConvexSet;
        out.pieces_path = path(required(node, key, "pieces"), join(key, "pieces"), "convex-piece file");
        if (node["mesh"].IsDefined()) out.mesh_path = path(node["mesh"], join(key, "mesh"), "mesh file");
      }
      out.scale = scale_of(node, key);
    } else {
      fail(type_node, join(key, "shape"), "got '" + type + "', expected one of: plane, box, sphere, mesh, convex_set");
    }
    return out;
  }

  // A mesh's or convex set's `scale`: one positive factor or three.
  Eigen::Vector3d scale_of(const YAML::Node& node, const std::string& key) const {
    const YAML::Node scale = node["scale"];
    if (!scale.IsDefined()) return Eigen::Vector3d::Ones();
    const std::string scale_key = join(key, "scale");
    const Eigen::Vector3d out = scale.IsSequence()
                                    ? vector(scale, scale_key, 3, "positive scale factors")
                                    : Eigen::Vector3d::Constant(number(scale, scale_key, "a positive scale factor or a list of 3"));
    if (!(out.minCoeff() > 0)) fail(scale, scale_key, "got " + shown(scale) + ", expected positive scale factors");
    return out;
  }

 private:
  std::string file_;
  std::filesystem::path base_dir_;
};

}  // namespace arphys::config
