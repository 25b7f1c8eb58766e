#include "app/calibration/hand_eye_samples.h"

#include <yaml-cpp/yaml.h>

#include <fstream>

#include "app/calibration/calibration_file.h"
#include "app/calibration/calibration_samples.h"
#include "core/config.h"
#include "core/transforms.h"

namespace aerograsp {

Side ParseSide(const std::string& arm) {
  if (arm == "left") return Side::kLeft;
  if (arm == "right") return Side::kRight;
  throw ConfigError("--arm: '" + arm + "' is not left or right");
}

void WriteSamplesYaml(const std::string& path, const std::string& platform_path, Side side,
                      const TagBoardConfig& board, const std::vector<WizardSample>& samples) {
  YAML::Emitter y;
  y.SetDoublePrecision(17);
  y << YAML::BeginMap;
  y << YAML::Key << "platform" << YAML::Value << platform_path;
  y << YAML::Key << "arm" << YAML::Value << SideName(side);
  y << YAML::Key << "board" << YAML::Value;
  EmitTagBoard(board, &y);
  y << YAML::Key << "samples" << YAML::Value << YAML::BeginSeq;
  for (const WizardSample& s : samples) {
    y << YAML::BeginMap;
    y << YAML::Key << "image" << YAML::Value << s.image;
    y << YAML::Key << "accepted" << YAML::Value << s.accepted;
    y << YAML::Key << "reject_reason" << YAML::Value << s.reject_reason;
    y << YAML::Key << "q_rad" << YAML::Value << YAML::Flow
      << std::vector<double>(s.q_rad.data(), s.q_rad.data() + s.q_rad.size());
    y << YAML::Key << "cMt" << YAML::Value << YAML::Flow << FlattenRowMajor(s.data.cMt);
    y << YAML::Key << "corners" << YAML::Value;
    EmitCorners(s.data.corners, &y);
    y << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap;
  std::ofstream out(path);
  out << "# aerograsp calibration samples: re-solve with `aerograsp calibrate --resolve DIR`.\n"
      << y.c_str() << "\n";
  if (!out) throw std::runtime_error(path + ": cannot be written");
}

std::vector<WizardSample> ReadSamplesYaml(const std::string& path, std::string* platform_path,
                                          Side* side, TagBoardConfig* board) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.RequireOnlyKeys({"platform", "arm", "board", "samples"});
  *platform_path = root.GetString("platform");
  CheckFileExists(path, "platform", *platform_path);
  *side = ParseSide(root.GetString("arm"));
  *board = TagBoardConfig::FromNode(root.Child("board"));
  const Platform platform = Platform::Load(*platform_path);
  const YAML::Node all = YAML::LoadFile(path)["samples"];
  if (!all || !all.IsSequence()) root.Fail("samples", "expected a list of samples");
  std::vector<WizardSample> samples;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const std::string where = "samples[" + std::to_string(i) + "]";
    try {
      WizardSample s;
      s.image = all[i]["image"].as<std::string>();
      s.accepted = all[i]["accepted"].as<bool>();
      s.reject_reason = all[i]["reject_reason"].as<std::string>("");
      const auto q = all[i]["q_rad"].as<std::vector<double>>();
      CheckFinite(path, where + ".q_rad", q);
      s.q_rad = Eigen::Map<const Eigen::VectorXd>(q.data(), static_cast<long>(q.size()));
      if (s.q_rad.size() != platform.arm(*side).dof())
        root.Fail(where + ".q_rad", "wrong number of joints");
      s.data.bMe = platform.arm(*side).ForwardKinematics(s.q_rad);
      const auto m = all[i]["cMt"].as<std::vector<double>>();
      if (m.size() != 16) root.Fail(where + ".cMt", "expected 16 numbers");
      CheckFinite(path, where + ".cMt", m);
      for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) s.data.cMt.matrix()(r, c) = m[4 * r + c];
      }
      s.data.corners = ReadCorners(all[i]["corners"], root, where + ".corners");
      samples.push_back(std::move(s));
    } catch (const YAML::Exception& e) {
      root.Fail(where, std::string("malformed: ") + e.what());
    }
  }
  return samples;
}

}  // namespace aerograsp
