#pragma once
// Monocular hue-to-depth cue of the seed paper (Sec. 2.2): the Joblove-Greenberg hue of an RGB
// colour (Eqs. 11-12) and the quadratic calibration d = a H^2 + b H + c (Eq. 10, paper
// coefficients a = 0.0032, b = -1.9492, c = 359.26, d in cm, H in degrees), plus a least-squares
// fit of the quadratic to calibration samples. Valid only for one object colour under one fixed
// illumination: hue does not depend on distance physically, it changes only through lighting
// fall-off and sensor response. See docs/objects.md.
#include <string>
#include <vector>

namespace cairn::agent {

/// Joblove-Greenberg hue in degrees, [0, 360). r, g, b share any scale (0..1 or 0..255).
/// Neutral colours (C = max - min = 0) give 0, as Eq. 11 specifies.
double jg_hue_deg(double r, double g, double b);

/// Eq. 10: depth in centimetres from the hue in degrees.
struct HueDepthModel {
  double a = 0.0032;
  double b = -1.9492;
  double c = 359.26;
  double depth_cm(double hue_deg) const { return (a * hue_deg + b) * hue_deg + c; }
};

struct HueDepthSample {
  double hue_deg = 0.0;
  double depth_cm = 0.0;
};

struct HueDepthFit {
  HueDepthModel model;
  bool converged = false;
  double score = 0.0;  ///< RMS residual, cm
  double max_abs_residual_cm = 0.0;
  std::string reason;  ///< why not converged
};

/// Least-squares quadratic (Eq. 10 form) through >= 3 samples with >= 3 distinct hues.
HueDepthFit fit_hue_depth(const std::vector<HueDepthSample>& samples);

/// The hue of the mean colour of RGB8 pixels (as the paper does: average the object's RGB, then
/// convert). `rgb` holds n*3 bytes; `mask` (n bytes, may be empty = all) selects pixels.
/// Returns a negative value when no pixel is selected.
double mean_hue_deg(const std::vector<unsigned char>& rgb, const std::vector<unsigned char>& mask);

}  // namespace cairn::agent
