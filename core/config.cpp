#include "core/config.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace aerograsp {
namespace {

std::string FormatNumber(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

std::string WithUnit(double v, const std::string& unit) {
  return unit.empty() ? FormatNumber(v) : FormatNumber(v) + " " + unit;
}

std::string TypeName(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "empty";
    case YAML::NodeType::Scalar:
      return "a scalar";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a map";
    default:
      return "undefined";
  }
}

[[noreturn]] void Throw(const std::string& source, const std::string& key,
                        const std::string& message) {
  throw ConfigError(source + ": " + (key.empty() ? "" : key + ": ") + message);
}

template <typename T>
T Convert(const YAML::Node& n, const std::string& source, const std::string& key,
          const char* expected) {
  if (!n.IsScalar())
    Throw(source, key, std::string("expected ") + expected + ", got " + TypeName(n));
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    Throw(source, key, std::string("expected ") + expected + ", got '" + n.Scalar() + "'");
  }
}

double ConvertDouble(const YAML::Node& n, const std::string& source, const std::string& key) {
  const double v = Convert<double>(n, source, key, "a number");
  if (!std::isfinite(v)) Throw(source, key, "expected a finite number, got '" + n.Scalar() + "'");
  return v;
}

constexpr std::size_t kMaxEntries = 1000000;  // keys and values in one file

/// Refuses a key given twice in one map (yaml-cpp would keep the first and
/// drop the second silently) and a key that is not a plain scalar, anywhere
/// in the tree below `node`. `budget` bounds the entries visited: aliases can
/// make a short file a huge tree.
void CheckKeys(const YAML::Node& node, const std::string& source, const std::string& prefix,
               std::size_t* budget) {
  if (*budget == 0) Throw(source, prefix, "too many entries (aliases nested too deep?)");
  --*budget;
  const auto line = [](const YAML::Node& n) { return std::to_string(n.Mark().line + 1); };
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      CheckKeys(node[i], source, prefix + "[" + std::to_string(i) + "]", budget);
    return;
  }
  if (!node.IsMap()) return;
  std::set<std::string> seen;
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) {
      Throw(source, prefix,
            "line " + line(kv.first) + ": a key must be a plain name, got " + TypeName(kv.first));
    }
    const std::string& key = kv.first.Scalar();
    const std::string path = prefix.empty() ? key : prefix + "." + key;
    if (!seen.insert(key).second)
      Throw(source, path, "line " + line(kv.first) + ": duplicate key (given twice in one map)");
    CheckKeys(kv.second, source, path, budget);
  }
}

}  // namespace

ConfigNode::ConfigNode(std::string source, std::string prefix, std::unique_ptr<YAML::Node> node)
    : source_(std::move(source)), prefix_(std::move(prefix)), node_(std::move(node)) {}

ConfigNode::~ConfigNode() = default;

ConfigNode::ConfigNode(const ConfigNode& other)
    : source_(other.source_),
      prefix_(other.prefix_),
      node_(std::make_unique<YAML::Node>(*other.node_)) {}

ConfigNode& ConfigNode::operator=(const ConfigNode& other) {
  if (this != &other) {
    source_ = other.source_;
    prefix_ = other.prefix_;
    node_ = std::make_unique<YAML::Node>(*other.node_);
  }
  return *this;
}

ConfigNode ConfigNode::LoadFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) Throw(path, "", "cannot open file");
  std::stringstream text;
  text << in.rdbuf();
  return Parse(text.str(), path);
}

ConfigNode ConfigNode::Parse(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    Throw(source, "",
          "not valid YAML at line " + std::to_string(e.mark.line + 1) + ", column " +
              std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  if (!root.IsMap())
    Throw(source, "", "expected a map of keys at the top level, got " + TypeName(root));
  std::size_t budget = kMaxEntries;
  CheckKeys(root, source, "", &budget);
  return ConfigNode(source, "", std::make_unique<YAML::Node>(root));
}

std::string ConfigNode::KeyPath(const std::string& key) const {
  return prefix_.empty() ? key : prefix_ + "." + key;
}

bool ConfigNode::Has(const std::string& key) const {
  const YAML::Node n = static_cast<const YAML::Node&>(*node_)[key];
  return n.IsDefined() && !n.IsNull();
}

std::vector<std::string> ConfigNode::Keys() const {
  std::vector<std::string> keys;
  for (const auto& kv : *node_) keys.push_back(kv.first.as<std::string>());
  return keys;
}

void ConfigNode::RequireOnlyKeys(const std::vector<std::string>& allowed) const {
  for (const std::string& k : Keys()) {
    bool known = false;
    for (const std::string& a : allowed) known = known || a == k;
    if (!known) {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      Throw(source_, KeyPath(k), "unknown key (expected one of: " + list + ")");
    }
  }
}

YAML::Node ConfigNode::Required(const std::string& key) const {
  const YAML::Node n = static_cast<const YAML::Node&>(*node_)[key];
  if (!n.IsDefined() || n.IsNull()) Throw(source_, KeyPath(key), "missing required key");
  return n;
}

ConfigNode ConfigNode::Child(const std::string& key) const {
  const YAML::Node n = Required(key);
  if (!n.IsMap()) Throw(source_, KeyPath(key), "expected a map, got " + TypeName(n));
  return ConfigNode(source_, KeyPath(key), std::make_unique<YAML::Node>(n));
}

double ConfigNode::GetDouble(const std::string& key) const {
  return ConvertDouble(Required(key), source_, KeyPath(key));
}

int ConfigNode::GetInt(const std::string& key) const {
  return Convert<int>(Required(key), source_, KeyPath(key), "an integer");
}

bool ConfigNode::GetBool(const std::string& key) const {
  return Convert<bool>(Required(key), source_, KeyPath(key), "true or false");
}

std::string ConfigNode::GetString(const std::string& key) const {
  return Convert<std::string>(Required(key), source_, KeyPath(key), "a string");
}

std::vector<double> ConfigNode::GetDoubles(const std::string& key,
                                           std::size_t expected_size) const {
  const YAML::Node n = Required(key);
  if (!n.IsSequence())
    Throw(source_, KeyPath(key), "expected a list of numbers, got " + TypeName(n));
  if (expected_size != 0 && n.size() != expected_size) {
    Throw(
        source_, KeyPath(key),
        "expected " + std::to_string(expected_size) + " numbers, got " + std::to_string(n.size()));
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < n.size(); ++i) {
    values.push_back(ConvertDouble(n[i], source_, KeyPath(key) + "[" + std::to_string(i) + "]"));
  }
  return values;
}

Eigen::Vector3d ConfigNode::GetVector3(const std::string& key) const {
  const std::vector<double> v = GetDoubles(key, 3);
  return {v[0], v[1], v[2]};
}

double ConfigNode::GetDouble(const std::string& key, double default_value) const {
  return Has(key) ? GetDouble(key) : default_value;
}

int ConfigNode::GetInt(const std::string& key, int default_value) const {
  return Has(key) ? GetInt(key) : default_value;
}

bool ConfigNode::GetBool(const std::string& key, bool default_value) const {
  return Has(key) ? GetBool(key) : default_value;
}

std::string ConfigNode::GetString(const std::string& key, const std::string& default_value) const {
  return Has(key) ? GetString(key) : default_value;
}

std::string ConfigNode::GetPath(const std::string& key) const {
  const std::filesystem::path p(GetString(key));
  if (p.is_absolute()) return p.lexically_normal().string();
  const std::filesystem::path folder = std::filesystem::path(source_).parent_path();
  return (folder / p).lexically_normal().string();
}

void ConfigNode::Fail(const std::string& key, const std::string& message) const {
  Throw(source_, KeyPath(key), message);
}

void CheckRange(const std::string& source, const std::string& key, const Eigen::Vector3d& v,
                double min, double max, const std::string& unit) {
  for (int i = 0; i < 3; ++i)
    CheckRange(source, key + "[" + std::to_string(i) + "]", v[i], min, max, unit);
}

void CheckRange(const std::string& source, const std::string& key, double value, double min,
                double max, const std::string& unit) {
  if (!std::isfinite(value)) Throw(source, key, "value is not finite");
  if (value < min) {
    Throw(source, key, WithUnit(value, unit) + " is below the lower bound " + WithUnit(min, unit));
  }
  if (value > max) {
    Throw(source, key, WithUnit(value, unit) + " is above the upper bound " + WithUnit(max, unit));
  }
}

void CheckFinite(const std::string& source, const std::string& key,
                 const std::vector<double>& values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      Throw(source, key + "[" + std::to_string(i) + "]",
            FormatNumber(values[i]) + " is not a finite number");
    }
  }
}

void CheckPositive(const std::string& source, const std::string& key, double value,
                   const std::string& unit) {
  if (!std::isfinite(value) || value <= 0.0) {
    Throw(source, key, WithUnit(value, unit) + " must be positive");
  }
}

void CheckOneOf(const std::string& source, const std::string& key, const std::string& value,
                const std::vector<std::string>& allowed) {
  std::string list;
  for (const std::string& a : allowed) {
    if (a == value) return;
    list += (list.empty() ? "" : ", ") + a;
  }
  Throw(source, key, "'" + value + "' is not one of: " + list);
}

void CheckFileExists(const std::string& source, const std::string& key, const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    Throw(source, key, "file '" + path + "' does not exist");
}

}  // namespace aerograsp
