#include <gtest/gtest.h>

#include "vaw/categories.hpp"
#include "vaw/primitives.hpp"

using namespace vaw;

TEST(Categories, DefaultThresholds) {
  const auto s = CategorySettings::defaults();
  EXPECT_EQ(categorize(0.3, 0.1, s).category, Category::OneHand);
  EXPECT_EQ(categorize(5.0, 0.1, s).category, Category::OneHand) << "a threshold belongs to the lighter category";
  EXPECT_EQ(categorize(5.01, 0.1, s).category, Category::TwoHand);
  EXPECT_EQ(categorize(23.0, 0.1, s).category, Category::TwoHand);
  EXPECT_EQ(categorize(23.01, 0.1, s).category, Category::Tool);
  EXPECT_EQ(categorize(250.0, 2.0, s).category, Category::Tool);
}

TEST(Categories, LightButLongNeedsTwoHands) {
  const auto s = CategorySettings::defaults();
  const auto r = categorize(0.5, 0.6, s);
  EXPECT_EQ(r.category, Category::TwoHand);
  EXPECT_NE(r.reason.find("0.6 m long"), std::string::npos) << r.reason;
}

TEST(Categories, ReasonsNameTheLimit) {
  const auto s = CategorySettings::defaults();
  EXPECT_NE(categorize(30.0, 0.2, s).reason.find("two-hand limit of 23 kg"), std::string::npos);
  EXPECT_NE(categorize(7.0, 0.2, s).reason.find("one-hand limit of 5 kg"), std::string::npos);
}

TEST(Categories, StricterPresetForAWiderPopulation) {
  const auto s = CategorySettings::stricter();
  EXPECT_EQ(s.preset, "stricter");
  EXPECT_EQ(categorize(4.0, 0.1, s).category, Category::TwoHand);
  EXPECT_EQ(categorize(20.0, 0.1, s).category, Category::Tool);
  CategorySettings byName;
  EXPECT_TRUE(CategorySettings::byName("stricter", byName));
  EXPECT_DOUBLE_EQ(byName.twoHandMaxMass, 16.0);
  EXPECT_FALSE(CategorySettings::byName("superhuman", byName));
}

TEST(Categories, ExtentAlongPrincipalAxes) {
  TriMesh rod = primitives::box({0.5, 0.02, 0.02});
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.6, Eigen::Vector3d(0, 0, 1)).toRotationMatrix();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  rod.transform(T);
  // Measured along the rod's own axes the length is exact; world axes would give less.
  EXPECT_NEAR(principalExtent(rod, R), 0.5, 1e-12);
  EXPECT_LT(principalExtent(rod, Eigen::Matrix3d::Identity()), 0.45);
}
