#include "ros2/ros2_config.h"

#include <cctype>

#include "core/config.h"

namespace aerograsp {

void Ros2Config::Validate() const {
  CheckRange(source, "ros2.domain_id", domain_id, 0, 232, "");
  const auto name_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '/';
  };
  for (const char c : topic_namespace) {
    if (!name_char(c)) {
      throw ConfigError(source + ": ros2.topic_namespace: '" + topic_namespace +
                        "' has a character that is not a letter, digit, '_' or '/'");
    }
  }
  if (!topic_namespace.empty() &&
      (topic_namespace.front() == '/' || topic_namespace.back() == '/' ||
       std::isdigit(static_cast<unsigned char>(topic_namespace.front())) ||
       topic_namespace.find("//") != std::string::npos)) {
    throw ConfigError(source + ": ros2.topic_namespace: '" + topic_namespace +
                      "' must not start with '/' or a digit, end with '/' or hold '//'");
  }
  CheckRange(source, "ros2.joint_states_rate_hz", joint_states_rate_hz, 1e-3, 1000, "Hz");
  CheckRange(source, "ros2.image_rate_hz", image_rate_hz, 0, 60, "Hz");
}

Ros2Config Ros2Config::Load(const std::string& path) {
  Ros2Config c;
  c.source = path;
  const ConfigNode root = ConfigNode::LoadFile(path);
  if (!root.Has("ros2")) {
    c.Validate();
    return c;
  }
  const ConfigNode node = root.Child("ros2");
  node.RequireOnlyKeys({"enabled", "domain_id", "topic_namespace", "dds_config",
                        "joint_states_rate_hz", "image_rate_hz", "publish_clock"});
  c.enabled = node.GetBool("enabled", c.enabled);
  c.domain_id = node.GetInt("domain_id", c.domain_id);
  c.topic_namespace = node.GetString("topic_namespace", c.topic_namespace);
  if (node.Has("dds_config") && !node.GetString("dds_config").empty()) {
    c.dds_config = node.GetPath("dds_config");
    CheckFileExists(path, "ros2.dds_config", c.dds_config);
  }
  c.joint_states_rate_hz = node.GetDouble("joint_states_rate_hz", c.joint_states_rate_hz);
  c.image_rate_hz = node.GetDouble("image_rate_hz", c.image_rate_hz);
  c.publish_clock = node.GetBool("publish_clock", c.publish_clock);
  c.Validate();
  return c;
}

}  // namespace aerograsp
