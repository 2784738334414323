// cairn_eval: scores a mission's results against the simulator's ground truth.
#include <CLI/CLI.hpp>

#include <iostream>

#include "common/errors.h"
#include "tools/eval/mission_eval.h"

int main(int argc, char** argv) {
  CLI::App app{"Cairn mission evaluation"};
  std::string gt_dir, results_dir;
  bool json = false;
  app.add_option("--ground-truth", gt_dir, "folder with gt_robot<N>.csv and gt_objects.csv")->required();
  app.add_option("--results", results_dir, "folder with trajectory_robot<N>.csv and objects.csv")->required();
  app.add_flag("--json", json, "print JSON instead of text");
  CLI11_PARSE(app, argc, argv);
  try {
    const auto score = cairn::eval::evaluate_mission(gt_dir, results_dir);
    std::cout << (json ? cairn::eval::to_json(score).dump(2) + "\n" : cairn::eval::format_score(score));
  } catch (const cairn::InputError& e) {
    std::cerr << "cairn_eval: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
