// Where a scripted device aims in a compiled scene, and a scene file's hash
// (core/scene/script_target.cpp).
#include <gtest/gtest.h>

#include <stdexcept>

#include "core/geometry/primitives.h"
#include "core/scene/scene.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

// A scene of two boxes, as compiled (only the specs and meshes are read).
CompiledScene TwoBoxes() {
  CompiledScene c;
  for (double x : {0.0, 20.0}) {
    ObjectSpec o;
    o.kind = ObjectSpec::Kind::kBox;
    o.name = "box";
    o.X_WO = RigidTransform(Matrix3::Identity(), Vector3(x, 0, 5));
    c.spec.objects.push_back(o);
    c.meshes.push_back(MakeBox(Vector3(4, 4, 2)));
  }
  return c;
}

TEST(ScriptTarget, AimsAtTheTopOfTheObjectItIsGiven) {
  const CompiledScene c = TwoBoxes();
  const ScriptTarget first = FindScriptTarget(c, "poke", -1);
  EXPECT_EQ(first.object, 0) << "no tooth: the first object";
  EXPECT_NEAR(first.p_W.z(), 6.0, 1e-9) << "the top of a 2 mm box centred at z = 5";
  EXPECT_EQ(first.n_W, Vector3::UnitZ());
  const ScriptTarget second = FindScriptTarget(c, "poke", 1);
  EXPECT_EQ(second.object, 1);
  EXPECT_NEAR(second.p_W.x(), 20.0, 2.0 + 1e-9) << "on the second box";
  EXPECT_THROW(FindScriptTarget(c, "poke", 2), std::invalid_argument);
  EXPECT_THROW(FindScriptTarget(CompiledScene{}, "poke", -1), std::invalid_argument);
}

TEST(ScriptTarget, AFilesHashFollowsItsBytes) {
  const auto dir = test::FreshOutputPath("script_target", "hash");
  test::WriteText(dir / "a.yaml", "objects: []\n");
  test::WriteText(dir / "b.yaml", "objects: []\n");
  test::WriteText(dir / "c.yaml", "objects: [ ]\n");
  EXPECT_EQ(HashFile(dir / "a.yaml"), HashFile(dir / "b.yaml"));
  EXPECT_NE(HashFile(dir / "a.yaml"), HashFile(dir / "c.yaml"));
}

}  // namespace
}  // namespace sulcus
