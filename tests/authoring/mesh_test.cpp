#include "annex/authoring/mesh.h"

#include <gtest/gtest.h>

#include "test_util.h"

namespace annex::authoring {
namespace {

TEST(LoadMesh, SampleObjWithMaterials) {
  auto mesh = load_mesh(testing::sample_model("champagne_bottle.obj"));
  ASSERT_TRUE(mesh) << mesh.error().format();
  EXPECT_GT(mesh->triangle_count(), 1000u);
  EXPECT_EQ(mesh->normals.size(), mesh->positions.size());
  EXPECT_EQ(mesh->colors.size(), mesh->positions.size());
  // 9 cm wide, 30 cm tall, standing on y = 0.
  EXPECT_NEAR(mesh->max.y - mesh->min.y, 0.30, 0.005);
  EXPECT_NEAR(mesh->max.x - mesh->min.x, 0.092, 0.003);
  EXPECT_NEAR(mesh->min.y, 0.0, 1e-6);
  // The MTL's green glass reaches the vertex colours.
  bool green = false;
  for (std::size_t i = 0; i < mesh->vertex_count(); ++i)
    green |= mesh->colors[3 * i + 1] > 2 * mesh->colors[3 * i] && mesh->colors[3 * i + 1] > 0.2f;
  EXPECT_TRUE(green);
}

TEST(LoadMesh, EverySampleLoads) {
  for (const char* name : {"champagne_bottle.obj", "lightsaber.obj", "lamp.obj", "mug.obj",
                           "pingpong_paddle.obj", "torch.obj"}) {
    auto mesh = load_mesh(testing::sample_model(name));
    ASSERT_TRUE(mesh) << name << ": " << mesh.error().format();
    EXPECT_GT(mesh->triangle_count(), 500u) << name;
  }
}

TEST(LoadMesh, AsciiPlyAndStl) {
  const auto dir = testing::fresh_dir("formats");
  testing::write_text(
      dir / "tri.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  auto ply = load_mesh(dir / "tri.ply");
  ASSERT_TRUE(ply) << ply.error().format();
  EXPECT_EQ(ply->triangle_count(), 1u);
  testing::write_text(dir / "tri.stl",
                      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 2 0 0\n"
                      "vertex 0 2 0\nendloop\nendfacet\nendsolid t\n");
  auto stl = load_mesh(dir / "tri.stl");
  ASSERT_TRUE(stl) << stl.error().format();
  EXPECT_NEAR(stl->max.x, 2.0, 1e-6);
}

TEST(LoadMesh, GltfWithNodeTransform) {
  const auto dir = testing::fresh_dir("gltf");
  // One triangle, its node lifted 2 m: the node transform must be baked in.
  testing::write_text(
      dir / "tri.gltf",
      R"GLTF({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"scene":0,"nodes":[{"mesh":0,"translation":[0,2,0]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],"buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]})GLTF");
  auto mesh = load_mesh(dir / "tri.gltf");
  ASSERT_TRUE(mesh) << mesh.error().format();
  EXPECT_EQ(mesh->triangle_count(), 1u);
  EXPECT_NEAR(mesh->min.y, 2.0, 1e-6);
  EXPECT_NEAR(mesh->max.y, 3.0, 1e-6);
}

TEST(LoadMesh, MissingFileNamesThePath) {
  auto mesh = load_mesh("/nonexistent/box.obj");
  ASSERT_FALSE(mesh);
  EXPECT_EQ(mesh.error().location.origin, "/nonexistent/box.obj");
}

}  // namespace
}  // namespace annex::authoring
