// The topic table of dds/topics.h against the "Topics and QoS" table of docs/architecture.md: the
// doc must list exactly the topics the code declares, with their message types.
#include "dds/topics.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace cairn::dds {
namespace {

using TopicTypes = std::map<std::string, std::string>;  ///< topic name (per-robot: with <N>) -> IDL type

/// The IDL type name of a topic's message, from its generated PubSubType ("cairn_msgs::Keyframe" -> "Keyframe").
template <typename Topic>
std::string type_name() {
  const std::string full = typename Topic::PubSub().getName();
  const auto colons = full.rfind("::");
  return colons == std::string::npos ? full : full.substr(colons + 2);
}

template <typename... Topics>
TopicTypes code_topics(TopicList<Topics...>) {
  return {{Topics::kName, type_name<Topics>()}...};
}

/// The `backticked` words of a table cell, in order.
std::vector<std::string> backticked(const std::string& cell) {
  std::vector<std::string> out;
  for (size_t open = cell.find('`'); open != std::string::npos; open = cell.find('`', open)) {
    const size_t close = cell.find('`', open + 1);
    if (close == std::string::npos) break;
    out.push_back(cell.substr(open + 1, close - open - 1));
    open = close + 1;
  }
  return out;
}

std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream s(row.substr(row.find('|') + 1));
  for (std::string cell; std::getline(s, cell, '|');) out.push_back(cell);
  return out;
}

/// The topics of the table under the heading "## Topics and QoS". In a row naming several topics
/// (`cairn/robot<N>/odometry`, `laser_scan`, ...) a name without '/' shares the first one's prefix.
/// Problems with the table itself go to `problems`.
TopicTypes doc_topics(std::istream& doc, std::vector<std::string>* problems) {
  TopicTypes out;
  std::string line;
  bool in_section = false, in_table = false;
  while (std::getline(doc, line)) {
    if (line.rfind("## ", 0) == 0) {
      if (in_section) break;
      in_section = line.rfind("## Topics and QoS", 0) == 0;
      continue;
    }
    if (!in_section) continue;
    if (line.rfind("|", 0) != 0) {
      if (in_table) break;
      continue;
    }
    const bool header = !in_table;
    in_table = true;
    const auto row = cells(line);
    if (header || row.empty() || row[0].find("---") != std::string::npos) continue;
    const auto names = backticked(row[0]);
    const auto types = row.size() > 1 ? backticked(row[1]) : std::vector<std::string>{};
    if (names.size() != types.size()) {
      problems->push_back("row '" + line + "' names " + std::to_string(names.size()) + " topics but " +
                          std::to_string(types.size()) + " types");
      continue;
    }
    std::string prefix;
    for (size_t i = 0; i < names.size(); ++i) {
      const auto slash = names[i].rfind('/');
      if (slash != std::string::npos) prefix = names[i].substr(0, slash + 1);
      const std::string name = slash == std::string::npos ? prefix + names[i] : names[i];
      if (!out.emplace(name, types[i]).second) problems->push_back("topic " + name + " is listed twice");
    }
  }
  if (out.empty()) problems->push_back("no \"## Topics and QoS\" table found");
  return out;
}

/// One line per difference, naming the topic.
std::vector<std::string> compare(const TopicTypes& code, const TopicTypes& doc) {
  std::vector<std::string> problems;
  for (const auto& [name, type] : code) {
    auto it = doc.find(name);
    if (it == doc.end()) {
      problems.push_back("missing from the doc: " + name + " (" + type + ")");
    } else if (it->second != type) {
      problems.push_back("topic " + name + ": the doc says type " + it->second + ", dds/topics.h says " + type);
    }
  }
  for (const auto& [name, type] : doc) {
    if (!code.count(name)) problems.push_back("not in dds/topics.h: " + name + " (" + type + ")");
  }
  return problems;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += "\n  " + l;
  return out;
}

TEST(Topics, ArchitectureDocListsExactlyTheTopicTable) {
  const std::string path = std::string(CAIRN_SOURCE_DIR) + "/docs/architecture.md";
  std::ifstream doc(path);
  ASSERT_TRUE(doc) << "cannot open " << path;
  std::vector<std::string> problems;
  const TopicTypes listed = doc_topics(doc, &problems);
  for (const auto& p : compare(code_topics(AllTopics{}), listed)) problems.push_back(p);
  EXPECT_TRUE(problems.empty()) << path << " \"Topics and QoS\" disagrees with dds/topics.h:" << joined(problems);
}

TEST(Topics, DocCheckNamesTheMissingAndTheExtraTopic) {
  std::istringstream doc(
      "## Topics and QoS (`dds/qos.cpp`)\n\n"
      "| topic | type | QoS |\n|---|---|---|\n"
      "| `cairn/robot<N>/odometry`, `rgbd` | `Odometry`, `RgbdFrame` | reliable |\n"
      "| `cairn/keyframe` | `Keyframe` (key: robot) | reliable |\n"
      "| `cairn/typo` | `Ack` | reliable |\n\n"
      "| `cairn/after_the_table` | `Ack` | |\n"
      "## Next\n| `cairn/other_section` | `Ack` | |\n");
  std::vector<std::string> problems;
  const TopicTypes listed = doc_topics(doc, &problems);
  EXPECT_TRUE(problems.empty()) << joined(problems);
  EXPECT_EQ(listed, (TopicTypes{{"cairn/robot<N>/odometry", "Odometry"},
                                {"cairn/robot<N>/rgbd", "RgbdFrame"},
                                {"cairn/keyframe", "Keyframe"},
                                {"cairn/typo", "Ack"}}));
  const TopicTypes code = {{"cairn/robot<N>/odometry", "Odometry"},
                           {"cairn/robot<N>/rgbd", "RgbdFrame"},
                           {"cairn/keyframe", "KeyframePoses"},
                           {"cairn/ack", "Ack"}};
  EXPECT_EQ(compare(code, listed),
            (std::vector<std::string>{
                "missing from the doc: cairn/ack (Ack)",
                "topic cairn/keyframe: the doc says type Keyframe, dds/topics.h says KeyframePoses",
                "not in dds/topics.h: cairn/typo (Ack)",
            }));
}

TEST(Topics, PerRobotNamesCarryTheRobotId) {
  EXPECT_EQ(topic_name<OdometryTopic>(RobotId(3)), "cairn/robot3/odometry");
  EXPECT_EQ(topic_name<LaserScanTopic>(RobotId(0)), "cairn/robot0/laser_scan");
  EXPECT_EQ(topic_name<RgbdTopic>(RobotId(12)), "cairn/robot12/rgbd");
  EXPECT_EQ(topic_name<KeyframeTopic>(), "cairn/keyframe");
}

}  // namespace
}  // namespace cairn::dds
