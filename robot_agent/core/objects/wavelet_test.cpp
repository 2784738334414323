#include "robot_agent/core/objects/wavelet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace cairn::agent {
namespace {

ImageD random_image(int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  ImageD im(rows, cols);
  for (double& v : im.data) v = u(rng);
  return im;
}

class WaveletTypes : public ::testing::TestWithParam<WaveletType> {};

TEST_P(WaveletTypes, FilterIsOrthonormal) {
  const std::vector<double> h = wavelet_lowpass(GetParam());
  double sum = 0, sq = 0;
  for (double v : h) sum += v, sq += v * v;
  EXPECT_NEAR(sum, std::sqrt(2.0), 1e-10);
  EXPECT_NEAR(sq, 1.0, 1e-10);
}

TEST_P(WaveletTypes, OneDimensionalRoundTripIsExact) {
  std::vector<double> x(64);
  for (size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.3 * double(i)) * 50 + double(i % 7);
  const std::vector<double> y = idwt_1d(dwt_1d(x, GetParam()), GetParam());
  ASSERT_EQ(y.size(), x.size());
  for (size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(y[i], x[i], 1e-9);
}

TEST_P(WaveletTypes, TwoDimensionalMultiLevelRoundTripIsExact) {
  const ImageD im = random_image(48, 64, 3);
  const Dwt2dResult fwd = dwt_2d(im, 3, GetParam());
  ASSERT_TRUE(fwd.converged) << fwd.reason;
  const ImageD back = idwt_2d(fwd.coeffs, 3, GetParam());
  ASSERT_EQ(back.data.size(), im.data.size());
  double max_err = 0.0, energy_in = 0.0, energy_out = 0.0;
  for (size_t i = 0; i < im.data.size(); ++i) {
    max_err = std::max(max_err, std::abs(back.data[i] - im.data[i]));
    energy_in += im.data[i] * im.data[i];
    energy_out += fwd.coeffs.data[i] * fwd.coeffs.data[i];
  }
  EXPECT_LT(max_err, 1e-9);
  EXPECT_NEAR(energy_out / energy_in, 1.0, 1e-10);  // Parseval: the transform is orthogonal
}

INSTANTIATE_TEST_SUITE_P(All, WaveletTypes,
                         ::testing::Values(WaveletType::kHaar, WaveletType::kDaubechies4Tap,
                                           WaveletType::kDaubechies8Tap));

TEST(Wavelet, HaarOfAConstantIsAllApproximation) {
  const Dwt2dResult r = dwt_2d(ImageD(8, 8, 1.0), 1, WaveletType::kHaar);
  ASSERT_TRUE(r.converged);
  EXPECT_NEAR(r.coeffs.at(0, 0), 2.0, 1e-12);  // (1/sqrt2)^2 * 4
  EXPECT_NEAR(r.coeffs.at(0, 4), 0.0, 1e-12);
  EXPECT_NEAR(r.coeffs.at(5, 5), 0.0, 1e-12);
}

TEST(Wavelet, FusionOfAnImageWithItselfIsTheImage) {
  const ImageD im = random_image(32, 32, 5);
  const Dwt2dResult f = fuse_wavelet(im, im, 2, WaveletType::kDaubechies4Tap);
  ASSERT_TRUE(f.converged);
  for (size_t i = 0; i < im.data.size(); ++i) EXPECT_NEAR(f.coeffs.data[i], im.data[i], 1e-9);
}

TEST(Wavelet, BadSizesGiveAReason) {
  const Dwt2dResult r = dwt_2d(ImageD(30, 32), 2, WaveletType::kHaar);
  EXPECT_FALSE(r.converged);
  EXPECT_FALSE(r.reason.empty());
  EXPECT_TRUE(dwt_1d({1.0, 2.0, 3.0}, WaveletType::kHaar).empty());
  EXPECT_FALSE(fuse_wavelet(ImageD(8, 8), ImageD(16, 8), 1, WaveletType::kHaar).converged);
  EXPECT_FALSE(dwt_2d(ImageD(), 1, WaveletType::kHaar).converged);
}

}  // namespace
}  // namespace cairn::agent
