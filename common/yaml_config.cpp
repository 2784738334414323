#include "common/yaml_config.h"

#include <fstream>
#include <sstream>

namespace cairn {

YamlConfig YamlConfig::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return from_string(ss.str(), path);
}

YamlConfig YamlConfig::from_string(const std::string& text, const std::string& name) {
  try {
    YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) throw InputError(name + ": expected a YAML map at the top level");
    return YamlConfig(root, name, "");
  } catch (const YAML::ParserException& e) {
    throw InputError(name + ": malformed YAML at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

std::string YamlConfig::key_name(const std::string& key) const {
  if (key_path_.empty()) return key;
  if (key.empty()) return key_path_;
  return key_path_ + "." + key;
}

void YamlConfig::fail(const std::string& key, const std::string& what) const {
  throw InputError(file_ + ": key '" + key_name(key) + "' " + what);
}

void YamlConfig::allow_only(std::initializer_list<const char*> allowed) const {
  if (!node_.IsMap()) return;
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar()) {  // e.g. "[k]: 1": a list or map where a name belongs
      throw InputError(file_ + ": " + (key_path_.empty() ? "the top level" : "key '" + key_path_ + "'") +
                       " has a key at line " + std::to_string(kv.first.Mark().line + 1) + " that is not a plain name");
    }
    const std::string key = kv.first.as<std::string>();
    bool known = false;
    std::string list;
    for (const char* a : allowed) {
      known = known || key == a;
      list += (list.empty() ? "" : ", ") + std::string(a);
    }
    if (!known) fail(key, "is not a known key (expected one of: " + list + ")");
  }
}

YamlConfig YamlConfig::operator[](const std::string& key) const {
  if (!has(key)) fail(key, "is missing");
  return YamlConfig(node_[key], file_, key_name(key));
}

std::vector<YamlConfig> YamlConfig::sequence(const std::string& key) const {
  if (!has(key)) fail(key, "is missing");
  const YAML::Node seq = node_[key];
  if (!seq.IsSequence()) fail(key, "must be a list");
  std::vector<YamlConfig> out;
  for (size_t i = 0; i < seq.size(); ++i) {
    out.emplace_back(seq[i], file_, key_name(key) + "[" + std::to_string(i) + "]");
  }
  return out;
}

std::vector<YamlConfig> YamlConfig::elements() const {
  if (!node_.IsSequence()) fail("", "must be a list");
  std::vector<YamlConfig> out;
  for (size_t i = 0; i < node_.size(); ++i) {
    out.emplace_back(node_[i], file_, key_path_ + "[" + std::to_string(i) + "]");
  }
  return out;
}

}  // namespace cairn
