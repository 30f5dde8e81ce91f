// The STEP reader's first pass (plugins/step/step_first_pass.hpp) on Part 21 text written here: what it
// refuses, with the entity and line named, what it rewrites, and what it leaves alone.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "step_first_pass.hpp"

namespace {

using vaw::step::firstPass;
using vaw::step::FirstPassRefusal;

std::string file(const std::string& data) {
  return "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('a /* not a comment */ #1 = nan'),'2;1');\n"
         "FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n" +
         data + "ENDSEC;\nEND-ISO-10303-21;\n";
}

FirstPassRefusal refusal(const std::string& text) {
  try {
    (void)firstPass(text);
  } catch (const FirstPassRefusal& r) {
    return r;
  }
  ADD_FAILURE() << "not refused";
  return {};
}

// An assembly: product definition #pd of PRODUCT 'name', with ids from `id` on.
std::string product(int id, const std::string& name) {
  const std::string n = std::to_string(id);
  return "#" + n + " = PRODUCT('" + name + "','" + name + "','',(#9));\n#" + std::to_string(id + 1) +
         " = PRODUCT_DEFINITION_FORMATION('','',#" + n + ");\n#" + std::to_string(id + 2) +
         " = PRODUCT_DEFINITION('design','',#" + std::to_string(id + 1) + ",#8);\n";
}

std::string use(int id, int parent, int child) {
  return "#" + std::to_string(id) + " = NEXT_ASSEMBLY_USAGE_OCCURRENCE('" + std::to_string(id) + "','','',#" +
         std::to_string(parent) + ",#" + std::to_string(child) + ",$);\n";
}

TEST(StepFirstPass, OrdinaryNumbersPass) {
  const auto r = firstPass(file("#1 = CARTESIAN_POINT('',(0.,-1.5E3,+2.E-400));\n#2 = DIRECTION('',(1.,0.,0.));\n"
                                "#3 = UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#4,'distance_accuracy_value','');\n"
                                "#5 = B_SPLINE_CURVE_WITH_KNOTS('',3,(#1,#1),.UNSPECIFIED.,.F.,.F.,(4,4),(-1.E50,1.E50),.PIECEWISE_BEZIER_KNOTS.);\n"));
  EXPECT_EQ(r.entities, 4u);
  EXPECT_EQ(r.rewritten, 0u);
  EXPECT_TRUE(r.text.empty());
}

TEST(StepFirstPass, NanIsRefusedWithTheEntityAndLine) {
  const auto r = refusal(file("#1 = DIRECTION('',(1.,0.,0.));\n#12 = CARTESIAN_POINT('',(nan,0.,0.));\n"));
  EXPECT_EQ(r.field, "#12 CARTESIAN_POINT");
  EXPECT_EQ(r.found, "\"nan\" on line 8");
  EXPECT_NE(r.expected.find("finite numbers"), std::string::npos);
  EXPECT_EQ(refusal(file("#7 = VECTOR('',#1,-INF);\n")).field, "#7 VECTOR");
  EXPECT_EQ(refusal(file("#7 = CIRCLE('',#1,1.E999);\n")).found, "1.E999 on line 7");
}

TEST(StepFirstPass, HugeNumbersAreRefused) {
  const auto point = refusal(file("#12 = CARTESIAN_POINT('',(1.E308,0.,0.));\n"));
  EXPECT_EQ(point.field, "#12 CARTESIAN_POINT");
  EXPECT_NE(point.expected.find("coordinates within"), std::string::npos) << point.expected;
  // Any number past Open CASCADE's infinity, wherever it is.
  const auto radius = refusal(file("#3 = CYLINDRICAL_SURFACE('',#2,1.E120);\n"));
  EXPECT_EQ(radius.field, "#3 CYLINDRICAL_SURFACE");
  EXPECT_NE(radius.expected.find("infinity"), std::string::npos) << radius.expected;
  // A large number that is no coordinate (a knot) is allowed below that.
  EXPECT_NO_THROW((void)firstPass(file("#3 = B_SPLINE_CURVE_WITH_KNOTS('',1,(#1,#2),.UNSPECIFIED.,.F.,.F.,(2,2),(0.,1.E20),.UNSPECIFIED.);\n")));
}

TEST(StepFirstPass, InstanceBombIsRefusedInTimeWithTheProductNamed) {
  // 20,000 instances of one bolt in one assembly.
  std::string data = product(10, "ASSEMBLY") + product(20, "BOLT");
  for (int i = 0; i < 20000; ++i) data += use(100 + i, 12, 22);
  const std::string text = file(data);
  const auto start = std::chrono::steady_clock::now();
  const auto r = refusal(text);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  EXPECT_EQ(r.field, "#22 PRODUCT_DEFINITION");
  EXPECT_EQ(r.found, "an assembly of 20000 part instances, 20000 of them of \"BOLT\" (#20)");
  EXPECT_NE(r.expected.find("at most 10000 part instances"), std::string::npos) << r.expected;
  // Under a raised limit it passes, and says how many.
  vaw::step::FirstPassLimits limits;
  limits.maxInstances = 25000;
  EXPECT_DOUBLE_EQ(firstPass(text, limits).instances, 20000.0);
}

TEST(StepFirstPass, NestedAssembliesMultiply) {
  // Six levels of ten: a million instances from 60 entities, refused without expanding them.
  std::string data;
  for (int level = 0; level <= 6; ++level) data += product(10 * (level + 1), "LEVEL" + std::to_string(level));
  int id = 1000;
  for (int level = 0; level < 6; ++level)
    for (int k = 0; k < 10; ++k) data += use(id++, 10 * (level + 1) + 2, 10 * (level + 2) + 2);
  const auto r = refusal(file(data));
  EXPECT_EQ(r.found, "an assembly of 1000000 part instances, 1000000 of them of \"LEVEL6\" (#70)");
  // A small tree is counted: 2 + 3 leaves.
  std::string small = product(10, "TOP") + product(20, "SUB") + product(30, "BOLT") + product(40, "PIN");
  small += use(100, 12, 22) + use(101, 12, 22) + use(102, 22, 32) + use(103, 12, 42);
  EXPECT_DOUBLE_EQ(firstPass(file(small)).instances, 3.0);
}

// A product that contains itself is refused with the products named, under a root or with none above it:
// counting stopped there would let an instance bomb past the limit.
TEST(StepFirstPass, AProductThatContainsItselfIsRefused) {
  std::string data = product(10, "A") + product(20, "B") + product(30, "ROOT");
  data += use(100, 32, 12) + use(101, 12, 22) + use(102, 22, 12);
  const auto r = refusal(file(data));
  EXPECT_EQ(r.field, "#12 PRODUCT_DEFINITION");
  EXPECT_EQ(r.expected, "an assembly tree, in which no product contains itself");
  EXPECT_EQ(r.found, "\"A\" (#10) contains itself through \"B\" (#20)");
  // The cycle beside an instance bomb: refused all the same, before the bomb is counted.
  std::string bomb = data + product(40, "BOLT");
  for (int i = 0; i < 20000; ++i) bomb += use(200 + i, 32, 42);
  EXPECT_NE(refusal(file(bomb)).found.find("contains itself"), std::string::npos);
  // With no root above it.
  std::string rootless = product(10, "A") + product(20, "B") + use(101, 12, 22) + use(102, 22, 12);
  const auto lone = refusal(file(rootless));
  EXPECT_NE(lone.found.find("contains itself (a cycle no root reaches)"), std::string::npos) << lone.found;
}

TEST(StepFirstPass, CommentOrLineBreakBeforeTheEqualsSignIsRewritten) {
  const std::string text = file("#11 = DIRECTION('',(1.,0.,0.));\n#12 /* a comment */ = CARTESIAN_POINT('',(0.,0.,0.));\n"
                                "#13\n=\nDIRECTION('#14 /* in a string */ =',(0.,0.,1.));\n#15\t=\tDIRECTION('',(0.,1.,0.));\n");
  const auto r = firstPass(text);
  EXPECT_EQ(r.rewritten, 2u);
  EXPECT_EQ(r.entities, 4u);
  EXPECT_EQ(r.text, file("#11 = DIRECTION('',(1.,0.,0.));\n#12 = CARTESIAN_POINT('',(0.,0.,0.));\n"
                         "\n#13 =\nDIRECTION('#14 /* in a string */ =',(0.,0.,1.));\n#15\t=\tDIRECTION('',(0.,1.,0.));\n"));
  // Every line keeps its number, so Open CASCADE's messages point into the user's file.
  EXPECT_EQ(std::count(r.text.begin(), r.text.end(), '\n'), std::count(text.begin(), text.end(), '\n'));
}

TEST(StepFirstPass, StringsAndCommentsAreNotValues) {
  EXPECT_NO_THROW((void)firstPass(file("#1 = PRODUCT('nan','inf 1.E999','/* (#2 = nan) */',(#9)); /* nan 1.E999 */\n"
                                       "#2 = PRODUCT('it''s','x','',(#9));\n")));
}

}  // namespace
