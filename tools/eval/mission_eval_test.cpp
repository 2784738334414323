#include "tools/eval/mission_eval.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/errors.h"

namespace cairn::eval {
namespace {

namespace fs = std::filesystem;

struct Dirs {
  fs::path gt, res;
};

Dirs make_dirs(const std::string& name) {
  Dirs d{fs::path(::testing::TempDir()) / name / "gt", fs::path(::testing::TempDir()) / name / "res"};
  fs::create_directories(d.gt);
  fs::create_directories(d.res);
  Trajectory truth, est;
  for (int i = 0; i < 50; ++i) {
    truth.push_back({StampNs(i) * kNsPerSec / 10, SE2(0.1 * i, 0, 0)});
    if (i % 5 == 0) est.push_back({StampNs(i) * kNsPerSec / 10, SE2(0.1 * i, 0.05, 0)});
  }
  write_trajectory_csv((d.gt / "gt_robot0.csv").string(), truth);
  write_trajectory_csv((d.res / "trajectory_robot0.csv").string(), est);
  std::ofstream(d.gt / "gt_objects.csv") << "id,class,shape,x_m,y_m,z_m,yaw_rad,size_x,size_y,size_z,r,g,b\n"
                                            "0,victim,box,1,1,0.2,0,1,1,1,255,0,0\n"
                                            "1,victim,box,5,1,0.2,0,1,1,1,255,0,0\n"
                                            "2,exit,box,3,3,1.0,0,1,1,1,0,255,0\n";
  return d;
}

TEST(MissionEval, ScoresTrajectoryAndObjects) {
  const Dirs d = make_dirs("eval_ok");
  // One victim 0.1 m off, one exit labelled hazard (a false positive), one victim missed.
  std::ofstream(d.res / "objects.csv")
      << "id,class,confidence,x_m,y_m,z_m,robots,observations,size_x_m,size_y_m,size_z_m,verdict,verdict_note\n"
         "0-0,victim,0.9,1.1,1,0.2,0,5,1,1,1,confirmed,alive\n"
         "0-1,hazard,0.9,3,3,1.0,0,5,1,1,1,unreviewed,\n";  // an empty last field is a field
  const MissionScore s = evaluate_mission(d.gt.string(), d.res.string());
  ASSERT_EQ(s.robots.size(), 1u);
  ASSERT_TRUE(s.robots[0].global);
  EXPECT_NEAR(s.robots[0].global->ate_rmse_m, 0.05, 1e-6);
  EXPECT_EQ(s.robots[0].keyframes, 10);
  EXPECT_EQ(s.objects.ground_truth, 3);
  EXPECT_EQ(s.objects.detected, 2);
  EXPECT_EQ(s.objects.matched, 1);
  EXPECT_NEAR(s.objects.mean_error_xy_m, 0.1, 1e-9);
  EXPECT_NEAR(s.objects.recall(), 1.0 / 3, 1e-9);
  EXPECT_NEAR(s.objects.precision(), 0.5, 1e-9);
  ASSERT_EQ(s.classes.size(), 3u);  // exit, hazard, victim
  EXPECT_EQ(s.classes[2].class_name, "victim");
  EXPECT_EQ(s.classes[2].matched, 1);
  EXPECT_NE(format_score(s).find("victim: found 1/2"), std::string::npos);
}

TEST(MissionEval, ScoresObjectsInEachRobotsOwnFrame) {
  const Dirs d = make_dirs("eval_robot_frame");
  std::ofstream(d.res / "objects.csv")
      << "id,class,confidence,x_m,y_m,z_m,robots,observations,size_x_m,size_y_m,size_z_m\n";
  // Robot 0 started at the world origin (gt_robot0 starts there). Its local SLAM put the anchor
  // keyframe of the second report at local (1.3, 0) where it truly was at (1.0, 0) (t = 1 s).
  std::ofstream(d.gt / "gt_robots.csv") << "id,start_x,start_y,start_yaw\n0,0,0,0\n";
  std::ofstream(d.res / "objects_robot_frame.csv")
      << "id,class,robot,anchor_seq,anchor_stamp_ns,anchor_x_m,anchor_y_m,anchor_yaw_rad,x_m,y_m,z_m,observations\n"
         "0-0,victim,0,0,0,0,0,0,1.05,1,0.2,5\n"
         "0-1,victim,0,3,1000000000,1.3,0,0,5.3,1,0.2,5\n"
         "0-2,exit,0,0,0,0,0,0,9,9,1,5\n";
  const MissionScore s = evaluate_mission(d.gt.string(), d.res.string());
  ASSERT_EQ(s.robot_frame.size(), 2u);
  const RobotFrameScore& start = s.robot_frame[0];
  EXPECT_EQ(start.placement, "true start");
  EXPECT_EQ(start.objects.detected, 3);
  EXPECT_EQ(start.objects.matched, 2);
  EXPECT_EQ(start.objects.objects_found, 2);  // both victims; the exit report is far off
  const ObjectScore& victim = start.classes.back();
  ASSERT_EQ(victim.class_name, "victim");
  EXPECT_NEAR(victim.mean_error_xy_m, (0.05 + 0.3) / 2, 1e-6);
  const ObjectScore& anchored = s.robot_frame[1].classes.back();
  EXPECT_EQ(s.robot_frame[1].placement, "true anchor");
  EXPECT_EQ(anchored.matched, 2);
  EXPECT_NEAR(anchored.mean_error_xy_m, 0.05 / 2, 1e-6);  // the anchor's drift is gone
  EXPECT_NE(format_score(s).find("robot's own frame"), std::string::npos);
  EXPECT_EQ(to_json(s)["robot_frame"][0]["objects"]["objects_found"], 2);
}

TEST(MissionEval, MalformedResultsNameTheFile) {
  const Dirs d = make_dirs("eval_bad");
  std::ofstream(d.res / "objects.csv") << "id,class,confidence,x_m,y_m,z_m\n0-0,victim,0.9,abc,1,0.2\n";
  try {
    evaluate_mission(d.gt.string(), d.res.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("objects.csv: column 'x_m' has a bad value"), std::string::npos) << e.what();
  }
  fs::remove(d.res / "objects.csv");
  EXPECT_THROW(evaluate_mission(d.gt.string(), d.res.string()), InputError);
}

// The whole map turned 1 deg about the entry: every robot's global error grows with its distance
// from there, yet the map is perfect in itself; a robot misplaced against the others is not.
TEST(MissionEval, MapConsistencySeparatesTheAnchorFromTheMerge) {
  const Dirs d = make_dirs("eval_consistency");
  std::ofstream(d.res / "objects.csv")
      << "id,class,confidence,x_m,y_m,z_m,robots,observations,size_x_m,size_y_m,size_z_m\n";
  const SE2 turn(0.0, 0.0, M_PI / 180.0);
  auto write_robot = [&](int id, const SE2& T_world_start, const SE2& misplacement) {
    Trajectory truth, est;
    for (int i = 0; i < 100; ++i) {
      const SE2 pose = T_world_start * SE2(0.2 * i, 0.0, 0.0);
      truth.push_back({StampNs(i) * kNsPerSec, pose});
      est.push_back({StampNs(i) * kNsPerSec, misplacement * turn * pose});
    }
    write_trajectory_csv((d.gt / ("gt_robot" + std::to_string(id) + ".csv")).string(), truth);
    write_trajectory_csv((d.res / ("trajectory_robot" + std::to_string(id) + ".csv")).string(), est);
  };
  write_robot(0, SE2(), SE2());
  write_robot(1, SE2(0.0, 10.0, M_PI / 2), SE2());
  MissionScore s = evaluate_mission(d.gt.string(), d.res.string());
  ASSERT_TRUE(s.map_consistency);
  EXPECT_EQ(s.map_consistency->robots, 2);
  EXPECT_EQ(s.map_consistency->keyframes, 200);
  EXPECT_LT(s.map_consistency->ate_rmse_m, 1e-6);
  EXPECT_NEAR(s.map_consistency->rotation_deg, -1.0, 1e-6);
  ASSERT_TRUE(s.robots[0].global);
  EXPECT_GT(s.robots[0].global->ate_rmse_m, 0.15);  // up to 20 m x 1 deg = 0.35 m
  EXPECT_NE(format_score(s).find("the merged map in itself (2 robots"), std::string::npos);
  EXPECT_TRUE(to_json(s).contains("map_consistency"));
  write_robot(1, SE2(0.0, 10.0, M_PI / 2), SE2(0.3, 0.0, 0.0));  // robot 1 placed 0.3 m off
  s = evaluate_mission(d.gt.string(), d.res.string());
  ASSERT_TRUE(s.map_consistency);
  EXPECT_GT(s.map_consistency->ate_rmse_m, 0.05);  // the alignment shares the 0.3 m between the two
}

}  // namespace
}  // namespace cairn::eval
