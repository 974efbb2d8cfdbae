// Tests of sim/scene/checks called directly on parsed objects: charges inside objects (with the
// object's placement), invalid charges keeping their index, names clashing, and the panel limit
// counted exactly as make_panels cuts.
#include "sim/scene/checks.hpp"

#include <cstdint>
#include <numbers>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

namespace brisance::scene {
namespace {

SceneObject box_object(std::string name, const Vec3& size, const Vec3& position,
                       const Quat& orientation = Quat::Identity()) {
  SceneObject object;
  object.spec.name = std::move(name);
  object.spec.shape = ShapeType::box;
  object.spec.box_size_m = size;
  object.spec.mesh = geometry::make_box(size);
  object.spec.position = position;
  object.spec.orientation = orientation;
  object.name_pointer = "/objects/0/name";
  object.position_pointer = "/objects/0/position";
  return object;
}

std::optional<ChargeSpec> charge_at(const Vec3& position) {
  ChargeSpec charge;
  charge.position = position;
  return charge;
}

TEST(SceneChecks, ChargeInsideATurnedObjectKeepsItsIndex) {
  // A 4 x 0.2 x 0.2 beam turned 90 degrees about y runs along z around (10, 0, 0).
  const Quat turn(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()));
  const std::vector<SceneObject> objects = {
      box_object("beam", Vec3(4, 0.2, 0.2), Vec3(10, 0, 0), turn)};
  Errors errors;
  check_charges_outside_objects(
      {std::nullopt, charge_at(Vec3(10, 0, 1.5)), charge_at(Vec3(11.5, 0, 0)),
       charge_at(Vec3(10.1, 0, 0))},  // the last one on the beam's surface
      objects, errors);
  const std::vector<ValidationError> list = errors.take();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].pointer, "/charges/1/position");
  EXPECT_EQ(list[0].message,
            "the charge is inside object 'beam'; move the charge out of the object (or the "
            "object away from it)");
}

TEST(SceneChecks, GeneratorNameClashIsReportedOnce) {
  std::vector<SceneObject> objects = {box_object("a", Vec3::Ones(), Vec3::Zero())};
  for (int i = 0; i < 3; ++i) {
    SceneObject generated = box_object("a", Vec3::Ones(), Vec3::Zero());
    generated.generator = 0;
    generated.name_pointer = "/generators/0/name";
    objects.push_back(generated);
  }
  Errors errors;
  check_unique_names(objects, errors);
  const std::vector<ValidationError> list = errors.take();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].pointer, "/generators/0/name");
}

TEST(SceneChecks, PanelLimitIsTheExactMakePanelsCount) {
  const std::vector<SceneObject> objects = {
      box_object("slab", Vec3(3, 0.2, 2), Vec3::Zero()),
      box_object("brick", Vec3(0.4, 0.15, 0.1), Vec3(0, 1, 0)),
      box_object("another slab", Vec3(3, 0.2, 2), Vec3(0, 2, 0))};
  SimulationSpec simulation;
  simulation.max_panel_area_m2 = 0.01;
  std::size_t panels = 0;
  for (const SceneObject& object : objects)
    panels += geometry::make_panels(object.spec.mesh, simulation.max_panel_area_m2).size();
  Limits limits;
  limits.max_panels = panels;  // exactly at the limit: allowed
  Errors at_limit;
  check_limits(objects, simulation, true, limits, at_limit);
  EXPECT_EQ(at_limit.count(), 0u);
  limits.max_panels = panels - 1;
  Errors over;
  check_limits(objects, simulation, true, limits, over);
  const std::vector<ValidationError> list = over.take();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].pointer, "");
  // An invalid simulation section is reported there; the limits are not checked against it.
  Errors skipped;
  check_limits(objects, simulation, false, limits, skipped);
  EXPECT_EQ(skipped.count(), 0u);
}

}  // namespace
}  // namespace brisance::scene
