#include "renderer.h"

#include "annex/formats/png_io.h"

#include <algorithm>
#include <cmath>

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "view.h"

namespace annex::authoring {

namespace {

constexpr float kPi = 3.14159265f;

const char* kMeshVs = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
uniform mat4 u_view_proj;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
out vec3 v_world;
out vec3 v_normal;
out vec3 v_color;
void main() {
  vec4 w = u_model * vec4(a_pos, 1.0);
  v_world = w.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_color = a_color;
  gl_Position = u_view_proj * w;
})";

// Two-sided Blinn-Phong with a key and a fill light and a sky/ground ambient.
const char* kMeshFs = R"(#version 330 core
in vec3 v_world;
in vec3 v_normal;
in vec3 v_color;
uniform vec3 u_eye;
uniform float u_alpha;
uniform vec3 u_tint;
out vec4 o_color;
void main() {
  vec3 n = normalize(v_normal);
  vec3 v = normalize(u_eye - v_world);
  if (dot(n, v) < 0.0) n = -n;
  vec3 key = normalize(vec3(0.5, 0.9, 0.6));
  vec3 fill = normalize(vec3(-0.7, 0.3, -0.4));
  float sky = 0.5 + 0.5 * n.y;
  vec3 ambient = mix(vec3(0.16, 0.15, 0.14), vec3(0.30, 0.32, 0.36), sky);
  vec3 base = v_color * u_tint;
  vec3 c = base * (ambient + 0.85 * max(dot(n, key), 0.0) + 0.25 * max(dot(n, fill), 0.0));
  vec3 h = normalize(key + v);
  c += vec3(0.35) * pow(max(dot(n, h), 0.0), 48.0);
  c += vec3(0.08) * pow(1.0 - max(dot(n, v), 0.0), 3.0);
  o_color = vec4(pow(c, vec3(1.0 / 1.15)), u_alpha);
})";

const char* kLineVs = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec4 a_color;
uniform mat4 u_view_proj;
out vec4 v_color;
void main() {
  v_color = a_color;
  gl_Position = u_view_proj * vec4(a_pos, 1.0);
})";

const char* kLineFs = R"(#version 330 core
in vec4 v_color;
uniform float u_alpha_scale;
out vec4 o_color;
void main() { o_color = vec4(v_color.rgb, v_color.a * u_alpha_scale); })";

Result<GLuint> compile(GLenum type, const char* src) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    return Error{std::string("shader compile failed: ") + log, {}};
  }
  return s;
}

Result<GLuint> link(const char* vs, const char* fs) {
  auto v = compile(GL_VERTEX_SHADER, vs);
  if (!v) return v.error();
  auto f = compile(GL_FRAGMENT_SHADER, fs);
  if (!f) return f.error();
  const GLuint p = glCreateProgram();
  glAttachShader(p, *v);
  glAttachShader(p, *f);
  glLinkProgram(p);
  glDeleteShader(*v);
  glDeleteShader(*f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[1024];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    return Error{std::string("shader link failed: ") + log, {}};
  }
  return p;
}

struct Rgba {
  float r, g, b, a;
};

// Appends line segments for one primitive (its local +Z is the axis).
void primitive_lines(std::vector<float>& out_xyz, const Primitive& p) {
  auto d = [&](std::size_t i) {
    return i < p.dimensions.size() ? static_cast<float>(p.dimensions[i].value_m) : 0.1f;
  };
  auto seg = [&](glm::vec3 a, glm::vec3 b) {
    out_xyz.insert(out_xyz.end(), {a.x, a.y, a.z, b.x, b.y, b.z});
  };
  const int n = 40;
  // A circle of radius r in a plane spanned by u, v around c.
  auto circle = [&](glm::vec3 c, glm::vec3 u, glm::vec3 v, float r) {
    for (int i = 0; i < n; ++i) {
      const float a0 = 2 * kPi * i / n, a1 = 2 * kPi * (i + 1) / n;
      seg(c + r * (std::cos(a0) * u + std::sin(a0) * v),
          c + r * (std::cos(a1) * u + std::sin(a1) * v));
    }
  };
  const glm::vec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1), O(0);
  switch (p.kind) {
    case ShapeKind::sphere: {
      const float r = d(0);
      circle(O, X, Y, r);
      circle(O, Y, Z, r);
      circle(O, X, Z, r);
      for (float z : {-0.5f, 0.5f}) circle(Z * (z * r), X, Y, r * std::sqrt(1 - z * z));
      break;
    }
    case ShapeKind::cylinder: {
      const float r = d(0), h = d(1);
      for (float z : {-0.5f * h, 0.f, 0.5f * h}) circle(Z * z, X, Y, r);
      for (int i = 0; i < 8; ++i) {
        const float a = 2 * kPi * i / 8;
        const glm::vec3 rim = r * (std::cos(a) * X + std::sin(a) * Y);
        seg(rim - Z * (0.5f * h), rim + Z * (0.5f * h));
      }
      break;
    }
    case ShapeKind::cone: {
      const float r = d(0), h = d(1);
      circle(-Z * (0.5f * h), X, Y, r);
      circle(O, X, Y, 0.5f * r);
      for (int i = 0; i < 8; ++i) {
        const float a = 2 * kPi * i / 8;
        seg(r * (std::cos(a) * X + std::sin(a) * Y) - Z * (0.5f * h), Z * (0.5f * h));
      }
      break;
    }
    case ShapeKind::torus: {
      const float big = d(0), small = d(1);
      circle(O, X, Y, big + small);
      circle(O, X, Y, std::max(0.f, big - small));
      circle(Z * small, X, Y, big);
      circle(-Z * small, X, Y, big);
      for (int i = 0; i < 8; ++i) {
        const float a = 2 * kPi * i / 8;
        const glm::vec3 radial = std::cos(a) * X + std::sin(a) * Y;
        circle(radial * big, radial, Z, small);
      }
      break;
    }
    case ShapeKind::box: {
      const glm::vec3 h(0.5f * d(0), 0.5f * d(1), 0.5f * d(2));
      for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 3; ++k) {
          if (i & (1 << k)) continue;
          const int j = i | (1 << k);
          auto corner = [&](int c) {
            return glm::vec3((c & 1) ? h.x : -h.x, (c & 2) ? h.y : -h.y, (c & 4) ? h.z : -h.z);
          };
          seg(corner(i), corner(j));
        }
      break;
    }
    case ShapeKind::plane: {  // the rectangle, its diagonals and a short normal
      const float hx = 0.5f * d(0), hy = 0.5f * d(1);
      const glm::vec3 c0 = -hx * X - hy * Y, c1 = hx * X - hy * Y, c2 = hx * X + hy * Y,
                      c3 = -hx * X + hy * Y;
      seg(c0, c1);
      seg(c1, c2);
      seg(c2, c3);
      seg(c3, c0);
      seg(c0, c2);
      seg(c1, c3);
      seg(O, Z * (0.25f * std::min(d(0), d(1))));
      break;
    }
  }
}

}  // namespace

Renderer::~Renderer() {
  clear_meshes();
  if (line_vbo_) glDeleteBuffers(1, &line_vbo_);
  if (line_vao_) glDeleteVertexArrays(1, &line_vao_);
  if (mesh_program_) glDeleteProgram(mesh_program_);
  if (line_program_) glDeleteProgram(line_program_);
}

Status Renderer::init() {
  auto m = link(kMeshVs, kMeshFs);
  if (!m) return m.error();
  mesh_program_ = *m;
  auto l = link(kLineVs, kLineFs);
  if (!l) return l.error();
  line_program_ = *l;
  glGenVertexArrays(1, &line_vao_);
  glGenBuffers(1, &line_vbo_);
  glBindVertexArray(line_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(LineVertex),
                        reinterpret_cast<void*>(3 * sizeof(float)));
  glBindVertexArray(0);
  return Ok{};
}

void Renderer::clear_meshes() {
  for (auto& [key, m] : meshes_) {
    glDeleteBuffers(1, &m.vbo);
    glDeleteBuffers(1, &m.ebo);
    glDeleteVertexArrays(1, &m.vao);
  }
  meshes_.clear();
}

const Renderer::GpuMesh& Renderer::upload(const MeshData& mesh) {
  auto it = meshes_.find(&mesh);
  if (it != meshes_.end()) return it->second;
  GpuMesh g;
  const std::size_t n = mesh.vertex_count();
  std::vector<float> interleaved;
  interleaved.reserve(n * 9);
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) interleaved.push_back(mesh.positions[3 * i + k]);
    for (int k = 0; k < 3; ++k) interleaved.push_back(mesh.normals[3 * i + k]);
    for (int k = 0; k < 3; ++k) interleaved.push_back(mesh.colors[3 * i + k]);
  }
  glGenVertexArrays(1, &g.vao);
  glGenBuffers(1, &g.vbo);
  glGenBuffers(1, &g.ebo);
  glBindVertexArray(g.vao);
  glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)),
               interleaved.data(), GL_STATIC_DRAW);
  for (int a = 0; a < 3; ++a) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, 3, GL_FLOAT, GL_FALSE, 9 * sizeof(float),
                          reinterpret_cast<void*>(static_cast<std::size_t>(a) * 3 * sizeof(float)));
  }
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
               mesh.indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  g.index_count = static_cast<int>(mesh.indices.size());
  return meshes_.emplace(&mesh, g).first->second;
}

void Renderer::draw_lines(const std::vector<LineVertex>& lines, const float* view_proj,
                          bool depth_test, float alpha_scale) {
  if (lines.empty()) return;
  glUseProgram(line_program_);
  glUniformMatrix4fv(glGetUniformLocation(line_program_, "u_view_proj"), 1, GL_FALSE, view_proj);
  glUniform1f(glGetUniformLocation(line_program_, "u_alpha_scale"), alpha_scale);
  glBindVertexArray(line_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(lines.size() * sizeof(LineVertex)),
               lines.data(), GL_STREAM_DRAW);
  if (depth_test)
    glEnable(GL_DEPTH_TEST);
  else
    glDisable(GL_DEPTH_TEST);
  glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(lines.size()));
  glBindVertexArray(0);
}

void Renderer::draw(const EditorDocument& doc, const UiState& ui, int fb_width, int fb_height,
                    float scale) {
  const Rect& vp = ui.layout.viewport;
  const int x = static_cast<int>(vp.x * scale), w = static_cast<int>(vp.w * scale);
  const int h = static_cast<int>(vp.h * scale);
  const int y = fb_height - static_cast<int>((vp.y + vp.h) * scale);
  if (w <= 0 || h <= 0) return;
  (void)fb_width;
  glEnable(GL_SCISSOR_TEST);
  glScissor(x, y, w, h);
  glViewport(x, y, w, h);
  glClearColor(0.20f, 0.21f, 0.24f, 1.f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);

  const glm::mat4 view_proj = projection_matrix(ui.camera, vp.w / vp.h) * view_matrix(ui.camera);
  const glm::vec3 eye = camera_position(ui.camera);
  const std::vector<Placement> placed = place_objects(doc, ui);

  // Grid on the floor (y = 0): 5 cm cells, 25 cm major lines, X red and Z blue axes.
  grid_.clear();
  if (ui.show_grid) {
    const float step = 0.05f;
    const int half = 30;
    for (int i = -half; i <= half; ++i) {
      const float t = i * step, e = half * step;
      const bool major = i % 5 == 0;
      const float a = major ? 0.55f : 0.25f;
      Rgba cx{0.6f, 0.6f, 0.62f, a}, cz = cx;
      if (i == 0) {
        cx = {0.85f, 0.3f, 0.3f, 0.9f};
        cz = {0.3f, 0.45f, 0.9f, 0.9f};
      }
      grid_.push_back({-e, 0, t, cx.r, cx.g, cx.b, cx.a});
      grid_.push_back({e, 0, t, cx.r, cx.g, cx.b, cx.a});
      grid_.push_back({t, 0, -e, cz.r, cz.g, cz.b, cz.a});
      grid_.push_back({t, 0, e, cz.r, cz.g, cz.b, cz.a});
    }
    draw_lines(grid_, glm::value_ptr(view_proj), true, 1.f);
  }

  // Shaded meshes; ghosts (limit previews) translucent.
  glUseProgram(mesh_program_);
  glUniformMatrix4fv(glGetUniformLocation(mesh_program_, "u_view_proj"), 1, GL_FALSE,
                     glm::value_ptr(view_proj));
  glUniform3f(glGetUniformLocation(mesh_program_, "u_eye"), eye.x, eye.y, eye.z);
  glEnable(GL_DEPTH_TEST);
  for (int pass = 0; pass < 2; ++pass) {
    for (const Placement& p : placed) {
      if (p.ghost != (pass == 1)) continue;
      // The file's mesh, uploaded once, drawn at the object's model_scale.
      const MeshData* mesh = doc.source_mesh_for(p.object);
      if (mesh == nullptr) continue;
      const GpuMesh& g = upload(*mesh);
      const glm::mat4 model =
          p.model * glm::scale(glm::mat4(1.f),
                               glm::vec3(static_cast<float>(doc.spec().objects[p.object].model_scale)));
      glUniformMatrix4fv(glGetUniformLocation(mesh_program_, "u_model"), 1, GL_FALSE,
                         glm::value_ptr(model));
      // Once per object on the CPU, not per vertex in the shader.
      const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(model)));
      glUniformMatrix3fv(glGetUniformLocation(mesh_program_, "u_normal_matrix"), 1, GL_FALSE,
                         glm::value_ptr(normal_matrix));
      glUniform1f(glGetUniformLocation(mesh_program_, "u_alpha"), p.ghost ? 0.55f : 1.f);
      const bool annexable = doc.spec().objects[p.object].annexable;
      // Virtual-only objects are drawn slightly washed out.
      const glm::vec3 tint = annexable ? glm::vec3(1.f) : glm::vec3(0.75f, 0.75f, 0.8f);
      glUniform3f(glGetUniformLocation(mesh_program_, "u_tint"), tint.x, tint.y, tint.z);
      glBindVertexArray(g.vao);
      glDrawElements(GL_TRIANGLES, g.index_count, GL_UNSIGNED_INT, nullptr);
    }
  }
  glBindVertexArray(0);

  // Primitive wireframes over the meshes: visible parts bright, hidden parts faint.
  wires_.clear();
  if (ui.show_wireframes) {
    std::vector<float> xyz;
    const Selection sel = doc.selection();
    for (const Placement& pl : placed) {
      const VirtualObject& o = doc.spec().objects[pl.object];
      for (int pi = 0; pi < static_cast<int>(o.primitives.size()); ++pi) {
        xyz.clear();
        primitive_lines(xyz, o.primitives[pi]);
        const glm::mat4 m = pl.model * primitive_matrix(o.primitives[pi]);
        Rgba c{0.25f, 0.85f, 1.0f, 0.95f};
        if (sel.object == pl.object && sel.primitive == pi)
          c = {1.0f, 0.82f, 0.15f, 1.f};
        else if (sel.object != pl.object)
          c = {0.3f, 0.7f, 0.8f, 0.7f};
        if (pl.ghost) c = {1.0f, 0.6f, 0.25f, 0.8f};
        for (std::size_t i = 0; i + 2 < xyz.size(); i += 3) {
          const glm::vec3 wv = glm::vec3(m * glm::vec4(xyz[i], xyz[i + 1], xyz[i + 2], 1.f));
          wires_.push_back({wv.x, wv.y, wv.z, c.r, c.g, c.b, c.a});
        }
      }
    }
    draw_lines(wires_, glm::value_ptr(view_proj), false, 0.28f);
    draw_lines(wires_, glm::value_ptr(view_proj), true, 1.f);
  }
  glDisable(GL_SCISSOR_TEST);
  glViewport(0, 0, fb_width, fb_height);
}

Status write_screenshot(const std::string& path, int width, int height) {
  std::vector<unsigned char> pixels(static_cast<std::size_t>(width) * height * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  for (std::size_t i = 3; i < pixels.size(); i += 4) pixels[i] = 255;  // opaque PNG
  // GL rows run bottom-up; PNG rows top-down.
  const std::size_t stride = static_cast<std::size_t>(width) * 4;
  std::vector<unsigned char> flipped(pixels.size());
  for (int row = 0; row < height; ++row)
    std::copy_n(pixels.data() + static_cast<std::size_t>(height - 1 - row) * stride, stride,
                flipped.data() + static_cast<std::size_t>(row) * stride);
  return write_png_file(path, width, height, 4, flipped.data());
}

}  // namespace annex::authoring
