// An independent ROS 2 peer for the tests: Fast DDS (eProsima, not the Cyclone
// DDS that aerograsp publishes with), its message types built at run time
// with Fast DDS's dynamic types from the ROS 2 message layouts written out
// below, on loopback only (UDP on 127.0.0.1, unicast discovery, no multicast,
// no shared memory).
//
//   ros2_peer listen DOMAIN NS OUT.jsonl [options]
//     Subscribes to every topic aerograsp publishes (ROS 2's QoS for each),
//     writes one JSON line per message: the topic, the ROS type, the bytes as
//     received (hex, with their encapsulation header) and the fields as Fast
//     DDS decoded them. Ends when a /rosout message contains --until, or
//     --timeout-s seconds after the start (exit 2).
//     --estop-on TEXT        publish std_msgs/Bool true on /NS/emergency_stop when a
//                            /NS/transitions message contains TEXT
//     --malformed-first      before that stop, publish a Bool whose byte is 7
//                            (neither false nor true), then a truncated one
//     --no-images            do not subscribe to the camera topics
//     --leave-after N        exit (without goodbye) after N messages in all
//     --ready-file PATH      create PATH once every reader has matched a writer
//     --lease-s S            the participant's lease (how soon others notice it died)
//   ros2_peer estop DOMAIN NS [--malformed] [--count N]
//     Once aerograsp's reader is matched, publishes the stop (or two malformed
//     Bools) N times (20) 50 ms apart, waits for them to be acknowledged, and
//     exits.
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/types/DynamicData.h>
#include <fastrtps/types/DynamicDataFactory.h>
#include <fastrtps/types/DynamicPubSubType.h>
#include <fastrtps/types/DynamicTypeBuilder.h>
#include <fastrtps/types/DynamicTypeBuilderFactory.h>
#include <fastrtps/types/DynamicTypeBuilderPtr.h>
#include <fastrtps/types/DynamicTypeMember.h>
#include <fastrtps/types/MemberDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;
using eprosima::fastrtps::rtps::SerializedPayload_t;
using eprosima::fastrtps::types::DynamicData;
using eprosima::fastrtps::types::DynamicData_ptr;
using eprosima::fastrtps::types::DynamicDataFactory;
using eprosima::fastrtps::types::DynamicPubSubType;
using eprosima::fastrtps::types::DynamicType_ptr;
using eprosima::fastrtps::types::DynamicTypeBuilder_ptr;
using eprosima::fastrtps::types::DynamicTypeBuilderFactory;
using eprosima::fastrtps::types::DynamicTypeMember;
using eprosima::fastrtps::types::MemberId;
using Json = nlohmann::json;
namespace types = eprosima::fastrtps::types;

// ---- The ROS 2 message layouts, as dynamic types ---------------------------------------

class Types {
 public:
  Types() {
    time_ = Struct("builtin_interfaces::msg::dds_::Time_",
                   {{"sec", F()->create_int32_type()}, {"nanosec", F()->create_uint32_type()}});
    header_ = Struct("std_msgs::msg::dds_::Header_", {{"stamp", time_}, {"frame_id", Str()}});
    string_ = Struct("std_msgs::msg::dds_::String_", {{"data", Str()}});
    bool_ = Struct("std_msgs::msg::dds_::Bool_", {{"data", F()->create_bool_type()}});
    const DynamicType_ptr d = F()->create_float64_type();
    point_ = Struct("geometry_msgs::msg::dds_::Point_", {{"x", d}, {"y", d}, {"z", d}});
    vector3_ = Struct("geometry_msgs::msg::dds_::Vector3_", {{"x", d}, {"y", d}, {"z", d}});
    quaternion_ =
        Struct("geometry_msgs::msg::dds_::Quaternion_", {{"x", d}, {"y", d}, {"z", d}, {"w", d}});
    pose_ = Struct("geometry_msgs::msg::dds_::Pose_",
                   {{"position", point_}, {"orientation", quaternion_}});
    pose_stamped_ =
        Struct("geometry_msgs::msg::dds_::PoseStamped_", {{"header", header_}, {"pose", pose_}});
    pose_cov_ = Struct("geometry_msgs::msg::dds_::PoseWithCovariance_",
                       {{"pose", pose_}, {"covariance", Array(d, 36)}});
    pose_cov_stamped_ = Struct("geometry_msgs::msg::dds_::PoseWithCovarianceStamped_",
                               {{"header", header_}, {"pose", pose_cov_}});
    transform_ = Struct("geometry_msgs::msg::dds_::Transform_",
                        {{"translation", vector3_}, {"rotation", quaternion_}});
    transform_stamped_ =
        Struct("geometry_msgs::msg::dds_::TransformStamped_",
               {{"header", header_}, {"child_frame_id", Str()}, {"transform", transform_}});
    tf_ = Struct("tf2_msgs::msg::dds_::TFMessage_", {{"transforms", Seq(transform_stamped_)}});
    joint_state_ = Struct("sensor_msgs::msg::dds_::JointState_", {{"header", header_},
                                                                  {"name", Seq(Str())},
                                                                  {"position", Seq(d)},
                                                                  {"velocity", Seq(d)},
                                                                  {"effort", Seq(d)}});
    const DynamicType_ptr u32 = F()->create_uint32_type();
    image_ = Struct("sensor_msgs::msg::dds_::Image_", {{"header", header_},
                                                       {"height", u32},
                                                       {"width", u32},
                                                       {"encoding", Str()},
                                                       {"is_bigendian", F()->create_byte_type()},
                                                       {"step", u32},
                                                       {"data", Seq(F()->create_byte_type())}});
    roi_ = Struct("sensor_msgs::msg::dds_::RegionOfInterest_",
                  {{"x_offset", u32},
                   {"y_offset", u32},
                   {"height", u32},
                   {"width", u32},
                   {"do_rectify", F()->create_bool_type()}});
    camera_info_ = Struct("sensor_msgs::msg::dds_::CameraInfo_", {{"header", header_},
                                                                  {"height", u32},
                                                                  {"width", u32},
                                                                  {"distortion_model", Str()},
                                                                  {"d", Seq(d)},
                                                                  {"k", Array(d, 9)},
                                                                  {"r", Array(d, 9)},
                                                                  {"p", Array(d, 12)},
                                                                  {"binning_x", u32},
                                                                  {"binning_y", u32},
                                                                  {"roi", roi_}});
    key_value_ =
        Struct("diagnostic_msgs::msg::dds_::KeyValue_", {{"key", Str()}, {"value", Str()}});
    diagnostic_status_ =
        Struct("diagnostic_msgs::msg::dds_::DiagnosticStatus_", {{"level", F()->create_byte_type()},
                                                                 {"name", Str()},
                                                                 {"message", Str()},
                                                                 {"hardware_id", Str()},
                                                                 {"values", Seq(key_value_)}});
    diagnostic_array_ = Struct("diagnostic_msgs::msg::dds_::DiagnosticArray_",
                               {{"header", header_}, {"status", Seq(diagnostic_status_)}});
    log_ = Struct("rcl_interfaces::msg::dds_::Log_", {{"stamp", time_},
                                                      {"level", F()->create_byte_type()},
                                                      {"name", Str()},
                                                      {"msg", Str()},
                                                      {"file", Str()},
                                                      {"function", Str()},
                                                      {"line", u32}});
    clock_ = Struct("rosgraph_msgs::msg::dds_::Clock_", {{"clock", time_}});
  }

  DynamicType_ptr time_, header_, string_, bool_, point_, vector3_, quaternion_, pose_,
      pose_stamped_, pose_cov_, pose_cov_stamped_, transform_, transform_stamped_, tf_,
      joint_state_, image_, roi_, camera_info_, key_value_, diagnostic_status_, diagnostic_array_,
      log_, clock_;

 private:
  static DynamicTypeBuilderFactory* F() { return DynamicTypeBuilderFactory::get_instance(); }
  static DynamicType_ptr Str() { return F()->create_string_type(types::BOUND_UNLIMITED); }
  static DynamicType_ptr Seq(const DynamicType_ptr& element) {
    DynamicTypeBuilder_ptr b(F()->create_sequence_builder(element, types::BOUND_UNLIMITED));
    return b->build();
  }
  static DynamicType_ptr Array(const DynamicType_ptr& element, uint32_t n) {
    DynamicTypeBuilder_ptr b(F()->create_array_builder(element, {n}));
    return b->build();
  }
  static DynamicType_ptr Struct(
      const std::string& name, const std::vector<std::pair<std::string, DynamicType_ptr>>& fields) {
    DynamicTypeBuilder_ptr b(F()->create_struct_builder());
    MemberId id = 0;
    for (const auto& [field, type] : fields) b->add_member(id++, field, type);
    b->set_name(name);
    return b->build();
  }
};

// ---- Dynamic data to JSON ---------------------------------------------------------------

Json ToJson(DynamicData* data, const DynamicType_ptr& type);

Json MemberToJson(DynamicData* data, MemberId id, const DynamicType_ptr& type) {
  switch (type->get_kind()) {
    case types::TK_BOOLEAN:
      return data->get_bool_value(id);
    case types::TK_BYTE:
      return data->get_byte_value(id);
    case types::TK_INT32:
      return data->get_int32_value(id);
    case types::TK_UINT32:
      return data->get_uint32_value(id);
    case types::TK_FLOAT64:
      return data->get_float64_value(id);
    case types::TK_STRING8:
      return data->get_string_value(id);
    default: {
      DynamicData* inner = data->loan_value(id);
      Json j = ToJson(inner, type);
      data->return_loaned_value(inner);
      return j;
    }
  }
}

Json ToJson(DynamicData* data, const DynamicType_ptr& type) {
  const types::TypeKind kind = type->get_kind();
  if (kind == types::TK_STRUCTURE) {
    Json j = Json::object();
    std::map<MemberId, DynamicTypeMember*> members;
    type->get_all_members(members);
    for (const auto& [id, member] : members) {
      types::MemberDescriptor desc;
      member->get_descriptor(&desc);
      j[desc.get_name()] = MemberToJson(data, id, desc.get_type());
    }
    return j;
  }
  if (kind == types::TK_SEQUENCE || kind == types::TK_ARRAY) {
    Json j = Json::array();
    const DynamicType_ptr element = type->get_descriptor()->get_element_type();
    const uint32_t n = data->get_item_count();
    for (uint32_t i = 0; i < n; ++i) j.push_back(MemberToJson(data, i, element));
    return j;
  }
  return nullptr;
}

// ---- Topic types that keep the bytes they decode ---------------------------------------

/// Decodes with Fast DDS's dynamic types and keeps the serialized bytes as received.
class RecordingType : public DynamicPubSubType {
 public:
  explicit RecordingType(DynamicType_ptr type) : DynamicPubSubType(type) {}
  bool deserialize(SerializedPayload_t* payload, void* data) override {
    last_bytes.assign(payload->data, payload->data + payload->length);
    return DynamicPubSubType::deserialize(payload, data);
  }
  std::vector<uint8_t> last_bytes;  // of the sample take_next_sample just decoded
};

/// Sends given bytes as a message of a given type name (for malformed messages).
class RawType : public TopicDataType {
 public:
  explicit RawType(const std::string& name) {
    setName(name.c_str());
    m_typeSize = 64;
  }
  bool serialize(void* data, SerializedPayload_t* payload) override {
    const auto* bytes = static_cast<std::vector<uint8_t>*>(data);
    std::memcpy(payload->data, bytes->data(), bytes->size());
    payload->length = static_cast<uint32_t>(bytes->size());
    payload->encapsulation = bytes->size() > 1 && (*bytes)[1] == 1 ? 1 : 0;  // CDR_LE
    return true;
  }
  bool deserialize(SerializedPayload_t*, void*) override { return false; }
  std::function<uint32_t()> getSerializedSizeProvider(void* data) override {
    const auto* bytes = static_cast<std::vector<uint8_t>*>(data);
    return [n = bytes->size()] { return static_cast<uint32_t>(n); };
  }
  void* createData() override { return new std::vector<uint8_t>(); }
  void deleteData(void* data) override { delete static_cast<std::vector<uint8_t>*>(data); }
  bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) override { return false; }
};

// ---- QoS as ROS 2's ---------------------------------------------------------------------

enum class Qos { kDefault, kSensorData, kTf, kLatched, kRosout, kClock };

DataReaderQos ReaderQos(Qos kind) {
  DataReaderQos q = DATAREADER_QOS_DEFAULT;
  const bool reliable = kind != Qos::kSensorData && kind != Qos::kClock;
  q.reliability().kind = reliable ? RELIABLE_RELIABILITY_QOS : BEST_EFFORT_RELIABILITY_QOS;
  q.durability().kind = kind == Qos::kLatched || kind == Qos::kRosout
                            ? TRANSIENT_LOCAL_DURABILITY_QOS
                            : VOLATILE_DURABILITY_QOS;
  q.history().kind = KEEP_LAST_HISTORY_QOS;
  q.history().depth = kind == Qos::kTf ? 100 : kind == Qos::kRosout ? 1000 : 1000;
  // Keep every message: the peer records all of them.
  q.resource_limits().max_samples = 5000;
  q.resource_limits().max_samples_per_instance = 5000;
  q.history().depth = 5000;
  q.endpoint().history_memory_policy =
      eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE;
  return q;
}

DomainParticipant* JoinLoopback(int domain, double lease_s) {
  DomainParticipantQos pqos = PARTICIPANT_QOS_DEFAULT;
  pqos.name("aerograsp_test_peer");
  pqos.transport().use_builtin_transports = false;  // no shared memory, no default UDP
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.push_back("127.0.0.1");
  pqos.transport().user_transports.push_back(udp);
  // Discovery by unicast only: our own unicast locator on 127.0.0.1 and, as
  // initial peers, the well-known ports of 127.0.0.1 (port 0: each index's).
  Locator_t local;
  local.kind = LOCATOR_KIND_UDPv4;
  IPLocator::setIPv4(local, 127, 0, 0, 1);
  pqos.wire_protocol().builtin.metatrafficUnicastLocatorList.push_back(local);
  pqos.wire_protocol().default_unicast_locator_list.push_back(local);
  pqos.wire_protocol().builtin.initialPeersList.push_back(local);
  // How soon the others notice that this peer is gone without a goodbye.
  auto& discovery = pqos.wire_protocol().builtin.discovery_config;
  discovery.leaseDuration = eprosima::fastrtps::Duration_t(lease_s);
  discovery.leaseDuration_announcementperiod = eprosima::fastrtps::Duration_t(lease_s / 4);
  return DomainParticipantFactory::get_instance()->create_participant(domain, pqos);
}

// ---- listen ----------------------------------------------------------------------------

struct TopicSpec {
  std::string ros_name;  // "/tf"
  std::string ros_type;  // "tf2_msgs/msg/TFMessage"
  DynamicType_ptr type;
  Qos qos;
};

struct Args {
  int domain = 0;
  std::string ns, out, until = "crosscheck done", estop_on;
  double timeout_s = 60;
  bool malformed_first = false, no_images = false, malformed = false;
  long leave_after = -1;
  std::string ready_file;
  double lease_s = 10;  // Fast DDS's default participant lease
  int count = 20;       // estop: times each message is sent (1 s in all)
};

class Peer {
 public:
  Peer(const Args& args) : args_(args) {
    participant_ = JoinLoopback(args.domain, args.lease_s);
    if (!participant_) throw std::runtime_error("cannot create the Fast DDS participant");
    subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
    publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
  }
  ~Peer() {
    if (raw_participant_) {
      raw_participant_->delete_contained_entities();
      DomainParticipantFactory::get_instance()->delete_participant(raw_participant_);
    }
    participant_->delete_contained_entities();
    DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }

  std::vector<TopicSpec> Topics() const {
    const std::string ns = args_.ns.empty() ? "" : "/" + args_.ns;
    std::vector<TopicSpec> t = {
        {ns + "/object_pose", "geometry_msgs/msg/PoseStamped", types_.pose_stamped_,
         Qos::kSensorData},
        {ns + "/object_pose_covariance", "geometry_msgs/msg/PoseWithCovarianceStamped",
         types_.pose_cov_stamped_, Qos::kSensorData},
        {ns + "/object_found", "std_msgs/msg/Bool", types_.bool_, Qos::kDefault},
        {ns + "/joint_states", "sensor_msgs/msg/JointState", types_.joint_state_, Qos::kDefault},
        {ns + "/joint_targets", "sensor_msgs/msg/JointState", types_.joint_state_, Qos::kDefault},
        {"/tf", "tf2_msgs/msg/TFMessage", types_.tf_, Qos::kTf},
        {"/tf_static", "tf2_msgs/msg/TFMessage", types_.tf_, Qos::kLatched},
        {ns + "/transitions", "std_msgs/msg/String", types_.string_, Qos::kDefault},
        {ns + "/grasp_pair", "std_msgs/msg/String", types_.string_, Qos::kLatched},
        {"/diagnostics", "diagnostic_msgs/msg/DiagnosticArray", types_.diagnostic_array_,
         Qos::kDefault},
        {"/rosout", "rcl_interfaces/msg/Log", types_.log_, Qos::kRosout},
        {"/clock", "rosgraph_msgs/msg/Clock", types_.clock_, Qos::kClock},
    };
    if (!args_.no_images) {
      t.push_back({ns + "/camera/color/image_raw", "sensor_msgs/msg/Image", types_.image_,
                   Qos::kSensorData});
      t.push_back({ns + "/camera/depth/image_raw", "sensor_msgs/msg/Image", types_.image_,
                   Qos::kSensorData});
      t.push_back({ns + "/camera/color/camera_info", "sensor_msgs/msg/CameraInfo",
                   types_.camera_info_, Qos::kSensorData});
    }
    return t;
  }

  /// Records every topic until --until or the timeout. Returns the exit code.
  int Listen() {
    std::ofstream out(args_.out);
    if (!out) {
      std::cerr << "ros2_peer: cannot write " << args_.out << "\n";
      return 1;
    }
    struct Reader {
      TopicSpec spec;
      RecordingType* type;
      DataReader* reader;
    };
    std::vector<Reader> readers;
    for (const TopicSpec& spec : Topics()) {
      auto* type = new RecordingType(spec.type);
      type->auto_fill_type_information(false);
      type->auto_fill_type_object(false);
      TypeSupport support(type);
      if (!participant_->find_type(type->getName())) support.register_type(participant_);
      Topic* topic =
          participant_->create_topic("rt" + spec.ros_name, type->getName(), TOPIC_QOS_DEFAULT);
      RecordingType* registered =
          static_cast<RecordingType*>(participant_->find_type(type->getName()).get());
      DataReader* reader = subscriber_->create_datareader(topic, ReaderQos(spec.qos));
      if (!reader) throw std::runtime_error("cannot create a reader on " + spec.ros_name);
      readers.push_back({spec, registered, reader});
    }
    DataWriter* estop = nullptr;
    DataWriter* malformed = nullptr;
    if (!args_.estop_on.empty()) estop = EstopWriter(false);
    if (!args_.estop_on.empty() && args_.malformed_first) malformed = EstopWriter(true);
    std::cout << "ros2_peer: listening on domain " << args_.domain << std::endl;
    bool ready = args_.ready_file.empty();

    const auto start = std::chrono::steady_clock::now();
    long count = 0;
    bool stopped = false, done = false;
    std::map<std::string, long> per_topic;
    while (!done) {
      if (!ready) {
        ready = true;
        for (const Reader& r : readers) {
          SubscriptionMatchedStatus status;
          r.reader->get_subscription_matched_status(status);
          ready = ready && status.current_count > 0;
        }
        if (ready) std::ofstream(args_.ready_file) << "ready\n";
      }
      bool any = false;
      for (Reader& r : readers) {
        DynamicData_ptr data(DynamicDataFactory::get_instance()->create_data(r.spec.type));
        SampleInfo info;
        while (r.reader->take_next_sample(data.get(), &info) == ReturnCode_t::RETCODE_OK) {
          if (!info.valid_data) continue;
          any = true;
          Json line;
          line["topic"] = r.spec.ros_name;
          line["type"] = r.spec.ros_type;
          std::string hex;
          static const char* digits = "0123456789abcdef";
          for (uint8_t b : r.type->last_bytes) {
            hex += digits[b >> 4];
            hex += digits[b & 15];
          }
          line["cdr"] = hex;
          line["fields"] = ToJson(data.get(), r.spec.type);
          out << line.dump(-1, ' ', false, Json::error_handler_t::replace) << "\n";
          ++count;
          ++per_topic[r.spec.ros_name];
          const Json& f = line["fields"];
          if (estop && !stopped && r.spec.ros_name == Ns() + "/transitions" &&
              f["data"].get<std::string>().find(args_.estop_on) != std::string::npos) {
            stopped = true;
            args_.count = 1;  // the reader has long been matched: once is enough
            if (malformed) SendMalformed(malformed);
            SendStop(estop);
            std::cout << "ros2_peer: sent the emergency stop on: " << f["data"].get<std::string>()
                      << std::endl;
          }
          if (r.spec.ros_name == "/rosout" &&
              f["msg"].get<std::string>().find(args_.until) != std::string::npos) {
            done = true;
          }
          if (args_.leave_after > 0 && count >= args_.leave_after) {
            std::cout << "ros2_peer: leaving after " << count << " messages" << std::endl;
            out.flush();
            std::_Exit(0);  // gone without a goodbye, as a crashed subscriber
          }
        }
      }
      if (done) break;
      if (std::chrono::steady_clock::now() - start >
          std::chrono::duration<double>(args_.timeout_s)) {
        std::cerr << "ros2_peer: timed out after " << args_.timeout_s << " s with " << count
                  << " messages\n";
        return 2;
      }
      if (!any) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    for (const auto& [topic, n] : per_topic) std::cout << "  " << topic << ": " << n << "\n";
    std::cout << "ros2_peer: " << count << " messages" << std::endl;
    return 0;
  }

  /// Sends one stop (or malformed Bools) once matched, then waits for the acknowledgement.
  int Estop() {
    if (args_.malformed)
      SendMalformed(EstopWriter(true));
    else
      SendStop(EstopWriter(false));
    return 0;
  }

 private:
  std::string Ns() const { return args_.ns.empty() ? "" : "/" + args_.ns; }

  /// A writer on /NS/emergency_stop: std_msgs/Bool, or (malformed) raw bytes
  /// under the same type name, from a participant of its own (one participant
  /// cannot register two types of one name).
  DataWriter* EstopWriter(bool malformed) {
    DomainParticipant* participant = participant_;
    Publisher* publisher = publisher_;
    if (malformed) {
      raw_participant_ = JoinLoopback(args_.domain, args_.lease_s);
      if (!raw_participant_) throw std::runtime_error("cannot create a second participant");
      participant = raw_participant_;
      publisher = raw_participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
    }
    TypeSupport support(malformed
                            ? static_cast<TopicDataType*>(new RawType("std_msgs::msg::dds_::Bool_"))
                            : new DynamicPubSubType(types_.bool_));
    support->auto_fill_type_information(false);
    support->auto_fill_type_object(false);
    support.register_type(participant);
    Topic* topic = participant->create_topic("rt" + Ns() + "/emergency_stop", support->getName(),
                                             TOPIC_QOS_DEFAULT);
    DataWriterQos q = DATAWRITER_QOS_DEFAULT;
    q.reliability().kind = RELIABLE_RELIABILITY_QOS;
    q.durability().kind = VOLATILE_DURABILITY_QOS;
    q.history().kind = KEEP_LAST_HISTORY_QOS;
    q.history().depth = 10;
    DataWriter* w = publisher->create_datawriter(topic, q);
    if (!w) throw std::runtime_error("cannot create the emergency-stop writer");
    return w;
  }

  /// Waits for aerograsp's reader to be matched (so nothing is written into
  /// the void), writes, and waits for the acknowledgement.
  /// A volatile reader accepts only what a writer sends after the reader has
  /// discovered it, and the two discover each other in either order: a
  /// message written the moment our writer sees the reader may be
  /// acknowledged and dropped as history. So `write` goes out `count` times,
  /// `kRepeatPeriodMs` apart (as an emergency-stop button repeats its state).
  /// `ack_wait_s` bounds the wait for the acknowledgement: a reader that
  /// cannot decode a message may never acknowledge it.
  void WhenMatched(DataWriter* w, const std::function<void()>& write, int ack_wait_s = 10) {
    const auto start = std::chrono::steady_clock::now();
    PublicationMatchedStatus status;
    while (w->get_publication_matched_status(status) == ReturnCode_t::RETCODE_OK &&
           status.current_count == 0) {
      if (std::chrono::steady_clock::now() - start > std::chrono::seconds(30))
        throw std::runtime_error("no emergency-stop reader matched within 30 s");
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    for (int i = 0; i < args_.count; ++i) {
      if (i > 0) std::this_thread::sleep_for(std::chrono::milliseconds(kRepeatPeriodMs));
      write();
    }
    w->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(ack_wait_s, 0));
  }
  static constexpr int kRepeatPeriodMs = 50;

  void SendMalformed(DataWriter* w) {
    WhenMatched(
        w,
        [w] {
          // Encapsulation CDR_LE, then the bool's byte: 7 is neither false nor true.
          std::vector<uint8_t> bad = {0x00, 0x01, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00};
          w->write(&bad);
          std::vector<uint8_t> truncated = {0x00, 0x01, 0x00, 0x00};  // no byte at all
          w->write(&truncated);
        },
        /*ack_wait_s=*/0);
    std::cout << "ros2_peer: sent two malformed emergency stops" << std::endl;
  }

  void SendStop(DataWriter* w) {
    WhenMatched(w, [this, w] {
      DynamicData_ptr stop(DynamicDataFactory::get_instance()->create_data(types_.bool_));
      stop->set_bool_value(true, 0);
      w->write(stop.get());
    });
  }

  Args args_;
  Types types_;
  DomainParticipant* participant_ = nullptr;
  Subscriber* subscriber_ = nullptr;
  Publisher* publisher_ = nullptr;
  DomainParticipant* raw_participant_ = nullptr;
};

int Usage() {
  std::cerr << "usage: ros2_peer listen DOMAIN NS OUT.jsonl [--until TEXT] [--timeout-s S]\n"
               "                 [--estop-on TEXT] [--malformed-first] [--no-images]\n"
               "                 [--leave-after N] [--ready-file PATH]\n"
               "                 [--lease-s S]\n"
               "       ros2_peer estop DOMAIN NS [--malformed] [--count N]\n";
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) return Usage();
  const std::string mode = argv[1];
  Args args;
  args.domain = std::stoi(argv[2]);
  args.ns = argv[3];
  int i = 4;
  if (mode == "listen") {
    if (argc < 5) return Usage();
    args.out = argv[i++];
  } else if (mode != "estop") {
    return Usage();
  }
  for (; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--until")
      args.until = value();
    else if (a == "--timeout-s")
      args.timeout_s = std::stod(value());
    else if (a == "--estop-on")
      args.estop_on = value();
    else if (a == "--malformed-first")
      args.malformed_first = true;
    else if (a == "--malformed")
      args.malformed = true;
    else if (a == "--no-images")
      args.no_images = true;
    else if (a == "--leave-after")
      args.leave_after = std::stol(value());
    else if (a == "--ready-file")
      args.ready_file = value();
    else if (a == "--lease-s")
      args.lease_s = std::stod(value());
    else if (a == "--count")
      args.count = std::stoi(value());
    else
      return Usage();
  }
  try {
    Peer peer(args);
    return mode == "listen" ? peer.Listen() : peer.Estop();
  } catch (const std::exception& e) {
    std::cerr << "ros2_peer: " << e.what() << "\n";
    return 1;
  }
}
