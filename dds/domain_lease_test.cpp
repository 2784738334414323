// Domain leases: two holders never get the same domain; a released domain is free again.
#include "dds/domain_lease.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

namespace cairn::dds {
namespace {

DomainLeaseOptions private_range() {
  DomainLeaseOptions o;
  o.lock_dir = ::testing::TempDir() + "/domain_lease_" + std::to_string(getpid());
  std::filesystem::create_directories(o.lock_dir);
  o.first_domain = 10;
  o.last_domain = 12;
  return o;
}

TEST(DomainLease, HoldersGetDistinctDomainsUntilTheRangeIsFull) {
  const auto o = private_range();
  std::string error;
  auto a = DomainLease::claim(o, &error);
  auto b = DomainLease::claim(o, &error);
  auto c = DomainLease::claim(o, &error);
  ASSERT_TRUE(a && b && c) << error;
  EXPECT_EQ(a->domain_id(), 10);
  EXPECT_EQ(b->domain_id(), 11);
  EXPECT_EQ(c->domain_id(), 12);
  EXPECT_EQ(DomainLease::claim(o, &error), nullptr);
  EXPECT_NE(error.find("no free DDS domain in 10..12"), std::string::npos) << error;
  b.reset();
  auto d = DomainLease::claim(o, &error);
  ASSERT_TRUE(d) << error;
  EXPECT_EQ(d->domain_id(), 11);
}

TEST(DomainLease, AnotherProcessSeesTheHoldAndGetsItBackWhenTheHolderExits) {
  const auto o = private_range();
  std::string error;
  int ready[2], done[2];
  ASSERT_EQ(pipe(ready), 0);
  ASSERT_EQ(pipe(done), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {  // holds domain 10 until told to exit (without releasing it explicitly)
    auto lease = DomainLease::claim(o, nullptr);
    char c = lease ? char(lease->domain_id()) : 0;
    (void)!write(ready[1], &c, 1);
    (void)!read(done[0], &c, 1);
    _exit(0);
  }
  char held = 0;
  ASSERT_EQ(read(ready[0], &held, 1), 1);
  EXPECT_EQ(held, 10);
  auto mine = DomainLease::claim(o, &error);
  ASSERT_TRUE(mine) << error;
  EXPECT_EQ(mine->domain_id(), 11);
  (void)!write(done[1], "x", 1);
  int status = 0;
  waitpid(child, &status, 0);
  auto again = DomainLease::claim(o, &error);
  ASSERT_TRUE(again) << error;
  EXPECT_EQ(again->domain_id(), 10);
}

TEST(DomainLease, UnwritableFolderIsNamedInTheError) {
  DomainLeaseOptions o;
  o.lock_dir = "/nonexistent/cairn";
  o.first_domain = o.last_domain = 5;
  std::string error;
  EXPECT_EQ(DomainLease::claim(o, &error), nullptr);
  EXPECT_NE(error.find("/nonexistent/cairn/cairn-dds-domain-5.lock"), std::string::npos) << error;
}

}  // namespace
}  // namespace cairn::dds
