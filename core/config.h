// YAML configuration access with errors a user can act on. Every message has
// the form "<file>: <key path>: <what is wrong>", e.g.
//   "data/config/platform_4dof.yaml: arms.left.home_rad[1]: -2.5 rad is below
//    the lower bound -1.745 rad".
// Config structs follow one pattern (STYLE.md): braced defaults with units in
// comments, a Load() that reads the file through ConfigNode, and a Validate()
// that checks every bound with CheckRange & co.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace aerograsp {

/// A configuration file (or value in it) that cannot be used.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A YAML map node that remembers its file and key path for error messages.
class ConfigNode {
 public:
  /// @throws ConfigError naming the path when it is missing, unreadable, not YAML
  /// (with the line and column), or its top level is not a map.
  static ConfigNode LoadFile(const std::string& path);
  /// Parses YAML text; `source` stands for the file name in messages.
  static ConfigNode Parse(const std::string& yaml_text, const std::string& source);

  ~ConfigNode();
  ConfigNode(const ConfigNode&);
  ConfigNode& operator=(const ConfigNode&);

  const std::string& source() const { return source_; }
  /// The dotted key path of `key` below this node, e.g. "arms.left.urdf".
  std::string KeyPath(const std::string& key) const;

  bool Has(const std::string& key) const;
  std::vector<std::string> Keys() const;
  /// @throws ConfigError naming every key of this map that is not in `allowed`
  /// (catches typos that would otherwise silently keep a default).
  void RequireOnlyKeys(const std::vector<std::string>& allowed) const;

  /// A child map. @throws ConfigError when missing or not a map.
  ConfigNode Child(const std::string& key) const;

  // Required values: @throws ConfigError when missing or of the wrong type.
  double GetDouble(const std::string& key) const;
  int GetInt(const std::string& key) const;
  bool GetBool(const std::string& key) const;
  std::string GetString(const std::string& key) const;
  /// A list of numbers; `expected_size` 0 accepts any length.
  std::vector<double> GetDoubles(const std::string& key, std::size_t expected_size = 0) const;
  Eigen::Vector3d GetVector3(const std::string& key) const;

  // Optional values: the default when the key is absent; type errors still throw.
  double GetDouble(const std::string& key, double default_value) const;
  int GetInt(const std::string& key, int default_value) const;
  bool GetBool(const std::string& key, bool default_value) const;
  std::string GetString(const std::string& key, const std::string& default_value) const;

  /// A path value resolved against the folder of the file it was read from.
  std::string GetPath(const std::string& key) const;

  /// @throws ConfigError "<source>: <key path>: <message>".
  [[noreturn]] void Fail(const std::string& key, const std::string& message) const;

 private:
  ConfigNode(std::string source, std::string prefix, std::unique_ptr<YAML::Node> node);
  YAML::Node Required(const std::string& key) const;

  std::string source_;
  std::string prefix_;  // key path of this node, "" at the top
  std::unique_ptr<YAML::Node> node_;
};

// Validation helpers for config structs' Validate(). `source` is the file, `key`
// the full key path; `unit` is printed after numbers ("m", "rad", "" for none).

/// @throws ConfigError unless min <= value <= max (and value is finite).
void CheckRange(const std::string& source, const std::string& key, double value, double min,
                double max, const std::string& unit);
/// Each component of `v` in [min, max], named "<key>[i]" when it is not.
void CheckRange(const std::string& source, const std::string& key, const Eigen::Vector3d& v,
                double min, double max, const std::string& unit);
/// @throws ConfigError "<source>: <key>[i]: nan is not a finite number" for the
/// first entry of `values` that is NaN or infinite.
void CheckFinite(const std::string& source, const std::string& key,
                 const std::vector<double>& values);
/// @throws ConfigError unless value > 0 (and finite).
void CheckPositive(const std::string& source, const std::string& key, double value,
                   const std::string& unit);
/// @throws ConfigError unless value is one of `allowed`.
void CheckOneOf(const std::string& source, const std::string& key, const std::string& value,
                const std::vector<std::string>& allowed);
/// @throws ConfigError unless the file exists.
void CheckFileExists(const std::string& source, const std::string& key, const std::string& path);

}  // namespace aerograsp
