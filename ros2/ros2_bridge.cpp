#include "ros2/ros2_bridge.h"

#include <dds/dds.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <thread>
#include <utility>
#include <vector>

// Generated at build time by Cyclone's idlc from ros2/idl/ (ROS 2's DDS names).
#include "builtin_interfaces/msg/Time.h"
#include "diagnostic_msgs/msg/DiagnosticArray.h"
#include "geometry_msgs/msg/PoseStamped.h"
#include "rcl_interfaces/msg/Log.h"
#include "rosgraph_msgs/msg/Clock.h"
#include "sensor_msgs/msg/Image.h"
#include "sensor_msgs/msg/JointState.h"
#include "std_msgs/msg/Bool.h"
#include "std_msgs/msg/String.h"
#include "tf2_msgs/msg/TFMessage.h"

namespace aerograsp {

// ---- The domain participant, shared by the sink and the emergency-stop reader ----------

class Ros2Participant {
 public:
  Ros2Participant(dds_entity_t domain, dds_entity_t participant)
      : domain_(domain), participant_(participant) {}
  ~Ros2Participant() {
    dds_delete(participant_);
    if (domain_ > 0) dds_delete(domain_);
  }
  Ros2Participant(const Ros2Participant&) = delete;
  Ros2Participant& operator=(const Ros2Participant&) = delete;

  dds_entity_t handle() const { return participant_; }

  /// The topic `name` (DDS name, e.g. "rt/tf") of `type`, created once.
  /// @throws std::runtime_error with Cyclone's reason.
  dds_entity_t Topic(const dds_topic_descriptor_t& type, const std::string& name) {
    const auto found = topics_.find(name);
    if (found != topics_.end()) return found->second;
    const dds_entity_t topic =
        dds_create_topic(participant_, &type, name.c_str(), nullptr, nullptr);
    if (topic < 0) {
      throw std::runtime_error(
          fmt::format("cannot create topic {}: {}", name, dds_strretcode(topic)));
    }
    topics_[name] = topic;
    return topic;
  }

  /// Waits until every writer has at least `count` matched readers.
  bool WaitForSubscribers(int count, double timeout_s) const {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (true) {
      if (AllMatched(count)) return true;
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  /// Waits at most `timeout_s` for every reliable message to be acknowledged.
  void WaitForAcks(double timeout_s) const {
    dds_entity_t publishers[16];
    const dds_return_t np = dds_get_children(participant_, publishers, 16);
    for (int p = 0; p < std::min<int>(np, 16); ++p) {
      // Topics and subscribers refuse it (illegal operation): only publishers wait.
      dds_wait_for_acks(publishers[p], static_cast<dds_duration_t>(timeout_s * 1e9));
    }
  }

 private:
  bool AllMatched(int count) const {
    dds_entity_t publishers[16];
    const dds_return_t np = dds_get_children(participant_, publishers, 16);
    for (int p = 0; p < std::min<int>(np, 16); ++p) {
      dds_entity_t writers[64];
      const dds_return_t nw = dds_get_children(publishers[p], writers, 64);
      for (int w = 0; w < std::min<int>(nw, 64); ++w) {
        dds_publication_matched_status_t status;
        if (dds_get_publication_matched_status(writers[w], &status) == DDS_RETCODE_OK &&
            static_cast<int>(status.current_count) < count)
          return false;
      }
    }
    return true;
  }

  dds_entity_t domain_;  // 0 when the participant made its own from CYCLONEDDS_URI
  dds_entity_t participant_;
  std::map<std::string, dds_entity_t> topics_;
};

namespace {

using Note = std::function<void(const std::string&)>;

// ---- QoS: ROS 2's profiles (rmw_qos_profile_default, _sensor_data, tf2_ros') ----------

enum class Qos {
  kDefault,     // reliable, volatile, keep last 10
  kSensorData,  // best effort, volatile, keep last 5
  kTf,          // reliable, volatile, keep last 100 (tf2_ros::DynamicBroadcasterQoS)
  kLatched,     // reliable, transient local, keep last 1 (tf2_ros::StaticBroadcasterQoS)
  kRosout,      // reliable, transient local, keep last 1000 (rcl's rosout)
  kClock,       // best effort, volatile, keep last 1 (rclcpp::ClockQoS)
};

/// The profile's QoS. Writers never wait for a subscriber: a reliable write
/// that would block (unacknowledged data above Cyclone's watermark) fails at
/// once instead, so a stalled subscriber cannot stall the servo loop.
dds_qos_t* MakeQos(Qos kind, bool writer) {
  dds_qos_t* qos = dds_create_qos();
  const bool reliable = kind != Qos::kSensorData && kind != Qos::kClock;
  dds_qset_reliability(qos, reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT,
                       writer ? 0 : DDS_MSECS(100));
  const bool latched = kind == Qos::kLatched || kind == Qos::kRosout;
  dds_qset_durability(qos, latched ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  int depth = 10;
  switch (kind) {
    case Qos::kDefault:
      depth = 10;
      break;
    case Qos::kSensorData:
      depth = 5;
      break;
    case Qos::kTf:
      depth = 100;
      break;
    case Qos::kLatched:
      depth = 1;
      break;
    case Qos::kRosout:
      depth = 1000;
      break;
    case Qos::kClock:
      depth = 1;
      break;
  }
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
  return qos;
}

std::string Guid(const dds_guid_t& guid) {
  std::string s;
  for (int i = 0; i < 16; ++i) s += fmt::format("{:02x}{}", guid.v[i], i == 11 ? ":" : "");
  return s;
}

/// The ROS time of mission time `t_s`: the start's whole seconds kept apart
/// from the fractions, so nanoseconds survive (a double near 1.7e9 s resolves
/// only a quarter of a microsecond).
builtin_interfaces_msg_dds__Time_ StampOf(double start_wall_s, double t_s) {
  const double start_sec = std::floor(start_wall_s);
  const double fraction = (start_wall_s - start_sec) + t_s;
  double sec = std::floor(fraction);
  long long nanosec = std::llround((fraction - sec) * 1e9);
  if (nanosec >= 1000000000LL) {
    sec += 1.0;
    nanosec -= 1000000000LL;
  }
  builtin_interfaces_msg_dds__Time_ t{};
  t.sec = static_cast<int32_t>(start_sec + sec);
  t.nanosec = static_cast<uint32_t>(nanosec);
  return t;
}

// Cyclone's generated structs hold `char*`; dds_write only reads through them.
char* Chars(const std::string& s) { return const_cast<char*>(s.c_str()); }
char* Chars(const char* s) { return const_cast<char*>(s); }

geometry_msgs_msg_dds__Pose_ PoseOf(const Eigen::Isometry3d& aMb) {
  geometry_msgs_msg_dds__Pose_ p{};
  const Eigen::Vector3d t = aMb.translation();
  const Eigen::Quaterniond q(aMb.rotation());
  p.position = {t.x(), t.y(), t.z()};
  p.orientation = {q.x(), q.y(), q.z(), q.w()};
  return p;
}

/// What went wrong, each kind said once per bridge (a subscriber that leaves
/// would otherwise be said on every topic), on the caller's thread at its next
/// call (DDS's threads find it first).
class NoteQueue {
 public:
  void Once(const std::string& kind, const std::string& line) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!said_.insert(kind).second) return;
    lines_.push_back(line);
  }
  void Flush(const Note& note) {
    std::vector<std::string> lines;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (lines_.empty()) return;
      lines.swap(lines_);
    }
    for (const std::string& line : lines) note(line);
  }

 private:
  std::mutex mutex_;
  std::set<std::string> said_;
  std::vector<std::string> lines_;
};

// ---- Cyclone's log lines ----------------------------------------------------------------

/// Cyclone says some things only in its log (a message that does not decode,
/// an interface that does not exist). The log sink is one per process: each
/// handler sees every line and takes those it understands; the others go to
/// stderr as Cyclone would print them.
class CycloneLog {
 public:
  using Handler = std::function<bool(const std::string&)>;

  static CycloneLog& Get() {
    static CycloneLog log;
    return log;
  }
  int Add(Handler handler) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!installed_) {
      installed_ = true;
      dds_set_log_sink(&CycloneLog::Sink, this);
    }
    handlers_[next_id_] = std::move(handler);
    return next_id_++;
  }
  void Remove(int id) {
    std::lock_guard<std::mutex> lock(mutex_);
    handlers_.erase(id);
  }

 private:
  static void Sink(void* arg, const dds_log_data_t* data) {
    auto* self = static_cast<CycloneLog*>(arg);
    std::string line(data->message, data->size);
    while (!line.empty() && (line.back() == '\n' || line.back() == ' ')) line.pop_back();
    std::lock_guard<std::mutex> lock(self->mutex_);
    for (auto& [id, handler] : self->handlers_) {
      if (handler(line)) return;
    }
    std::fprintf(stderr, "cyclonedds: %s\n", line.c_str());
  }

  std::mutex mutex_;
  bool installed_ = false;
  int next_id_ = 1;
  std::map<int, Handler> handlers_;
};

/// Collects Cyclone's log lines while it lives (the reasons of a failed start).
class CycloneLogCapture {
 public:
  CycloneLogCapture()
      : id_(CycloneLog::Get().Add([this](const std::string& line) {
          lines_.push_back(line);
          return true;
        })) {}
  ~CycloneLogCapture() { CycloneLog::Get().Remove(id_); }
  CycloneLogCapture(const CycloneLogCapture&) = delete;
  CycloneLogCapture& operator=(const CycloneLogCapture&) = delete;
  /// The lines so far, joined by "; ".
  std::string Text() const {
    std::string text;
    for (const std::string& l : lines_) text += (text.empty() ? "" : "; ") + l;
    return text;
  }

 private:
  std::vector<std::string> lines_;  // written under CycloneLog's lock
  int id_;
};

// ---- Writers ------------------------------------------------------------------------------

/// One topic's writer: writes, and says once what went wrong.
class Writer {
 public:
  Writer() = default;
  Writer(Ros2Participant* participant, const dds_topic_descriptor_t& type,
         const std::string& ros_name, Qos qos, NoteQueue* notes)
      : ros_name_(ros_name), notes_(notes) {
    const dds_entity_t topic = participant->Topic(type, "rt" + ros_name);
    dds_qos_t* q = MakeQos(qos, true);
    dds_listener_t* listener = dds_create_listener(this);
    dds_lset_publication_matched(listener, &Writer::OnMatched);
    writer_ = dds_create_writer(participant->handle(), topic, q, listener);
    dds_delete_listener(listener);
    dds_delete_qos(q);
    if (writer_ < 0) {
      throw std::runtime_error(
          fmt::format("cannot create a writer on {}: {}", ros_name, dds_strretcode(writer_)));
    }
  }
  ~Writer() {
    if (writer_ > 0) dds_delete(writer_);  // waits for a listener call in progress
  }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// Writes `sample` (the generated C type of the topic).
  void Write(const void* sample) {
    const dds_return_t rc = dds_write(writer_, sample);
    if (rc == DDS_RETCODE_OK) return;
    if (rc == DDS_RETCODE_TIMEOUT) {
      notes_->Once("unacknowledged",
                   fmt::format("ROS 2: a subscriber of {} does not acknowledge; messages are "
                               "dropped while it lasts (the mission does not wait)",
                               ros_name_));
    } else {
      notes_->Once("write " + ros_name_,
                   fmt::format("ROS 2: {}: cannot write ({}); its messages are dropped", ros_name_,
                               dds_strretcode(rc)));
    }
  }

 private:
  static void OnMatched(dds_entity_t /*writer*/, const dds_publication_matched_status_t status,
                        void* arg) {
    auto* self = static_cast<Writer*>(arg);
    if (status.current_count_change < 0) {
      self->notes_->Once("left", fmt::format("ROS 2: a subscriber of {} left ({} remain); "
                                             "publishing goes on",
                                             self->ros_name_, status.current_count));
    }
  }

  std::string ros_name_;
  NoteQueue* notes_ = nullptr;
  dds_entity_t writer_ = 0;
};

/// Lets a topic through at most `rate_hz` on mission time.
class RateLimit {
 public:
  explicit RateLimit(double rate_hz) : period_s_(rate_hz > 0 ? 1.0 / rate_hz : -1.0) {}
  bool Due(double t_s) {
    if (period_s_ < 0) return false;
    if (last_s_ > -1e300 && t_s < last_s_ + period_s_ - 1e-9) return false;
    last_s_ = t_s;
    return true;
  }

 private:
  double period_s_;
  double last_s_ = -1e301;
};

// ---- The sink --------------------------------------------------------------------------------

class Ros2Sink final : public TelemetrySink {
 public:
  Ros2Sink(std::shared_ptr<Ros2Participant> participant, const Ros2Config& config, Note note,
           double start_wall_s)
      : participant_(std::move(participant)),
        config_(config),
        note_(std::move(note)),
        start_wall_s_(start_wall_s),
        joints_rate_(config.joint_states_rate_hz),
        targets_rate_(config.joint_states_rate_hz),
        tf_rate_(config.joint_states_rate_hz),
        clock_rate_(config.joint_states_rate_hz),
        image_rate_(config.image_rate_hz) {
    const std::string ns = config.topic_namespace.empty() ? "" : "/" + config.topic_namespace;
    Ros2Participant* p = participant_.get();
    NoteQueue* q = &notes_;
    pose_ = std::make_unique<Writer>(p, geometry_msgs_msg_dds__PoseStamped__desc,
                                     ns + "/object_pose", Qos::kSensorData, q);
    pose_cov_ = std::make_unique<Writer>(p, geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc,
                                         ns + "/object_pose_covariance", Qos::kSensorData, q);
    found_ = std::make_unique<Writer>(p, std_msgs_msg_dds__Bool__desc, ns + "/object_found",
                                      Qos::kDefault, q);
    joints_ = std::make_unique<Writer>(p, sensor_msgs_msg_dds__JointState__desc,
                                       ns + "/joint_states", Qos::kDefault, q);
    targets_ = std::make_unique<Writer>(p, sensor_msgs_msg_dds__JointState__desc,
                                        ns + "/joint_targets", Qos::kDefault, q);
    tf_ = std::make_unique<Writer>(p, tf2_msgs_msg_dds__TFMessage__desc, "/tf", Qos::kTf, q);
    tf_static_ = std::make_unique<Writer>(p, tf2_msgs_msg_dds__TFMessage__desc, "/tf_static",
                                          Qos::kLatched, q);
    transitions_ = std::make_unique<Writer>(p, std_msgs_msg_dds__String__desc, ns + "/transitions",
                                            Qos::kDefault, q);
    grasp_pair_ = std::make_unique<Writer>(p, std_msgs_msg_dds__String__desc, ns + "/grasp_pair",
                                           Qos::kLatched, q);
    diagnostics_ = std::make_unique<Writer>(p, diagnostic_msgs_msg_dds__DiagnosticArray__desc,
                                            "/diagnostics", Qos::kDefault, q);
    rosout_ =
        std::make_unique<Writer>(p, rcl_interfaces_msg_dds__Log__desc, "/rosout", Qos::kRosout, q);
    if (config.image_rate_hz > 0) {
      color_ = std::make_unique<Writer>(p, sensor_msgs_msg_dds__Image__desc,
                                        ns + "/camera/color/image_raw", Qos::kSensorData, q);
      depth_ = std::make_unique<Writer>(p, sensor_msgs_msg_dds__Image__desc,
                                        ns + "/camera/depth/image_raw", Qos::kSensorData, q);
      camera_info_ =
          std::make_unique<Writer>(p, sensor_msgs_msg_dds__CameraInfo__desc,
                                   ns + "/camera/color/camera_info", Qos::kSensorData, q);
    }
    if (config.publish_clock) {
      clock_ =
          std::make_unique<Writer>(p, rosgraph_msgs_msg_dds__Clock__desc, "/clock", Qos::kClock, q);
    }
  }

  ~Ros2Sink() override {
    // Writers go before the participant (their listeners reference `notes_`).
    pose_.reset(), pose_cov_.reset(), found_.reset(), joints_.reset(), targets_.reset();
    tf_.reset(), tf_static_.reset(), transitions_.reset(), grasp_pair_.reset();
    diagnostics_.reset(), rosout_.reset(), color_.reset(), depth_.reset(), camera_info_.reset();
    clock_.reset();
  }

  void StaticTransforms(double t_s, const std::vector<TelemetryTransform>& transforms) override {
    if (!Open()) return;
    // /tf_static keeps one message: it carries every fixed transform so far.
    for (const TelemetryTransform& tr : transforms) static_[tr.child] = tr;
    std::vector<TelemetryTransform> all;
    for (const auto& [child, tr] : static_) all.push_back(tr);
    PublishTf(*tf_static_, t_s, all);
  }

  void Transforms(double t_s, const std::vector<TelemetryTransform>& transforms) override {
    if (!Open() || !tf_rate_.Due(t_s)) return;
    PublishTf(*tf_, t_s, transforms);
    PublishClock(t_s);
  }

  void ObjectPose(const TelemetryObjectPose& pose) override {
    if (!Open()) return;
    const std_msgs_msg_dds__Header_ header = Header(pose.t_s, pose.frame_id.c_str());
    if (pose.valid) {
      geometry_msgs_msg_dds__PoseStamped_ msg{};
      msg.header = header;
      msg.pose = PoseOf(pose.fMo);
      pose_->Write(&msg);
      if (pose.covariance) {
        geometry_msgs_msg_dds__PoseWithCovarianceStamped_ cov{};
        cov.header = header;
        cov.pose.pose = msg.pose;
        for (int r = 0; r < 6; ++r)
          for (int c = 0; c < 6; ++c) cov.pose.covariance[6 * r + c] = (*pose.covariance)(r, c);
        pose_cov_->Write(&cov);
      }
    }
    std_msgs_msg_dds__Bool_ found{};
    found.data = pose.found;
    found_->Write(&found);
    if (pose.found != object_found_) {
      object_found_ = pose.found;
      PublishDiagnostics(pose.t_s);
    }
  }

  void Arms(const TelemetryArms& arms) override {
    if (!Open()) return;
    bool gripper_changed = false;
    for (int a = 0; a < 2; ++a) {
      const TelemetryArmState& arm = arms.arms[a];
      const std::string state = arm.gripper_holding  ? "holding"
                                : arm.gripper_closed ? "closed"
                                                     : "open";
      if (state != gripper_state_[a]) {
        gripper_state_[a] = state;
        gripper_changed = true;
      }
    }
    if (gripper_changed) PublishDiagnostics(arms.t_s);
    if (joints_rate_.Due(arms.t_s)) PublishJoints(*joints_, arms, false);
    if (targets_rate_.Due(arms.t_s)) PublishJoints(*targets_, arms, true);
    PublishClock(arms.t_s);
  }

  void Transition(const TelemetryTransition& t) override {
    if (!Open()) return;
    const std::string line = fmt::format("{}: {} -> {}: {}", t.machine, t.from, t.to, t.cause);
    std_msgs_msg_dds__String_ msg{};
    msg.data = Chars(line);
    transitions_->Write(&msg);
    machines_[t.machine] = {t.to, t.cause};
    PublishDiagnostics(t.t_s);
  }

  void GraspPair(const TelemetryGraspPair& pair) override {
    if (!Open()) return;
    grasp_pair_line_ =
        fmt::format("left {} right {}: {}", pair.left_pair, pair.right_pair, pair.reason);
    std_msgs_msg_dds__String_ msg{};
    msg.data = Chars(grasp_pair_line_);
    grasp_pair_->Write(&msg);
    PublishDiagnostics(pair.t_s);
  }

  void Image(const TelemetryImage& image) override {
    if (!Open() || !color_ || !image.color || !image_rate_.Due(image.t_s)) return;
    const std_msgs_msg_dds__Header_ header = Header(image.t_s, image.frame_id.c_str());
    sensor_msgs_msg_dds__Image_ color{};
    color.header = header;
    color.height = static_cast<uint32_t>(image.color->height);
    color.width = static_cast<uint32_t>(image.color->width);
    color.encoding = Chars(kRgb8);
    color.step = color.width * 3;
    // The sample borrows the image's pixels: dds_write serialises them before returning.
    color.data._buffer = const_cast<uint8_t*>(image.color->data.data());
    color.data._length = color.data._maximum = static_cast<uint32_t>(image.color->data.size());
    color_->Write(&color);

    sensor_msgs_msg_dds__CameraInfo_ info{};
    info.header = header;
    info.height = color.height;
    info.width = color.width;
    info.distortion_model = Chars(kPlumbBob);
    double d[5] = {0, 0, 0, 0, 0};  // the colour image is rectified
    info.d._buffer = d;
    info.d._length = info.d._maximum = 5;
    const CameraIntrinsics& K = image.K;
    const double k[9] = {K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1};
    const double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double p[12] = {K.fx, 0, K.cx, 0, 0, K.fy, K.cy, 0, 0, 0, 1, 0};
    std::copy(k, k + 9, info.k);
    std::copy(r, r + 9, info.r);
    std::copy(p, p + 12, info.p);
    camera_info_->Write(&info);

    if (!image.depth) return;
    sensor_msgs_msg_dds__Image_ depth{};
    depth.header = header;
    depth.height = static_cast<uint32_t>(image.depth->height);
    depth.width = static_cast<uint32_t>(image.depth->width);
    // ROS's convention: 16UC1 in millimetres, else 32FC1 in metres.
    std::vector<float> metres;
    if (std::abs(image.depth_scale_m - 0.001) < 1e-12) {
      depth.encoding = Chars(k16UC1);
      depth.step = depth.width * 2;
      depth.data._buffer =
          reinterpret_cast<uint8_t*>(const_cast<uint16_t*>(image.depth->data.data()));
      depth.data._length = static_cast<uint32_t>(image.depth->data.size() * 2);
    } else {
      metres.resize(image.depth->data.size());
      for (std::size_t i = 0; i < metres.size(); ++i) {
        metres[i] = image.depth->data[i] == 0
                        ? NAN
                        : static_cast<float>(image.depth->data[i] * image.depth_scale_m);
      }
      depth.encoding = Chars(k32FC1);
      depth.step = depth.width * 4;
      depth.data._buffer = reinterpret_cast<uint8_t*>(metres.data());
      depth.data._length = static_cast<uint32_t>(metres.size() * 4);
    }
    depth.data._maximum = depth.data._length;
    depth_->Write(&depth);
  }

  void Log(double t_s, TelemetryLevel level, const std::string& name,
           const std::string& line) override {
    if (!Open()) return;
    rcl_interfaces_msg_dds__Log_ msg{};
    msg.stamp = StampOf(start_wall_s_, t_s);
    static constexpr uint8_t kLevels[] = {10, 20, 30, 40, 50};  // rcl_interfaces/Log's
    msg.level = kLevels[static_cast<int>(level)];
    const std::string logger = "aerograsp." + name;
    msg.name = Chars(logger);
    msg.msg = Chars(line);
    msg.file = Chars(kEmpty);
    msg.function = Chars(kEmpty);
    rosout_->Write(&msg);
  }

  /// Stops publishing and waits (at most kCloseWaitS) for subscribers to
  /// acknowledge what they have not yet, so the last messages reach them.
  void Close() override {
    if (closed_) return;
    closed_ = true;
    participant_->WaitForAcks(kCloseWaitMs * 1e-3);
  }

 private:
  static constexpr int kCloseWaitMs = 1000;
  static constexpr const char* kRgb8 = "rgb8";
  static constexpr const char* k16UC1 = "16UC1";
  static constexpr const char* k32FC1 = "32FC1";
  static constexpr const char* kPlumbBob = "plumb_bob";
  static constexpr const char* kEmpty = "";

  /// Says what DDS's threads saw; false once closed.
  bool Open() {
    notes_.Flush(note_);
    return !closed_;
  }

  /// `frame_id` must outlive the write (the header points into it).
  std_msgs_msg_dds__Header_ Header(double t_s, const char* frame_id) const {
    std_msgs_msg_dds__Header_ h{};
    h.stamp = StampOf(start_wall_s_, t_s);
    h.frame_id = Chars(frame_id);
    return h;
  }

  void PublishTf(Writer& writer, double t_s, const std::vector<TelemetryTransform>& transforms) {
    std::vector<geometry_msgs_msg_dds__TransformStamped_> items(transforms.size());
    for (std::size_t i = 0; i < transforms.size(); ++i) {
      const TelemetryTransform& tr = transforms[i];
      geometry_msgs_msg_dds__TransformStamped_& item = items[i];
      item.header = Header(t_s, tr.parent.c_str());
      item.child_frame_id = Chars(tr.child);
      const geometry_msgs_msg_dds__Pose_ p = PoseOf(tr.parentMchild);
      item.transform.translation = {p.position.x, p.position.y, p.position.z};
      item.transform.rotation = p.orientation;
    }
    tf2_msgs_msg_dds__TFMessage_ msg{};
    msg.transforms._buffer = items.data();
    msg.transforms._length = msg.transforms._maximum = static_cast<uint32_t>(items.size());
    writer.Write(&msg);
  }

  void PublishJoints(Writer& writer, const TelemetryArms& arms, bool targets) {
    std::vector<std::string> names;
    std::vector<double> position, velocity;
    bool velocities = !targets;
    for (int a = 0; a < 2; ++a) {
      const TelemetryArmState& arm = arms.arms[a];
      const Eigen::VectorXd& q = targets ? arm.target_rad : arm.position_rad;
      if (q.size() != static_cast<Eigen::Index>(arm.joint_names.size())) continue;
      velocities = velocities && arm.velocity_radps.size() == q.size();
      for (std::size_t j = 0; j < arm.joint_names.size(); ++j) {
        names.push_back("arm_" + arm.arm + "_" + arm.joint_names[j]);
        position.push_back(q[static_cast<Eigen::Index>(j)]);
        if (velocities) velocity.push_back(arm.velocity_radps[static_cast<Eigen::Index>(j)]);
      }
      if (!targets) {  // the gripper as a prismatic joint: the opening between the pads, m
        names.push_back("arm_" + arm.arm + "_gripper");
        position.push_back(arm.gripper_aperture_m);
        if (velocities) velocity.push_back(0.0);
      }
    }
    if (names.empty()) return;
    if (!velocities) velocity.clear();
    std::vector<char*> name_ptrs;
    for (const std::string& n : names) name_ptrs.push_back(Chars(n));
    sensor_msgs_msg_dds__JointState_ msg{};
    msg.header = Header(arms.t_s, kEmpty);
    msg.name._buffer = name_ptrs.data();
    msg.name._length = msg.name._maximum = static_cast<uint32_t>(name_ptrs.size());
    msg.position._buffer = position.data();
    msg.position._length = msg.position._maximum = static_cast<uint32_t>(position.size());
    msg.velocity._buffer = velocity.data();
    msg.velocity._length = msg.velocity._maximum = static_cast<uint32_t>(velocity.size());
    writer.Write(&msg);
  }

  void PublishClock(double t_s) {
    if (!clock_ || !clock_rate_.Due(t_s)) return;
    rosgraph_msgs_msg_dds__Clock_ msg{};
    msg.clock = StampOf(start_wall_s_, t_s);
    clock_->Write(&msg);
  }

  /// One status per state machine (its state, the last transition's cause),
  /// the followed grasp pair, the object found and each gripper.
  void PublishDiagnostics(double t_s) {
    struct Status {
      std::string name, message;
      std::vector<std::pair<std::string, std::string>> values;
    };
    std::vector<Status> statuses;
    for (const auto& [machine, state] : machines_) {
      statuses.push_back({"aerograsp: " + machine, state.first, {{"cause", state.second}}});
    }
    statuses.push_back({"aerograsp: object", object_found_ ? "found" : "not found", {}});
    statuses.push_back({"aerograsp: grasp pair", grasp_pair_line_, {}});
    for (int a = 0; a < 2; ++a) {
      statuses.push_back(
          {fmt::format("aerograsp: {} gripper", a == 0 ? "left" : "right"), gripper_state_[a], {}});
    }
    std::vector<std::vector<diagnostic_msgs_msg_dds__KeyValue_>> values(statuses.size());
    std::vector<diagnostic_msgs_msg_dds__DiagnosticStatus_> items(statuses.size());
    for (std::size_t i = 0; i < statuses.size(); ++i) {
      for (const auto& [key, value] : statuses[i].values)
        values[i].push_back({Chars(key), Chars(value)});
      diagnostic_msgs_msg_dds__DiagnosticStatus_& s = items[i];
      s = {};
      s.level = 0;  // OK: the states say what happens, nothing here is a fault of the link
      s.name = Chars(statuses[i].name);
      s.message = Chars(statuses[i].message);
      s.hardware_id = Chars(kHardwareId);
      s.values._buffer = values[i].data();
      s.values._length = s.values._maximum = static_cast<uint32_t>(values[i].size());
    }
    diagnostic_msgs_msg_dds__DiagnosticArray_ msg{};
    msg.header = Header(t_s, kEmpty);
    msg.status._buffer = items.data();
    msg.status._length = msg.status._maximum = static_cast<uint32_t>(items.size());
    diagnostics_->Write(&msg);
  }

  static constexpr const char* kHardwareId = "aerograsp";

  std::shared_ptr<Ros2Participant> participant_;
  Ros2Config config_;
  Note note_;
  double start_wall_s_;
  NoteQueue notes_;
  std::unique_ptr<Writer> pose_, pose_cov_, found_, joints_, targets_, tf_, tf_static_,
      transitions_, grasp_pair_, diagnostics_, rosout_, color_, depth_, camera_info_, clock_;
  RateLimit joints_rate_, targets_rate_, tf_rate_, clock_rate_, image_rate_;
  std::map<std::string, TelemetryTransform> static_;
  std::map<std::string, std::pair<std::string, std::string>> machines_;  // state, cause
  std::string grasp_pair_line_ = "none";
  std::string gripper_state_[2] = {"open", "open"};
  bool object_found_ = false;
  bool closed_ = false;
};

// ---- The emergency stop ------------------------------------------------------------------

/// Hears /NS/emergency_stop on a DDS thread and latches the first `true`.
class Ros2EmergencyStop final : public EmergencyStopSource {
 public:
  Ros2EmergencyStop(std::shared_ptr<Ros2Participant> participant, const std::string& ros_name)
      : participant_(std::move(participant)), ros_name_(ros_name) {
    const dds_entity_t topic = participant_->Topic(std_msgs_msg_dds__Bool__desc, "rt" + ros_name);
    dds_qos_t* qos = MakeQos(Qos::kDefault, false);
    dds_listener_t* listener = dds_create_listener(this);
    dds_lset_data_available(listener, &Ros2EmergencyStop::OnData);
    dds_lset_requested_incompatible_qos(listener, &Ros2EmergencyStop::OnIncompatible);
    reader_ = dds_create_reader(participant_->handle(), topic, qos, listener);
    dds_delete_listener(listener);
    dds_delete_qos(qos);
    if (reader_ < 0) {
      throw std::runtime_error(
          fmt::format("cannot create a reader on {}: {}", ros_name, dds_strretcode(reader_)));
    }
    // A message that does not decode as std_msgs/Bool (a byte other than 0
    // or 1, too short) is dropped by Cyclone, which says so only in its log.
    log_id_ = CycloneLog::Get().Add([this](const std::string& line) { return OnLog(line); });
  }
  ~Ros2EmergencyStop() override {
    CycloneLog::Get().Remove(log_id_);
    if (reader_ > 0) dds_delete(reader_);  // waits for a listener call in progress
  }
  Ros2EmergencyStop(const Ros2EmergencyStop&) = delete;
  Ros2EmergencyStop& operator=(const Ros2EmergencyStop&) = delete;

  EmergencyStopPoll Poll(double t_s) override { return latch_.Poll(t_s); }

  /// Waits at most `timeout_s` for a publisher to match; whether one did.
  bool WaitForPublisher(double timeout_s) const {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    dds_subscription_matched_status_t status{};
    while (dds_get_subscription_matched_status(reader_, &status) == DDS_RETCODE_OK &&
           status.current_count == 0) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
  }

 private:
  static void OnData(dds_entity_t reader, void* arg) {
    auto* self = static_cast<Ros2EmergencyStop*>(arg);
    constexpr int kMax = 16;
    std_msgs_msg_dds__Bool_ samples[kMax];
    void* buffers[kMax];
    for (int i = 0; i < kMax; ++i) buffers[i] = &samples[i];
    dds_sample_info_t infos[kMax];
    int n;
    while ((n = dds_take(reader, buffers, infos, kMax, kMax)) > 0) {
      for (int i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const std::string writer = self->WriterName(infos[i].publication_handle);
        if (samples[i].data) {
          self->latch_.Request(fmt::format("ROS 2 {} ({})", self->ros_name_, writer),
                               "std_msgs/Bool true");
        } else if (!self->said_false_) {
          self->said_false_ = true;
          self->latch_.Note(fmt::format(
              "ROS 2: {}: false from {} ignored (a stop is released by nothing but the end of "
              "the mission)",
              self->ros_name_, writer));
        }
      }
    }
  }

  static void OnIncompatible(dds_entity_t /*reader*/,
                             const dds_requested_incompatible_qos_status_t status, void* arg) {
    auto* self = static_cast<Ros2EmergencyStop*>(arg);
    if (status.total_count_change <= 0 || self->said_incompatible_) return;
    self->said_incompatible_ = true;
    self->latch_.Note(fmt::format(
        "ROS 2: {}: a publisher's QoS does not match (policy {}); its stops are not heard: "
        "publish it reliable (ROS 2's default)",
        self->ros_name_, status.last_policy_id));
  }

  /// Takes Cyclone's "deserialization <topic>/<type> failed" lines of our topic.
  bool OnLog(const std::string& line) {
    const std::string topic = "deserialization rt" + ros_name_ + "/";
    if (line.find(topic) == std::string::npos || line.find("failed") == std::string::npos)
      return false;
    if (!said_malformed_) {
      said_malformed_ = true;
      // "... data(application, vendor 1.15): <writer guid> #<seq>: deserialization ..."
      const std::size_t from = line.find("): ");
      const std::size_t to = line.find(" #", from);
      const std::string writer = from != std::string::npos && to != std::string::npos
                                     ? "writer " + line.substr(from + 3, to - from - 3)
                                     : "a writer";
      latch_.Note(
          fmt::format("ROS 2: {}: a malformed message from {} was dropped (it does not decode as "
                      "std_msgs/Bool); it does not stop the mission",
                      ros_name_, writer));
    }
    return true;
  }

  std::string WriterName(dds_instance_handle_t handle) const {
    dds_builtintopic_endpoint_t* ep = dds_get_matched_publication_data(reader_, handle);
    if (!ep) return "an unknown writer";
    const std::string name = "writer " + Guid(ep->key);
    dds_builtintopic_free_endpoint(ep);
    return name;
  }

  std::shared_ptr<Ros2Participant> participant_;
  std::string ros_name_;
  dds_entity_t reader_ = 0;
  EmergencyStopLatch latch_;
  // Touched on DDS's listener thread only.
  bool said_false_ = false, said_incompatible_ = false;
  bool said_malformed_ = false;  // under CycloneLog's lock
  int log_id_ = 0;
};

}  // namespace

Ros2Bridge OpenRos2(const Ros2Config& config, std::function<void(const std::string&)> note,
                    double start_wall_s) {
  Ros2Bridge bridge;
  if (!config.enabled) return bridge;
  if (start_wall_s < 0) {
    start_wall_s =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  }
  const auto fail = [&](const std::string& why) {
    note(fmt::format("ROS 2: cannot join DDS domain {} ({}); going on without ROS 2 topics",
                     config.domain_id, why));
    return Ros2Bridge{};
  };
  CycloneLogCapture reasons;  // what Cyclone says while it starts
  dds_entity_t domain = 0;
  if (!config.dds_config.empty()) {
    const std::string uri =
        "file://" + std::filesystem::absolute(config.dds_config).lexically_normal().string();
    domain = dds_create_domain(static_cast<dds_domainid_t>(config.domain_id), uri.c_str());
    if (domain < 0) {
      return fail(
          fmt::format("{} with {}: {}", dds_strretcode(domain), config.dds_config, reasons.Text()));
    }
  }
  const dds_entity_t participant =
      dds_create_participant(static_cast<dds_domainid_t>(config.domain_id), nullptr, nullptr);
  if (participant < 0) {
    if (domain > 0) dds_delete(domain);
    return fail(fmt::format("{}: {}", dds_strretcode(participant), reasons.Text()));
  }
  auto shared = std::make_shared<Ros2Participant>(domain, participant);
  try {
    const std::string ns = config.topic_namespace.empty() ? "" : "/" + config.topic_namespace;
    bridge.participant = shared;
    bridge.sink = std::make_unique<Ros2Sink>(shared, config, note, start_wall_s);
    auto stop = std::make_unique<Ros2EmergencyStop>(shared, ns + "/emergency_stop");
    if (config.emergency_stop_wait_s > 0 && !stop->WaitForPublisher(config.emergency_stop_wait_s)) {
      note(fmt::format("ROS 2: no publisher on {}/emergency_stop within {:g} s; going on", ns,
                       config.emergency_stop_wait_s));
    }
    bridge.emergency_stop = std::move(stop);
  } catch (const std::exception& e) {
    return fail(e.what());
  }
  return bridge;
}

bool WaitForSubscribers(const Ros2Bridge& bridge, int count, double timeout_s) {
  return bridge.participant && bridge.participant->WaitForSubscribers(count, timeout_s);
}

}  // namespace aerograsp
