// cairn_hue_depth: fit the seed paper's hue-to-depth quadratic (Eq. 10) to calibration samples.
// Input CSV lines: "hue_deg,depth_cm" or "r,g,b,depth_cm" (hue by Joblove-Greenberg, Eqs. 11-12);
// '#' lines and a non-numeric header are skipped. Prints a, b, c, the RMS and max residual.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "robot_agent/core/objects/hue_depth.h"

int main(int argc, char** argv) {
  CLI::App app{"Fit d = a H^2 + b H + c (seed paper Eq. 10) to hue/depth samples"};
  std::string path;
  app.add_option("samples", path, "CSV: hue_deg,depth_cm or r,g,b,depth_cm per line")->required();
  CLI11_PARSE(app, argc, argv);
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "cairn_hue_depth: cannot read %s\n", path.c_str());
    return 1;
  }
  std::vector<cairn::agent::HueDepthSample> samples;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream s(line);
    std::vector<double> v;
    double x;
    while (s >> x) v.push_back(x);
    if (v.size() == 2)
      samples.push_back({v[0], v[1]});
    else if (v.size() == 4)
      samples.push_back({cairn::agent::jg_hue_deg(v[0], v[1], v[2]), v[3]});
    else if (v.empty() && samples.empty())
      continue;  // a header line
    else {
      std::fprintf(stderr, "cairn_hue_depth: %s:%d: expected 2 or 4 numbers\n", path.c_str(), line_no);
      return 1;
    }
  }
  const cairn::agent::HueDepthFit fit = cairn::agent::fit_hue_depth(samples);
  if (!fit.converged) {
    std::fprintf(stderr, "cairn_hue_depth: %s\n", fit.reason.c_str());
    return 1;
  }
  std::printf("samples %zu\nd_cm = %.6g * H^2 + %.6g * H + %.6g\nrms %.4f cm, max %.4f cm\n", samples.size(),
              fit.model.a, fit.model.b, fit.model.c, fit.score, fit.max_abs_residual_cm);
  return 0;
}
