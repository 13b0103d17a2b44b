#include "annex/authoring/script.h"

#include <gtest/gtest.h>

#include "test_util.h"

namespace annex::authoring {
namespace {

TEST(ParseScript, WordsQuotesAndComments) {
  auto lines =
      parse_script("# header\n\nadd  cylinder body # trailing\nimport \"my mesh.obj\"\n", "s.txt");
  ASSERT_TRUE(lines) << lines.error().format();
  ASSERT_EQ(lines->size(), 2u);
  EXPECT_EQ((*lines)[0].line, 3);
  EXPECT_EQ((*lines)[0].words, (std::vector<std::string>{"add", "cylinder", "body"}));
  EXPECT_EQ((*lines)[1].words, (std::vector<std::string>{"import", "my mesh.obj"}));
}

TEST(ParseScript, UnterminatedQuoteHasLineAndColumn) {
  auto lines = parse_script("new\nimport \"open.obj\n", "s.txt");
  ASSERT_FALSE(lines);
  EXPECT_EQ(lines.error().location.line, 2);
  EXPECT_EQ(lines.error().location.column, 8);
  EXPECT_EQ(lines.error().format().rfind("s.txt:2:8:", 0), 0u) << lines.error().format();
}

TEST(ParseDouble, IsStrict) {
  double v = 0;
  EXPECT_TRUE(parse_double("0.25", v));
  EXPECT_EQ(v, 0.25);
  EXPECT_TRUE(parse_double("-1e-3", v));
  EXPECT_FALSE(parse_double("0.25m", v));
  EXPECT_FALSE(parse_double("", v));
  EXPECT_FALSE(parse_double("nan", v));
}

using testing::run;

TEST(RunDocumentCommand, BuildsTheTutorialBottle) {
  EditorDocument doc;
  run(doc, "import " + testing::sample_model("champagne_bottle.obj") +
               " bottle\n"
               "add cylinder body\n"
               "fit cylinder box -0.05 0 -0.05 0.05 0.19 0.05\n"
               "set dim_weight radius 0.8\n"
               "set dim_weight height 0.2\n"
               "set limits radius 0.7 1.3\n"
               "add cone neck\n"
               "fit box -0.03 0.2 -0.03 0.03 0.3 0.03\n"
               "rank primitives body neck\n"
               "select bottle\n"
               "set priority 0.9\n"
               "validate\n");
  const VirtualObject& o = doc.spec().objects.at(0);
  EXPECT_EQ(o.name, "bottle");
  EXPECT_EQ(o.priority, 0.9);
  ASSERT_EQ(o.primitives.size(), 2u);
  const Primitive& body = o.primitives[0];
  EXPECT_NEAR(body.dimensions[0].value_m, 0.045, 0.002);
  EXPECT_NEAR(body.dimensions[1].value_m, 0.19, 0.002);
  EXPECT_NEAR(body.pose.axis().y, 1.0, 1e-6);
  EXPECT_EQ(body.dimensions[0].weight, 0.8);
  EXPECT_EQ(body.dimensions[0].min_scale, 0.7);
  EXPECT_EQ(body.weight, 1.0);
  EXPECT_EQ(o.primitives[1].weight, 0.5);
  EXPECT_EQ(o.primitives[1].kind, ShapeKind::cone);
  EXPECT_NEAR(o.primitives[1].pose.axis().y, 1.0, 1e-6);  // the apex is up
}

TEST(RunDocumentCommand, UndoRedoAndSetValues) {
  EditorDocument doc;
  run(doc, "add_object thing\nadd sphere ball\nset radius 0.2\nset position 1 2 3\nundo\n");
  const Primitive& p = doc.spec().objects[0].primitives[0];
  EXPECT_EQ(p.dimensions[0].value_m, 0.2);
  EXPECT_EQ(p.pose.position, (Vec3{0, 0, 0}));
  run(doc, "redo\nset axis 1 0 0\nset annexable off\n");
  EXPECT_EQ(doc.spec().objects[0].primitives[0].pose.position, (Vec3{1, 2, 3}));
  EXPECT_NEAR(doc.spec().objects[0].primitives[0].pose.axis().x, 1.0, 1e-12);
  EXPECT_FALSE(doc.spec().objects[0].annexable);
}

TEST(RunDocumentCommand, ErrorsNameTheLine) {
  EditorDocument doc;
  auto lines = parse_script("add_object thing\nadd cylinder\nset radiuss 0.2\n", "t.script");
  ASSERT_TRUE(lines);
  ASSERT_TRUE(run_document_command(doc, (*lines)[0], "t.script"));
  ASSERT_TRUE(run_document_command(doc, (*lines)[1], "t.script"));
  auto r = run_document_command(doc, (*lines)[2], "t.script");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().location.line, 3);
  EXPECT_NE(r.error().message.find("radiuss"), std::string::npos);
}

// Found by fuzz_script: ranking fewer items than there are wrote out of bounds
// before the ranking was checked.
TEST(RunDocumentCommand, RankingOfSomeItemsIsAnErrorNotACrash) {
  for (const char* last : {"rank primitives c\n", "rank objects thing thing\n",
                           "rank dimensions size_x size_y\n"}) {
    EditorDocument doc;
    auto lines = parse_script(std::string("add_object thing\nadd cylinder a\nadd sphere b\n"
                                          "add box c\n") + last,
                              "t.script");
    ASSERT_TRUE(lines);
    for (std::size_t i = 0; i + 1 < lines->size(); ++i)
      ASSERT_TRUE(run_document_command(doc, (*lines)[i], "t.script"));
    auto r = run_document_command(doc, lines->back(), "t.script");
    ASSERT_FALSE(r) << last;
    EXPECT_EQ(r.error().location.line, 5);
    EXPECT_NE(r.error().message.find("a ranking must list every"), std::string::npos)
        << r.error().format();
  }
}

TEST(RunDocumentCommand, UnknownVerbIsLeftToTheApp) {
  EditorDocument doc;
  auto lines = parse_script("screenshot a.png\n", "t.script");
  ASSERT_TRUE(lines);
  auto r = run_document_command(doc, (*lines)[0], "t.script");
  ASSERT_TRUE(r);
  EXPECT_FALSE(r->handled);
}

TEST(RunDocumentCommand, SaveAndOpen) {
  const auto dir = testing::fresh_dir("save");
  EditorDocument doc;
  run(doc, "import " + testing::sample_model("mug.obj") + "\nadd cylinder\nsave " +
               (dir / "mug.haptic").string() + "\nnew\nopen " + (dir / "mug.haptic").string() +
               "\n");
  ASSERT_EQ(doc.spec().objects.size(), 1u);
  EXPECT_EQ(doc.spec().objects[0].name, "mug");
  EXPECT_NE(doc.mesh_for(0), nullptr);
  EXPECT_FALSE(doc.dirty());
}

}  // namespace
}  // namespace annex::authoring
