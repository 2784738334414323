// Every DDS sample type a Cairn process reads from the network: the first byte picks the type, the
// rest is the serialized sample (CDR with its encapsulation). A corrupt sample must be refused by
// from_cdr or from_msg, never crash a reader.
#include "common/keyframe.h"
#include "fuzz/decode_record.h"
#include "fuzz/fuzz_input.h"

namespace {

using namespace cairn;

enum Type : uint8_t {
  kOdometry,
  kLaserScan,
  kRgbdFrame,
  kKeyframe,
  kKeyframePoses,
  kObjectReport,
  kRobotStatus,
  kVelocityCommand,
  kExplorationGoal,
  kOperatorCommand,
  kTypeCount
};

template <typename PubSubType, typename Msg>
void write_seed(const std::string& dir, Type type, const Msg& msg) {
  std::vector<uint8_t> bytes = dds::to_cdr<PubSubType>(msg);
  bytes.insert(bytes.begin(), uint8_t(type));
  fuzz::write_file(dir, "sample-" + std::to_string(int(type)), bytes.data(), bytes.size());
}

// One whole sample of each type; the keyframe a real one (its scan zstd-compressed), the others
// with their default (empty) fields: what the fuzzer needs is the shape of the CDR.
void write_seeds(const std::string& dir) {
  Keyframe kf;
  kf.id = {RobotId(1), 3};
  kf.T_local_base = SE2(1.0, 2.0, 0.3);
  kf.scan.angle_min_rad = -float(M_PI);
  kf.scan.angle_increment_rad = float(2 * M_PI / 90);
  kf.scan.range_max_m = 12.f;
  for (int i = 0; i < 90; ++i) kf.scan.ranges_m.push_back(1.f + 0.02f * float(i));
  write_seed<cairn_msgs::OdometryPubSubType>(dir, kOdometry, cairn_msgs::Odometry());
  write_seed<cairn_msgs::LaserScanPubSubType>(dir, kLaserScan, dds::to_msg(RobotId(1), kf.scan));
  write_seed<cairn_msgs::RgbdFramePubSubType>(dir, kRgbdFrame, cairn_msgs::RgbdFrame());
  write_seed<cairn_msgs::KeyframePubSubType>(dir, kKeyframe, dds::to_msg(kf));
  write_seed<cairn_msgs::KeyframePosesPubSubType>(dir, kKeyframePoses, cairn_msgs::KeyframePoses());
  write_seed<cairn_msgs::ObjectReportPubSubType>(dir, kObjectReport, cairn_msgs::ObjectReport());
  write_seed<cairn_msgs::RobotStatusPubSubType>(dir, kRobotStatus, cairn_msgs::RobotStatus());
  write_seed<cairn_msgs::VelocityCommandPubSubType>(dir, kVelocityCommand, cairn_msgs::VelocityCommand());
  write_seed<cairn_msgs::ExplorationGoalPubSubType>(dir, kExplorationGoal, cairn_msgs::ExplorationGoal());
  write_seed<cairn_msgs::OperatorCommandPubSubType>(dir, kOperatorCommand, cairn_msgs::OperatorCommand());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const std::string dir = fuzz::seeds_dir(); !dir.empty()) write_seeds(dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // Indexed by Type.
  using Decoder = void (*)(const std::vector<uint8_t>&);
  static constexpr Decoder kDecoders[kTypeCount] = {
      &fuzz::decode_sample<cairn_msgs::OdometryPubSubType, cairn_msgs::Odometry>,
      &fuzz::decode_sample<cairn_msgs::LaserScanPubSubType, cairn_msgs::LaserScan>,
      &fuzz::decode_sample<cairn_msgs::RgbdFramePubSubType, cairn_msgs::RgbdFrame>,
      &fuzz::decode_sample<cairn_msgs::KeyframePubSubType, cairn_msgs::Keyframe>,
      &fuzz::decode_sample<cairn_msgs::KeyframePosesPubSubType, cairn_msgs::KeyframePoses>,
      &fuzz::decode_sample<cairn_msgs::ObjectReportPubSubType, cairn_msgs::ObjectReport>,
      &fuzz::decode_status,
      &fuzz::decode_sample<cairn_msgs::VelocityCommandPubSubType, cairn_msgs::VelocityCommand>,
      &fuzz::decode_sample<cairn_msgs::ExplorationGoalPubSubType, cairn_msgs::ExplorationGoal>,
      &fuzz::decode_sample<cairn_msgs::OperatorCommandPubSubType, cairn_msgs::OperatorCommand>,
  };
  if (size < 1) return 0;
  kDecoders[data[0] % kTypeCount](std::vector<uint8_t>(data + 1, data + size));
  return 0;
}
