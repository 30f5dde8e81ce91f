// Free flight: closed-form translation, constant-omega and torque-free rotation (PHYSICS.md section 2).
#include <gtest/gtest.h>

#include <cmath>

#include "vaw/dynamics/free_flight.hpp"
#include "vaw/dynamics/gravity.hpp"

using namespace vaw::dyn;

namespace {

// A 0.2 x 0.1 x 0.05 m steel block: three distinct principal moments.
Eigen::Matrix3d blockInertia() {
  const double m = 7850 * 0.2 * 0.1 * 0.05, a = 0.2, b = 0.1, c = 0.05;
  return (m / 12.0 * Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b)).asDiagonal();
}

}  // namespace

TEST(Ballistic, ExactAtAnyTimeIndependentOfStep) {
  Release r;
  r.t0 = 1.25;
  r.position = {0.1, -0.2, 1.0};
  r.velocity = {0.5, 0.3, 1.2};
  const Eigen::Vector3d g = 0.25 * worldGravity();
  for (double t : {1.25, 1.3, 2.0, 3.7}) {
    const double dt = t - r.t0;
    const Eigen::Vector3d want(0.1 + 0.5 * dt, -0.2 + 0.3 * dt, 1.0 + 1.2 * dt - 0.5 * 0.25 * 9.80665 * dt * dt);
    EXPECT_LE((ballisticPosition(r, g, t) - want).norm(), 4 * std::numeric_limits<double>::epsilon() * want.norm());
  }
  // Evaluated from the release time, not accumulated: the same time gives the same bits however the
  // frames before it were stepped.
  EXPECT_EQ(ballisticPosition(r, g, 2.0), ballisticPosition(r, g, r.t0 + 0.75));
  EXPECT_NEAR(timeToHeight(r, g, 0.0), (1.2 + std::sqrt(1.44 + 2 * 0.25 * 9.80665)) / (0.25 * 9.80665), 1e-12);
}

TEST(TorqueFree, ConservesEnergyAndMomentum) {
  Release r;
  r.omega = {3.0, 1.0, 5.0};
  r.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()));
  TorqueFree tf(r, blockInertia());
  const double e0 = tf.kineticEnergy();
  const Eigen::Vector3d L0 = tf.angularMomentum();
  for (int i = 0; i < 900; ++i) tf.step(1.0 / 90.0);  // 10 s at 90 Hz
  // Bounds: RK4 at 90 Hz with |w| h = 0.07: energy to 1e-6, L to round-off (L is the model's invariant).
  EXPECT_NEAR(tf.kineticEnergy(), e0, 1e-6 * e0);
  const Eigen::Matrix3d R = tf.orientation().toRotationMatrix();
  const Eigen::Vector3d L = R * blockInertia() * tf.omegaBody();
  EXPECT_LE((L - L0).norm(), 1e-12 * L0.norm());
  // Against the reference (Dormand-Prince, 1e-12).
  EXPECT_LT(angleBetween(tf.orientation(), TorqueFree::reference(r, blockInertia(), 10.0)), 1e-4);
}

TEST(TorqueFree, TennisRacketFlipsWithTheEllipticPeriod) {
  // Spin about the intermediate axis (y) with a small perturbation: w_y changes sign periodically with
  // period 4 K(k) / lambda (Landau & Lifshitz, Mechanics, section 37).
  const Eigen::Matrix3d I = blockInertia();
  // Principal moments A < B < C along x, y, z (the block is longest in x); y is the intermediate axis.
  const double A = I(0, 0), B = I(1, 1), C = I(2, 2);
  ASSERT_LT(A, B);
  ASSERT_LT(B, C);
  Release r;
  r.omega = {0.01, 6.0, 0.02};  // world = body at t0 (identity orientation)
  const Eigen::Vector3d w = r.omega;
  const double twoE = w.dot(I * w);
  const double L2 = (I * w).squaredNorm();
  double lambda, k2;
  if (L2 > twoE * B) {
    lambda = std::sqrt((C - B) * (L2 - twoE * A) / (A * B * C));
    k2 = (B - A) * (twoE * C - L2) / ((C - B) * (L2 - twoE * A));
  } else {
    lambda = std::sqrt((B - A) * (twoE * C - L2) / (A * B * C));
    k2 = (C - B) * (L2 - twoE * A) / ((B - A) * (twoE * C - L2));
  }
  const double period = 4.0 * std::comp_ellint_1(std::sqrt(k2)) / lambda;
  TorqueFree tf(r, I);
  const double h = 1e-3;
  std::vector<double> ups;
  double prev = tf.omegaBody().y(), t = 0;
  while (t < 3.2 * period) {
    tf.step(h);
    t += h;
    const double cur = tf.omegaBody().y();
    if (prev < 0 && cur >= 0) ups.push_back(t - h + h * (-prev) / (cur - prev));
    prev = cur;
  }
  ASSERT_GE(ups.size(), 2u) << "the spin about the intermediate axis must flip";
  EXPECT_NEAR((ups.back() - ups.front()) / static_cast<double>(ups.size() - 1), period, 1e-4 * period);
}

TEST(TorqueFree, ConstantOmegaErrorIsReportedAndDrivesTheChoice) {
  const Eigen::Matrix3d I = blockInertia();
  Release tumbling;
  tumbling.omega = {3.0, 1.0, 5.0};
  // Measured error of the paper's model against the reference over a 1 s flight.
  double measured = 0;
  for (int i = 1; i <= 20; ++i) {
    const double t = i * 0.05;
    measured = std::max(measured, angleBetween(constantOmegaOrientation(tumbling, t), TorqueFree::reference(tumbling, I, t)));
  }
  const double predicted = predictedConstantOmegaError(tumbling, I, 1.0);
  EXPECT_GT(measured, 10 * M_PI / 180) << "a tumbling block is not a constant-omega body";
  EXPECT_NEAR(predicted, measured, 0.05 * measured);
  EXPECT_EQ(chooseRotationModel(tumbling, I, 1.0).model, RotationModel::TorqueFree);
  // Spin about a principal axis: the cheap model is exact, and chosen.
  Release spin;
  spin.omega = {0.0, 0.0, 8.0};
  const auto c = chooseRotationModel(spin, I, 1.0);
  EXPECT_EQ(c.model, RotationModel::ConstantOmega);
  EXPECT_LT(c.predictedError, 1e-7);  // round-off of the prediction's own integration
  // A short flight keeps even a tumble under 1 degree.
  EXPECT_EQ(chooseRotationModel(tumbling, I, 0.01).model, RotationModel::ConstantOmega);
}
