// The renderer-neutral scene description and frame: what both the Qt3D viewport and the headset draw.
#include <gtest/gtest.h>

#include <set>

#include "sim_test_support.hpp"
#include "vaw/view/frame.hpp"

using namespace vaw;
using namespace vaw::sim;
using interact::PartState;
using simtest::at;

TEST(SceneDescription, SharesMeshBuffersAndResolvesColours) {
  const Assembly a = simtest::loadBundled("large-gearbox.vaw.json");
  const view::SceneDescription d = view::describe(a);
  std::set<const TriMesh*> meshes;
  std::size_t withMesh = 0;
  for (const Part& p : a.parts)
    if (p.mesh) {
      meshes.insert(p.mesh.get());
      ++withMesh;
    }
  std::set<const view::MeshBuffer*> buffers;
  for (const auto& dr : d.drawables)
    if (dr.kind != view::DrawableKind::Environment) buffers.insert(dr.mesh.get());
  EXPECT_EQ(buffers.size(), meshes.size()) << "one buffer per distinct mesh";
  EXPECT_LT(meshes.size(), withMesh) << "the gearbox repeats bolts, nuts and washers";
  for (const Part& p : a.parts) {
    ASSERT_TRUE(d.partDrawable[p.id].has_value());
    const view::Drawable& dr = d.drawables[*d.partDrawable[p.id]];
    EXPECT_EQ(dr.name, p.name);
    EXPECT_EQ(dr.mesh->vertexCount, 3 * p.mesh->triangleCount());
    const Eigen::Vector3f c = a.materials.at(p.material).color;
    EXPECT_EQ(dr.color, (view::Rgb{c.x(), c.y(), c.z()}));
    EXPECT_EQ(dr.kind, a.base == p.id ? view::DrawableKind::Base : view::DrawableKind::Part);
  }
  // Flat shading: the three vertices of a triangle carry its unit face normal.
  const view::MeshBuffer& m = *d.drawables.front().mesh;
  const float* v = m.vertices.data();
  const Eigen::Vector3f p0(v[0], v[1], v[2]), p1(v[6], v[7], v[8]), p2(v[12], v[13], v[14]);
  const Eigen::Vector3f n = (p1 - p0).cross(p2 - p0).normalized();
  for (int k = 0; k < 3; ++k) EXPECT_LT((Eigen::Vector3f(v[6 * k + 3], v[6 * k + 4], v[6 * k + 5]) - n).norm(), 1e-5f);
}

// A part held 150 mm above the table: its frame shows it INHAND, tinted, with a drop line from its centre
// of mass to the table's top face (z = 0) and the hand holding it.
TEST(Frame, HeldPartHasADropLineToTheTableAndItsHand) {
  const auto scene = Scene::build(simtest::loadBundled("sleeve-on-shaft.vaw.json"));
  const view::SceneDescription d = view::describe(scene->assembly());
  const PartId sleeve = *scene->assembly().findPart("sleeve");
  World w(scene);
  Input in;
  in.right = simtest::hand(w.part(sleeve).pose, true);
  in.right.target = sleeve;
  w.step(in);
  in.right.pose = at(0.3, 0.2, 0.15);
  w.step(in);
  view::Frame f;
  view::makeFrame(w, d, {sleeve, true}, f);
  EXPECT_EQ(f.step, 2u);
  ASSERT_EQ(f.parts.size(), scene->assembly().parts.size());
  EXPECT_EQ(f.parts[sleeve].state, PartState::InHand);
  EXPECT_EQ(f.parts[sleeve].holder, Holder::Right);
  EXPECT_TRUE(f.parts[sleeve].pose.isApprox(w.part(sleeve).pose, 0.0));
  EXPECT_TRUE(f.parts[sleeve].selected);
  const view::Rgb own = d.drawables[*d.partDrawable[sleeve]].color;
  EXPECT_EQ(f.parts[sleeve].color, view::displayColor(own, PartState::InHand, true));
  EXPECT_FALSE(f.parts[sleeve].color == own);
  EXPECT_TRUE(f.hands[1].grab);
  EXPECT_EQ(f.hands[1].holding, sleeve);
  EXPECT_FALSE(f.hands[0].holding.has_value());
  ASSERT_EQ(f.drops.size(), 1u);
  const Eigen::Vector3d com = w.part(sleeve).pose * scene->assembly().parts[sleeve].mass.centerOfMass;
  EXPECT_LT((f.drops[0].from - com).norm(), 1e-12);
  EXPECT_NEAR(f.drops[0].to.z(), 0.0, 1e-9) << "the table's top face";
  EXPECT_NEAR(f.drops[0].to.x(), com.x(), 1e-9);

  // Above the base the line ends on the base's top face (z = 40 mm), not on the table.
  in.right.pose = at(0.06, 0.0, 0.2);
  w.step(in);
  view::makeFrame(w, d, {}, f);
  ASSERT_EQ(f.drops.size(), 1u);
  EXPECT_NEAR(f.drops[0].to.z(), 0.04, 1e-9);
  EXPECT_FALSE(f.parts[sleeve].selected);
}

TEST(Frame, HoistAndItsLoad) {
  const auto scene = Scene::build(simtest::loadBundled("hoist-demo.vaw.json"));
  const view::SceneDescription d = view::describe(scene->assembly());
  ASSERT_EQ(d.hoists.size(), 1u);
  World w(scene);
  Input in;
  in.hoist = {true, 0.15, 0.0};
  w.step(in);
  view::Frame f;
  view::makeFrame(w, d, {}, f);
  ASSERT_EQ(f.hoists.size(), 1u);
  EXPECT_TRUE(f.hoists[0].engaged);
  EXPECT_EQ(f.hoists[0].load, scene->assembly().findPart("block"));
  EXPECT_EQ(f.hoists[0].hook.translation(), Eigen::Vector3d(0.5, 0.0, 0.15));
  EXPECT_EQ(f.hoists[0].top, 1.2);
  in.hoist.height = 5.0;  // beyond the travel: the hook stops at the top
  w.step(in);
  view::makeFrame(w, d, {}, f);
  EXPECT_EQ(f.hoists[0].hook.translation().z(), 1.2);
}
