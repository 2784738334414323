#pragma once
// Reading YAML into options structs with errors that name the file and the key.
//   YamlConfig cfg = YamlConfig::load("worlds/office.yaml");
//   double v = cfg["robot"].get("max_speed_mps", 0.5);   // optional with default
//   int n = cfg["laser"].require<int>("beams");           // required
// Every failure throws InputError("worlds/office.yaml: key 'laser.beams': expected int ...").
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <vector>

#include "common/errors.h"

namespace cairn {

class YamlConfig {
 public:
  /// Parses a file; throws InputError naming the file (and line) when missing or malformed.
  static YamlConfig load(const std::string& path);
  static YamlConfig from_string(const std::string& text, const std::string& name);

  YamlConfig(YAML::Node node, std::string file, std::string key_path)
      : node_(std::move(node)), file_(std::move(file)), key_path_(std::move(key_path)) {}

  bool has(const std::string& key) const { return node_.IsMap() && node_[key].IsDefined(); }
  /// Child map; throws if absent (use has() for optional sections).
  YamlConfig operator[](const std::string& key) const;
  /// Elements of a sequence under `key`; throws if absent or not a sequence.
  std::vector<YamlConfig> sequence(const std::string& key) const;
  /// Elements when this node itself is a sequence.
  std::vector<YamlConfig> elements() const;

  template <typename T>
  T require(const std::string& key) const {
    if (!has(key)) fail(key, "is missing");
    return convert<T>(node_[key], key);
  }
  template <typename T>
  T get(const std::string& key, const T& default_value) const {
    return has(key) ? convert<T>(node_[key], key) : default_value;
  }
  /// This node's own value (for sequence elements).
  template <typename T>
  T as() const {
    return convert<T>(node_, "");
  }

  /// Throws for any key of this map not in `allowed`: a typo must never silently become a default.
  void allow_only(std::initializer_list<const char*> allowed) const;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  std::string key_name(const std::string& key) const;
  const std::string& file() const { return file_; }
  const YAML::Node& node() const { return node_; }

 private:
  template <typename T>
  T convert(const YAML::Node& n, const std::string& key) const {
    try {
      T v = n.as<T>();
      if constexpr (std::is_floating_point_v<T>) {
        if (!std::isfinite(v)) fail(key, "must be a finite number");
      }
      return v;
    } catch (const YAML::Exception&) {
      fail(key, std::string("has the wrong type (line ") + std::to_string(n.Mark().line + 1) + ")");
    }
  }

  YAML::Node node_;
  std::string file_;
  std::string key_path_;
};

}  // namespace cairn
