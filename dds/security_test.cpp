// DDS Security over real Fast DDS: participants whose certificates the mission CA signed find each
// other and exchange samples; one without certificates, or with another CA's, never matches.
// Material from deploy/security/make_certs.sh (needs the openssl command).
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <thread>
#include <utility>
#include <vector>

#include "cairn_msgsPubSubTypes.h"
#include "dds/conversions.h"
#include "dds/domain_lease.h"
#include "dds/endpoints.h"

namespace cairn::dds {
namespace {

namespace fs = std::filesystem;
using KeyframeWriter = Writer<KeyframeTopic>;
using KeyframeReader = Reader<KeyframeTopic>;

class Security : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::path(::testing::TempDir()) / ("dds_security_" + std::to_string(getpid())));
    fs::remove_all(*dir_);
    const std::string script = std::string(CAIRN_SOURCE_DIR) + "/deploy/security/make_certs.sh";
    made_ = std::system(("bash " + script + " " + (*dir_ / "team").string() + " base robot0 > /dev/null && bash " +
                         script + " " + (*dir_ / "intruders").string() + " robot9 > /dev/null")
                            .c_str()) == 0;
  }
  void SetUp() override {
    if (!made_) GTEST_SKIP() << "could not make certificates (is openssl installed?)";
    lease_ = DomainLease::claim({}, &error_);
    ASSERT_TRUE(lease_) << error_;
  }
  std::unique_ptr<Participant> participant(const std::string& name, const std::string& identity) {
    ParticipantOptions o;
    o.domain_id = lease_->domain_id();
    o.name = name;
    if (!identity.empty()) o.security_dir = (*dir_ / identity).string();
    auto p = Participant::create(o, &error_);
    EXPECT_TRUE(p) << error_;
    return p;
  }
  static bool matched_within(KeyframeWriter& w, KeyframeReader& r, double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      if (w.matched_readers() > 0 && r.matched_writers() > 0) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }
  static cairn_msgs::Keyframe keyframe(int seq) {
    Keyframe kf;
    kf.id = {RobotId(0), seq};
    kf.scan.angle_increment_rad = 0.01f;
    kf.scan.range_max_m = 10.f;
    kf.scan.ranges_m.assign(360, 2.0f);
    return to_msg(kf);
  }
  /// Writes `n` keyframes and returns those the reader got within `seconds`, with their writers.
  static std::vector<KeyframeReader::FromWriter> received(KeyframeWriter& w, KeyframeReader& r, double seconds,
                                                          int n = 3) {
    for (int i = 0; i < n; ++i) w.write(keyframe(i));
    std::vector<KeyframeReader::FromWriter> got;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (got.size() < size_t(n) && std::chrono::steady_clock::now() < end) {
      for (auto& s : r.take_all_from_writers()) got.push_back(std::move(s));
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return got;
  }
  /// How many of three keyframes written the reader got within `seconds`.
  static size_t exchange(KeyframeWriter& w, KeyframeReader& r, double seconds) {
    return received(w, r, seconds).size();
  }

  /// A writer on `from` and a reader on `to` never match, and nothing written arrives.
  static void expect_isolated(Participant& from, Participant& to) {
    KeyframeWriter w(from);
    KeyframeReader r(to);
    EXPECT_FALSE(matched_within(w, r, 4.0));
    EXPECT_EQ(exchange(w, r, 1.0), 0u);
  }
  /// A folder `name` with each file copied from the identity folder given with it.
  static fs::path identity(const std::string& name, const std::vector<std::pair<std::string, std::string>>& files) {
    const fs::path dir = *dir_ / name;
    fs::create_directories(dir);
    for (const auto& [file, from] : files) {
      fs::copy_file(*dir_ / from / file, dir / file, fs::copy_options::overwrite_existing);
    }
    return dir;
  }
  /// Creating a participant with the identity in `dir` fails; returns the error.
  std::string create_error(const fs::path& dir) {
    ParticipantOptions o;
    o.domain_id = lease_->domain_id();
    o.security_dir = dir.string();
    std::string error;
    EXPECT_EQ(Participant::create(o, &error), nullptr);
    return error;
  }

  static fs::path* dir_;
  static bool made_;
  std::unique_ptr<DomainLease> lease_;
  std::string error_;
};
fs::path* Security::dir_ = nullptr;
bool Security::made_ = false;

TEST_F(Security, TeamMembersAuthenticateAndExchangeKeyframes) {
  auto robot = participant("robot0", "team/robot0");
  auto base = participant("base", "team/base");
  ASSERT_TRUE(robot && base);
  KeyframeWriter w(*robot);
  KeyframeReader r(*base);
  ASSERT_TRUE(matched_within(w, r, 20.0));
  EXPECT_EQ(exchange(w, r, 10.0), 3u);
}

TEST_F(Security, AParticipantKeptToItsHostStillHearsItsTeamOnThatHost) {
  // The simulator's same-host filter (ParticipantOptions::same_host_only) judges hosts by the GUID
  // prefix, which under PKI-DH comes from the certificate: left on, it ignored every agent.
  ParticipantOptions o;
  o.domain_id = lease_->domain_id();
  o.name = "sim";
  o.same_host_only = true;
  o.security_dir = (*dir_ / "team/base").string();
  auto sim = Participant::create(o, &error_);
  auto robot = participant("robot0", "team/robot0");
  ASSERT_TRUE(sim && robot) << error_;
  KeyframeWriter w(*sim);
  KeyframeReader r(*robot);
  ASSERT_TRUE(matched_within(w, r, 20.0));
  EXPECT_EQ(exchange(w, r, 10.0), 3u);
}

TEST_F(Security, ASamplesWriterIsKnownByTheCertificateItAuthenticatedWith) {
  auto robot = participant("robot0", "team/robot0");
  auto base = participant("base", "team/base");
  ASSERT_TRUE(robot && base);
  KeyframeWriter w(*robot);
  KeyframeReader r(*base);
  ASSERT_TRUE(matched_within(w, r, 20.0));
  const auto got = received(w, r, 10.0, 1);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_TRUE(authenticated_as(got[0].writer, robot_identity(0)));
  EXPECT_FALSE(authenticated_as(got[0].writer, robot_identity(1)));
  EXPECT_FALSE(authenticated_as(got[0].writer, "base"));
  // Without security Fast DDS starts a prefix with its vendor id (first bit 0): no certificate.
  const GuidPrefix open_prefix{0x01, 0x0f, 0x5a, 0x11, 0x22, 0x33, 0, 0, 0, 0, 0, 1};
  EXPECT_FALSE(authenticated_as(open_prefix, robot_identity(0)));
}

TEST_F(Security, AParticipantWithoutCertificatesHearsNothing) {
  auto robot = participant("robot0", "team/robot0");
  auto eavesdropper = participant("eavesdropper", "");
  ASSERT_TRUE(robot && eavesdropper);
  expect_isolated(*robot, *eavesdropper);
}

TEST_F(Security, AnotherCasCertificateIsRefused) {
  auto base = participant("base", "team/base");
  auto intruder = participant("intruder", "intruders/robot9");
  ASSERT_TRUE(base && intruder);
  expect_isolated(*intruder, *base);
}

TEST_F(Security, AMissingKeyIsNamed) {
  const fs::path dir = identity("partial", {{"ca.pem", "team/robot0"}, {"cert.pem", "team/robot0"}});
  EXPECT_NE(create_error(dir).find((dir / "key.pem").string()), std::string::npos);
}

TEST_F(Security, AKeyThatIsNotTheCertificatesIsRefused) {
  const fs::path dir =
      identity("mixed", {{"ca.pem", "team/robot0"}, {"cert.pem", "team/robot0"}, {"key.pem", "team/base"}});
  EXPECT_NE(create_error(dir).find("DDS security from " + dir.string()), std::string::npos);
}

}  // namespace
}  // namespace cairn::dds
