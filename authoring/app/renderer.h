#pragma once
// OpenGL 3.3 core drawing of the viewport: grid, shaded visual meshes and the
// haptic primitives as wireframes over them (paper Figure 2a). ImGui draws the
// panels and overlays afterwards.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "annex/authoring/editor_document.h"
#include "annex/common/result.h"
#include "ui_state.h"

namespace annex::authoring {

class Renderer {
 public:
  Renderer() = default;
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;
  ~Renderer();

  // Compiles the shaders; needs a current GL 3.3 core context.
  Status init();
  // Drops GPU copies of meshes (call when the document is replaced).
  void clear_meshes();
  // Draws into the viewport rectangle of the framebuffer; `scale` is framebuffer
  // pixels per window coordinate.
  void draw(const EditorDocument& doc, const UiState& ui, int fb_width, int fb_height, float scale);

 private:
  struct GpuMesh {
    unsigned vao = 0, vbo = 0, ebo = 0;
    int index_count = 0;
  };
  struct LineVertex {
    float x, y, z, r, g, b, a;
  };
  const GpuMesh& upload(const MeshData& mesh);
  void draw_lines(const std::vector<LineVertex>& lines, const float* view_proj, bool depth_test,
                  float alpha_scale);

  unsigned mesh_program_ = 0;
  unsigned line_program_ = 0;
  unsigned line_vao_ = 0, line_vbo_ = 0;
  std::map<const MeshData*, GpuMesh> meshes_;
  std::vector<LineVertex> grid_, wires_;  // rebuilt each frame, kept to reuse memory
};

// Reads the current back buffer (bottom-up GL rows) into a PNG, top row first.
Status write_screenshot(const std::string& path, int width, int height);

}  // namespace annex::authoring
