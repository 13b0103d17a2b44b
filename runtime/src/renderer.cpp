// The Renderer on OpenGL 3.3 core: an EGL surfaceless context (no X server) or a
// GLFW window, one offscreen framebuffer reused frame after frame, meshes uploaded
// once. Projections are the sensor's pinhole model, flipped so that framebuffer row 0
// is image row 0: glReadPixels then yields the image top row first.
#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <map>
#include <string>
#include <utility>

#include "annex/runtime/renderer.h"

namespace annex {
namespace {

constexpr int kMaxImageSide = 16384;

// Row-major 4x4, for building projections on the CPU; uploaded with transpose.
using Mat4 = std::array<double, 16>;

Mat4 mat4_from(const Affine& a) {
  Mat4 m{};
  std::copy(a.m.begin(), a.m.end(), m.begin());
  m[15] = 1;
  return m;
}

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) r[i * 4 + j] += a[i * 4 + k] * b[k * 4 + j];
  return r;
}

// Clip coordinates from eye coordinates (x right, y down, z forward) for a pinhole
// camera: pixel u = fx x / z + cx has its centre at window x = u + 0.5. Window row v
// is image row v (y is not flipped), so readback comes out top row first.
Mat4 clip_from_eye(const Eye& eye) {
  const CameraIntrinsics& k = eye.intrinsics;
  const double w = k.width, h = k.height, n = eye.near_m, f = eye.far_m;
  Mat4 p{};
  p[0] = 2 * k.fx / w;
  p[2] = 2 * (k.cx + 0.5) / w - 1;
  p[5] = 2 * k.fy / h;
  p[6] = 2 * (k.cy + 0.5) / h - 1;
  p[10] = (f + n) / (f - n);
  p[11] = -2 * f * n / (f - n);
  p[14] = 1;
  return p;
}

std::array<float, 16> to_gl(const Mat4& m) {
  std::array<float, 16> out;
  for (int i = 0; i < 16; ++i) out[i] = static_cast<float>(m[i]);
  return out;
}

// Normals under an affine map follow the inverse transpose of its linear part; the
// cofactor matrix is that up to the determinant, whose sign keeps them outward.
std::array<float, 9> normal_matrix(const Mat4& m) {
  const auto a = [&](int r, int c) { return m[r * 4 + c]; };
  std::array<double, 9> cof;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
      cof[r * 3 + c] = a(r1, c1) * a(r2, c2) - a(r1, c2) * a(r2, c1);
    }
  const double det = a(0, 0) * cof[0] + a(0, 1) * cof[1] + a(0, 2) * cof[2];
  const double sign = det < 0 ? -1.0 : 1.0;
  std::array<float, 9> out;
  for (int i = 0; i < 9; ++i) out[i] = static_cast<float>(sign * cof[i]);
  return out;
}

const char* const kMeshVs = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
uniform mat4 u_eye_from_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_clip_from_eye;
out vec3 v_pos;
out vec3 v_normal;
out vec3 v_color;
void main() {
  vec4 p = u_eye_from_model * vec4(a_pos, 1.0);
  v_pos = p.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_color = a_color;
  gl_Position = u_clip_from_eye * p;
}
)";

// A headlight (two-sided, so open meshes read well) plus light from above (-y).
const char* const kMeshFs = R"(#version 330 core
in vec3 v_pos;
in vec3 v_normal;
in vec3 v_color;
uniform vec4 u_tint;
uniform int u_lit;
out vec4 frag;
void main() {
  if (u_lit == 0) { frag = u_tint; return; }
  float len = length(v_normal);
  vec3 n = len > 0.0 ? v_normal / len : vec3(0.0, 0.0, -1.0);
  vec3 to_eye = normalize(-v_pos);
  float head = abs(dot(n, to_eye));
  float top = max(dot(n, vec3(0.0, -1.0, 0.0)), 0.0);
  vec3 c = v_color * u_tint.rgb * (0.3 + 0.55 * head + 0.25 * top);
  frag = vec4(min(c, vec3(1.0)), u_tint.a);
}
)";

// Points arrive compacted (no NaN). A fixed glPointSize, not gl_PointSize: llvmpipe
// draws programmable-size points much more slowly.
const char* const kPointVs = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_color;
uniform mat4 u_clip_from_sensor;
out vec3 v_color;
void main() {
  v_color = a_color;
  gl_Position = u_clip_from_sensor * vec4(a_pos, 1.0);
}
)";

const char* const kPointFs = R"(#version 330 core
in vec3 v_color;
out vec4 frag;
void main() { frag = vec4(v_color, 1.0); }
)";

const char* const kImageVs = R"(#version 330 core
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec2 a_uv;
uniform mat4 u_clip_from_sensor;
out vec2 v_uv;
void main() {
  v_uv = a_uv;
  gl_Position = u_clip_from_sensor * vec4(a_pos, 1.0);
}
)";

const char* const kImageFs = R"(#version 330 core
in vec2 v_uv;
uniform sampler2D u_image;
out vec4 frag;
void main() { frag = vec4(texture(u_image, v_uv).rgb, 1.0); }
)";

// Occlusion: the sensor's depth image written into the depth buffer (no colour), each
// pixel's depth pushed back by the margin, so an overlay is hidden only where a real
// surface lies clearly in front of it. The projection's depth depends on z alone for
// the sensor's own view, so (0, 0, z) gives every pixel's window depth.
const char* const kDepthVs = R"(#version 330 core
void main() {
  vec2 p = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)) * 2.0 - 1.0;
  gl_Position = vec4(p, 0.0, 1.0);
}
)";

const char* const kDepthFs = R"(#version 330 core
uniform sampler2D u_depth;
uniform mat4 u_clip_from_sensor;
uniform int u_x_offset;
uniform float u_margin;
void main() {
  float z = texelFetch(u_depth, ivec2(gl_FragCoord.xy) - ivec2(u_x_offset, 0), 0).r;
  if (!(z > 0.0)) discard;
  vec4 c = u_clip_from_sensor * vec4(0.0, 0.0, z + u_margin, 1.0);
  gl_FragDepth = clamp(0.5 * c.z / c.w + 0.5, 0.0, 1.0);
}
)";

Result<GLuint> compile(GLenum type, const char* source, const char* name) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (ok) return s;
  char log[2048] = {};
  glGetShaderInfoLog(s, sizeof log - 1, nullptr, log);
  glDeleteShader(s);
  return Error{std::string("renderer: cannot compile the ") + name + " shader: " + log, {}};
}

Result<GLuint> link_program(const char* vs, const char* fs, const char* name) {
  auto v = compile(GL_VERTEX_SHADER, vs, name);
  if (!v) return v.error();
  auto f = compile(GL_FRAGMENT_SHADER, fs, name);
  if (!f) {
    glDeleteShader(*v);
    return f.error();
  }
  const GLuint p = glCreateProgram();
  glAttachShader(p, *v);
  glAttachShader(p, *f);
  glLinkProgram(p);
  glDeleteShader(*v);
  glDeleteShader(*f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (ok) return p;
  char log[2048] = {};
  glGetProgramInfoLog(p, sizeof log - 1, nullptr, log);
  glDeleteProgram(p);
  return Error{std::string("renderer: cannot link the ") + name + " shader: " + log, {}};
}

struct GpuMesh {
  GLuint vao = 0;
  std::array<GLuint, 3> vbo{};  // positions, normals, colours
  GLuint ebo = 0;
  GLuint edge_ebo = 0;  // each triangle edge once, for wireframes as GL_LINES
  GLsizei index_count = 0;
  GLsizei edge_index_count = 0;
};

// Unique undirected edges of a triangle list, two indices each.
std::vector<std::uint32_t> unique_edges(const std::vector<std::uint32_t>& tri) {
  std::vector<std::uint64_t> keys;
  keys.reserve(tri.size());
  for (std::size_t t = 0; t + 2 < tri.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = tri[t + k], b = tri[t + (k + 1) % 3];
      keys.push_back(a < b ? (a << 32) | b : (b << 32) | a);
    }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<std::uint32_t> out;
  out.reserve(keys.size() * 2);
  for (std::uint64_t k : keys) {
    out.push_back(static_cast<std::uint32_t>(k >> 32));
    out.push_back(static_cast<std::uint32_t>(k & 0xffffffffu));
  }
  return out;
}

std::string egl_error_name(EGLint e) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "EGL error 0x%04X", static_cast<unsigned>(e));
  return buf;
}

std::string glfw_error_text() {
  const char* desc = nullptr;
  const int code = glfwGetError(&desc);
  if (code == GLFW_NO_ERROR) return "unknown GLFW error";
  return desc != nullptr ? desc : "GLFW error " + std::to_string(code);
}

bool has_word(const char* list, std::string_view word) {
  if (list == nullptr) return false;
  std::string_view s(list);
  for (std::size_t pos = 0; (pos = s.find(word, pos)) != std::string_view::npos;
       pos += word.size()) {
    const bool start = pos == 0 || s[pos - 1] == ' ';
    const bool end = pos + word.size() == s.size() || s[pos + word.size()] == ' ';
    if (start && end) return true;
  }
  return false;
}

}  // namespace

struct Renderer::Impl {
  RenderTarget target = RenderTarget::headless;
  EGLDisplay egl_display = EGL_NO_DISPLAY;
  EGLContext egl_context = EGL_NO_CONTEXT;
  GLFWwindow* window = nullptr;
  std::string backend;

  GLuint mesh_program = 0, point_program = 0, image_program = 0, depth_program = 0;
  GLint u_eye_from_model = -1, u_normal_matrix = -1, u_clip_from_eye = -1, u_tint = -1, u_lit = -1,
        u_point_clip = -1, u_image_clip = -1, u_image = -1, u_depth = -1, u_depth_clip = -1,
        u_depth_x_offset = -1, u_depth_margin = -1;

  std::vector<GpuMesh> meshes;
  std::map<std::string, MeshId> mesh_by_path;

  GLuint fbo = 0, color_rb = 0, depth_rb = 0;
  int fbo_width = 0, fbo_height = 0;
  GLint max_renderbuffer = 0;

  GLuint points_vao = 0, points_vbo = 0;
  GLuint image_vao = 0, image_vbo = 0, image_tex = 0, image_fbo = 0;
  int tex_width = 0, tex_height = 0;
  GLuint depth_tex = 0;  // the frame's depth (metres, 0 where invalid) for occlusion
  int depth_width = 0, depth_height = 0;
  bool have_depth = false;
  std::vector<float> z_scratch;            // reused: the frame's depth as an image
  std::vector<std::uint8_t> rgb_scratch;   // reused: the frame's colours as an image
  std::vector<PointXYZRGB> point_scratch;  // reused: the frame's valid points, thinned
  GLsizei point_count = 0;
  std::vector<float> depth_sample;  // reused: for the image plane's median depth

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl();

  // False when the context cannot be made current on this thread (e.g. another
  // API's context, GLX through GLFW, is current here).
  bool make_current();
  Status create_egl();
  Status create_glfw(bool visible, const RendererParams& params);
  Status init_gl();
  void ensure_framebuffer(int width, int height);
  Status draw(const RenderScene& scene, std::span<const Eye> eyes);
  void draw_background(const RenderScene& scene, const Eye& eye, int x_offset,
                       const Mat4& clip_from_sensor, bool have_image, bool have_points,
                       double image_depth);
  void draw_overlays(const RenderScene& scene, const Eye& eye);
  Status upload_background(const RenderScene& scene, bool& have_image, bool& have_points);
  double median_depth(const Frame& frame);
};

bool Renderer::Impl::make_current() {
  if (egl_context != EGL_NO_CONTEXT) {
    if (eglGetCurrentContext() != egl_context)
      return eglMakeCurrent(egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_context) == EGL_TRUE;
  } else if (window != nullptr && glfwGetCurrentContext() != window) {
    glfwMakeContextCurrent(window);
    return glfwGetCurrentContext() == window;
  }
  return true;
}

Renderer::Impl::~Impl() {
  if (egl_context == EGL_NO_CONTEXT && window == nullptr) return;
  make_current();
  for (const GpuMesh& m : meshes) {
    glDeleteVertexArrays(1, &m.vao);
    glDeleteBuffers(3, m.vbo.data());
    glDeleteBuffers(1, &m.ebo);
    glDeleteBuffers(1, &m.edge_ebo);
  }
  glDeleteFramebuffers(1, &fbo);
  glDeleteRenderbuffers(1, &color_rb);
  glDeleteRenderbuffers(1, &depth_rb);
  glDeleteVertexArrays(1, &points_vao);
  glDeleteBuffers(1, &points_vbo);
  glDeleteVertexArrays(1, &image_vao);
  glDeleteBuffers(1, &image_vbo);
  glDeleteTextures(1, &image_tex);
  glDeleteTextures(1, &depth_tex);
  glDeleteFramebuffers(1, &image_fbo);
  glDeleteProgram(depth_program);
  glDeleteProgram(mesh_program);
  glDeleteProgram(point_program);
  glDeleteProgram(image_program);
  if (egl_context != EGL_NO_CONTEXT) {
    eglMakeCurrent(egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(egl_display, egl_context);
    // The display stays initialised: eglTerminate would pull it from under any other
    // Renderer of this process.
  }
  if (window != nullptr) {
    glfwMakeContextCurrent(nullptr);
    glfwDestroyWindow(window);
    // GLFW stays initialised for the same reason (glfwTerminate closes every window).
  }
}

Status Renderer::Impl::create_egl() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  const auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr || !has_word(client, "EGL_MESA_platform_surfaceless"))
    return Error{"EGL: no surfaceless platform (EGL_MESA_platform_surfaceless)", {}};
  EGLDisplay display =
      get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
    return Error{
        "EGL: cannot initialise the surfaceless display (" + egl_error_name(eglGetError()) + ")",
        {}};
  if (!has_word(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context"))
    return Error{"EGL: the display has no EGL_KHR_surfaceless_context", {}};
  if (!eglBindAPI(EGL_OPENGL_API)) return Error{"EGL: no desktop OpenGL API", {}};
  const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  eglChooseConfig(display, config_attribs, &config, 1, &count);
  const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                    3,
                                    EGL_CONTEXT_MINOR_VERSION,
                                    3,
                                    EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                    EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                    EGL_NONE};
  EGLContext context = eglCreateContext(display, count > 0 ? config : EGL_NO_CONFIG_KHR,
                                        EGL_NO_CONTEXT, context_attribs);
  if (context == EGL_NO_CONTEXT)
    return Error{
        "EGL: cannot create an OpenGL 3.3 core context (" + egl_error_name(eglGetError()) + ")",
        {}};
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    const EGLint e = eglGetError();
    eglDestroyContext(display, context);
    return Error{"EGL: cannot make the context current (" + egl_error_name(e) + ")", {}};
  }
  egl_display = display;
  egl_context = context;
  backend = "EGL surfaceless";
  return Ok{};
}

Status Renderer::Impl::create_glfw(bool visible, const RendererParams& params) {
  if (!glfwInit()) return Error{"GLFW: " + glfw_error_text(), {}};
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow* w =
      glfwCreateWindow(std::max(1, params.window_width), std::max(1, params.window_height),
                       params.window_title.c_str(), nullptr, nullptr);
  if (w == nullptr) return Error{"GLFW: cannot create a window: " + glfw_error_text(), {}};
  window = w;
  glfwMakeContextCurrent(w);
  glfwSwapInterval(0);  // the caller paces frames (the sensor does, at 30 Hz)
  backend = visible ? "GLFW window" : "hidden GLFW window";
  return Ok{};
}

Status Renderer::Impl::init_gl() {
  backend += std::string(": ") + reinterpret_cast<const char*>(glGetString(GL_RENDERER)) +
             ", OpenGL " + reinterpret_cast<const char*>(glGetString(GL_VERSION));
  auto mesh = link_program(kMeshVs, kMeshFs, "mesh");
  if (!mesh) return mesh.error();
  mesh_program = *mesh;
  auto point = link_program(kPointVs, kPointFs, "point");
  if (!point) return point.error();
  point_program = *point;
  auto image = link_program(kImageVs, kImageFs, "image");
  if (!image) return image.error();
  image_program = *image;
  auto depth = link_program(kDepthVs, kDepthFs, "occlusion depth");
  if (!depth) return depth.error();
  depth_program = *depth;
  u_depth = glGetUniformLocation(depth_program, "u_depth");
  u_depth_clip = glGetUniformLocation(depth_program, "u_clip_from_sensor");
  u_depth_x_offset = glGetUniformLocation(depth_program, "u_x_offset");
  u_depth_margin = glGetUniformLocation(depth_program, "u_margin");
  u_eye_from_model = glGetUniformLocation(mesh_program, "u_eye_from_model");
  u_normal_matrix = glGetUniformLocation(mesh_program, "u_normal_matrix");
  u_clip_from_eye = glGetUniformLocation(mesh_program, "u_clip_from_eye");
  u_tint = glGetUniformLocation(mesh_program, "u_tint");
  u_lit = glGetUniformLocation(mesh_program, "u_lit");
  u_point_clip = glGetUniformLocation(point_program, "u_clip_from_sensor");
  u_image_clip = glGetUniformLocation(image_program, "u_clip_from_sensor");
  u_image = glGetUniformLocation(image_program, "u_image");
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_renderbuffer);

  glGenFramebuffers(1, &fbo);
  glGenRenderbuffers(1, &color_rb);
  glGenRenderbuffers(1, &depth_rb);

  // Points come straight from Frame::points: x y z floats, then r g b bytes.
  glGenVertexArrays(1, &points_vao);
  glGenBuffers(1, &points_vbo);
  glBindVertexArray(points_vao);
  glBindBuffer(GL_ARRAY_BUFFER, points_vbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(PointXYZRGB),
                        reinterpret_cast<void*>(offsetof(PointXYZRGB, x)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(PointXYZRGB),
                        reinterpret_cast<void*>(offsetof(PointXYZRGB, r)));

  // The camera image: a quad of 4 vertices (x y z u v), rewritten per eye.
  glGenVertexArrays(1, &image_vao);
  glGenBuffers(1, &image_vbo);
  glBindVertexArray(image_vao);
  glBindBuffer(GL_ARRAY_BUFFER, image_vbo);
  glBufferData(GL_ARRAY_BUFFER, 4 * 5 * sizeof(float), nullptr, GL_DYNAMIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 5 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 5 * sizeof(float),
                        reinterpret_cast<void*>(3 * sizeof(float)));
  glGenTextures(1, &image_tex);
  glGenFramebuffers(1, &image_fbo);
  glBindTexture(GL_TEXTURE_2D, image_tex);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glGenTextures(1, &depth_tex);
  glBindTexture(GL_TEXTURE_2D, depth_tex);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glBindVertexArray(0);

  const GLenum err = glGetError();
  if (err != GL_NO_ERROR)
    return Error{"renderer: OpenGL error " + std::to_string(err) + " while setting up", {}};
  return Ok{};
}

void Renderer::Impl::ensure_framebuffer(int width, int height) {
  if (width == fbo_width && height == fbo_height) return;
  glBindRenderbuffer(GL_RENDERBUFFER, color_rb);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_rb);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_rb);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
  fbo_width = width;
  fbo_height = height;
}

double Renderer::Impl::median_depth(const Frame& frame) {
  // Every 16th point is plenty for a plane that only sets the image's parallax.
  depth_sample.clear();
  for (std::size_t i = 0; i < frame.points.size(); i += 16) {
    const float z = frame.points[i].z;
    if (std::isfinite(z) && z > 0) depth_sample.push_back(z);
  }
  if (depth_sample.empty()) return 1.0;
  auto mid = depth_sample.begin() + depth_sample.size() / 2;
  std::nth_element(depth_sample.begin(), mid, depth_sample.end());
  return *mid;
}

Status Renderer::Impl::upload_background(const RenderScene& scene, bool& have_image,
                                         bool& have_points) {
  have_image = have_points = have_depth = false;
  if (scene.background == Background::clear) return Ok{};
  const Location where{scene.frame != nullptr ? "frame " + std::to_string(scene.frame->index)
                                              : std::string("renderer"),
                       0, 0};
  if (scene.frame == nullptr)
    return Error{"renderer: the background needs a frame (use Background::clear without one)",
                 where};
  const Frame& frame = *scene.frame;
  if (frame.width < 0 || frame.height < 0 ||
      static_cast<std::size_t>(frame.width) * static_cast<std::size_t>(frame.height) !=
          frame.points.size())
    return Error{"renderer: the frame's " + std::to_string(frame.points.size()) +
                     " points do not fill its " + std::to_string(frame.width) + "x" +
                     std::to_string(frame.height) + " grid",
                 where};
  if (scene.background == Background::point_cloud) {
    // Invalid points are dropped here rather than in the shader (llvmpipe's cost
    // is per vertex); organized frames are thinned by rows and columns.
    const int stride = std::max(1, scene.point_stride);
    point_scratch.clear();
    const auto keep = [&](const PointXYZRGB& p) {
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
        point_scratch.push_back(p);
    };
    if (frame.organized()) {
      for (int v = 0; v < frame.height; v += stride)
        for (int u = 0; u < frame.width; u += stride)
          keep(frame.points[static_cast<std::size_t>(v) * frame.width + u]);
    } else {
      for (std::size_t i = 0; i < frame.points.size(); i += stride) keep(frame.points[i]);
    }
    glBindBuffer(GL_ARRAY_BUFFER, points_vbo);
    // Orphaning the old storage lets the driver keep drawing the previous frame.
    glBufferData(GL_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(point_scratch.size() * sizeof(PointXYZRGB)),
                 point_scratch.data(), GL_STREAM_DRAW);
    point_count = static_cast<GLsizei>(point_scratch.size());
    have_points = point_count > 0;
    return Ok{};
  }
  if (!frame.organized() || frame.width > kMaxImageSide || frame.height > kMaxImageSide)
    return Error{"renderer: a camera image background needs an organized frame; this one is " +
                     std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                     " (use the point cloud background)",
                 where};
  if (scene.camera.width <= 0 || scene.camera.height <= 0 || !(scene.camera.fx > 0) ||
      !(scene.camera.fy > 0))
    return Error{"renderer: the camera intrinsics need a positive size and focal lengths", where};
  rgb_scratch.resize(frame.points.size() * 3);
  for (std::size_t i = 0; i < frame.points.size(); ++i) {
    rgb_scratch[3 * i] = frame.points[i].r;
    rgb_scratch[3 * i + 1] = frame.points[i].g;
    rgb_scratch[3 * i + 2] = frame.points[i].b;
  }
  glBindTexture(GL_TEXTURE_2D, image_tex);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (frame.width != tex_width || frame.height != tex_height) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, frame.width, frame.height, 0, GL_RGB, GL_UNSIGNED_BYTE,
                 rgb_scratch.data());
    tex_width = frame.width;
    tex_height = frame.height;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, image_fbo);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, image_tex, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, frame.width, frame.height, GL_RGB, GL_UNSIGNED_BYTE,
                    rgb_scratch.data());
  }
  have_image = true;
  if (scene.occlusion_margin_m >= 0) {
    z_scratch.resize(frame.points.size());
    for (std::size_t i = 0; i < frame.points.size(); ++i) {
      const float z = frame.points[i].z;
      z_scratch[i] = std::isfinite(z) && z > 0 ? z : 0.0f;
    }
    glBindTexture(GL_TEXTURE_2D, depth_tex);
    if (frame.width != depth_width || frame.height != depth_height) {
      glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, frame.width, frame.height, 0, GL_RED, GL_FLOAT,
                   z_scratch.data());
      depth_width = frame.width;
      depth_height = frame.height;
    } else {
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, frame.width, frame.height, GL_RED, GL_FLOAT,
                      z_scratch.data());
    }
    have_depth = true;
  }
  return Ok{};
}

void Renderer::Impl::draw_background(const RenderScene& scene, const Eye& eye, int x_offset,
                                     const Mat4& clip_from_sensor, bool have_image,
                                     bool have_points, double image_depth) {
  const auto clip = to_gl(clip_from_sensor);
  const CameraIntrinsics& cam = scene.camera;
  const CameraIntrinsics& in = eye.intrinsics;
  const bool same_camera = eye.eye_from_sensor.m == Affine{}.m && in.width == cam.width &&
                           in.height == cam.height && in.fx == cam.fx && in.fy == cam.fy &&
                           in.cx == cam.cx && in.cy == cam.cy && tex_width == cam.width &&
                           tex_height == cam.height;
  if (have_image && same_camera) {
    // The sensor's own view at the image's size: the image is copied, not drawn
    // (the texture's row 0 is image row 0, as in the framebuffer).
    glBindFramebuffer(GL_READ_FRAMEBUFFER, image_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glBlitFramebuffer(0, 0, tex_width, tex_height, x_offset, 0, x_offset + tex_width, tex_height,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    if (have_depth) {
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_ALWAYS);
      glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
      glUseProgram(depth_program);
      glUniformMatrix4fv(u_depth_clip, 1, GL_TRUE, clip.data());
      glUniform1i(u_depth, 0);
      glUniform1i(u_depth_x_offset, x_offset);
      glUniform1f(u_depth_margin, static_cast<float>(scene.occlusion_margin_m));
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, depth_tex);
      glBindVertexArray(image_vao);
      glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
      glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      glDepthFunc(GL_LESS);
    }
  } else if (have_image) {
    // The camera's image plane at depth d: its pixel corners back-projected through
    // the camera's intrinsics. Seen from the sensor itself it fills the view exactly.
    const CameraIntrinsics& k = scene.camera;
    const double d = std::clamp(image_depth, 2 * eye.near_m, 0.5 * eye.far_m);
    const auto corner = [&](double u, double v, float s, float t) {
      return std::array<float, 5>{static_cast<float>((u - k.cx) / k.fx * d),
                                  static_cast<float>((v - k.cy) / k.fy * d), static_cast<float>(d),
                                  s, t};
    };
    const double u1 = k.width - 0.5, v1 = k.height - 0.5;
    const std::array<std::array<float, 5>, 4> quad = {corner(-0.5, -0.5, 0, 0),
                                                      corner(u1, -0.5, 1, 0),
                                                      corner(-0.5, v1, 0, 1), corner(u1, v1, 1, 1)};
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glUseProgram(image_program);
    glUniformMatrix4fv(u_image_clip, 1, GL_TRUE, clip.data());
    glUniform1i(u_image, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, image_tex);
    glBindVertexArray(image_vao);
    glBindBuffer(GL_ARRAY_BUFFER, image_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, sizeof quad, quad.data());
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDepthMask(GL_TRUE);
  }
  if (have_points) {
    glEnable(GL_DEPTH_TEST);
    glUseProgram(point_program);
    glUniformMatrix4fv(u_point_clip, 1, GL_TRUE, clip.data());
    glPointSize(std::max(1.0f, scene.point_size_px));
    glBindVertexArray(points_vao);
    glDrawArrays(GL_POINTS, 0, point_count);
  }
}

void Renderer::Impl::draw_overlays(const RenderScene& scene, const Eye& eye) {
  const Mat4 eye_from_sensor = mat4_from(eye.eye_from_sensor);
  const auto clip = to_gl(clip_from_eye(eye));
  glUseProgram(mesh_program);
  glUniformMatrix4fv(u_clip_from_eye, 1, GL_TRUE, clip.data());
  glEnable(GL_DEPTH_TEST);
  // Opaque overlays first; blended ones after them, reading but not writing depth.
  for (int pass = 0; pass < 2; ++pass) {
    const bool blended = pass == 1;
    if (blended) {
      glEnable(GL_BLEND);
      glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
      glDepthMask(GL_FALSE);
    }
    for (const Overlay& o : scene.overlays) {
      if ((o.tint.a < 1.0f) != blended) continue;
      const GpuMesh& m = meshes[o.mesh.index];
      const Mat4 eye_from_model = eye_from_sensor * mat4_from(o.world_from_model);
      const auto em = to_gl(eye_from_model);
      const auto nm = normal_matrix(eye_from_model);
      glUniformMatrix4fv(u_eye_from_model, 1, GL_TRUE, em.data());
      glUniformMatrix3fv(u_normal_matrix, 1, GL_TRUE, nm.data());
      glUniform4f(u_tint, o.tint.r, o.tint.g, o.tint.b, o.tint.a);
      // Wireframes as lines over each edge once: llvmpipe's glPolygonMode(GL_LINE)
      // is several times slower.
      const bool wire = o.style == OverlayStyle::wireframe;
      glUniform1i(u_lit, wire ? 0 : 1);
      glBindVertexArray(m.vao);
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, wire ? m.edge_ebo : m.ebo);
      glDrawElements(wire ? GL_LINES : GL_TRIANGLES, wire ? m.edge_index_count : m.index_count,
                     GL_UNSIGNED_INT, nullptr);
    }
  }
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
}

Status Renderer::Impl::draw(const RenderScene& scene, std::span<const Eye> eyes) {
  if (eyes.empty()) return Error{"renderer: no eye to render", {}};
  long total_width = 0;
  int height = 0;
  for (const Eye& e : eyes) {
    const CameraIntrinsics& k = e.intrinsics;
    if (k.width < 1 || k.height < 1 || k.width > kMaxImageSide || k.height > kMaxImageSide ||
        !(k.fx > 0) || !(k.fy > 0) || !std::isfinite(k.cx) || !std::isfinite(k.cy))
      return Error{"renderer: an eye needs a size of 1 to " + std::to_string(kMaxImageSide) +
                       " pixels and positive focal lengths, got " + std::to_string(k.width) + "x" +
                       std::to_string(k.height),
                   {}};
    if (!(e.near_m > 0) || !(e.far_m > e.near_m))
      return Error{"renderer: an eye needs 0 < near < far", {}};
    total_width += k.width;
    height = std::max(height, k.height);
  }
  if (total_width > max_renderbuffer || height > max_renderbuffer)
    return Error{"renderer: " + std::to_string(total_width) + "x" + std::to_string(height) +
                     " is larger than this OpenGL's limit of " + std::to_string(max_renderbuffer),
                 {}};
  for (const Overlay& o : scene.overlays)
    if (o.mesh.index < 0 || o.mesh.index >= static_cast<int>(meshes.size()))
      return Error{"renderer: overlay with unknown mesh id " + std::to_string(o.mesh.index), {}};

  if (!make_current())
    return Error{"renderer: cannot make the OpenGL context current on this thread", {}};
  ensure_framebuffer(static_cast<int>(total_width), height);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glDisable(GL_SCISSOR_TEST);
  glViewport(0, 0, fbo_width, fbo_height);
  const Rgba& bg = scene.clear_color;
  glClearColor(bg.r, bg.g, bg.b, bg.a);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  bool have_image = false, have_points = false;
  if (auto st = upload_background(scene, have_image, have_points); !st) return st;
  // The image plane's depth matters only for eyes away from the sensor.
  double image_depth = scene.image_depth_m > 0 ? scene.image_depth_m : 1.0;
  const bool all_at_sensor = std::all_of(
      eyes.begin(), eyes.end(), [](const Eye& e) { return e.eye_from_sensor.m == Affine{}.m; });
  if (have_image && !(scene.image_depth_m > 0) && !all_at_sensor)
    image_depth = median_depth(*scene.frame);

  int x = 0;
  for (const Eye& e : eyes) {
    glViewport(x, 0, e.intrinsics.width, e.intrinsics.height);
    const Mat4 clip_from_sensor = clip_from_eye(e) * mat4_from(e.eye_from_sensor);
    draw_background(scene, e, x, clip_from_sensor, have_image, have_points, image_depth);
    draw_overlays(scene, e);
    x += e.intrinsics.width;
  }
  glBindVertexArray(0);
  const GLenum err = glGetError();
  if (err != GL_NO_ERROR)
    return Error{"renderer: OpenGL error " + std::to_string(err) + " while drawing", {}};
  return Ok{};
}

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;
Renderer::~Renderer() = default;

Result<Renderer> Renderer::create(const RendererParams& params) {
  auto impl = std::make_unique<Impl>();
  impl->target = params.target;
  std::string tried;
  Status made = Error{"no backend enabled in RendererParams", {}};
  if (params.target == RenderTarget::window) {
    made = impl->create_glfw(true, params);
    if (!made) tried = made.error().message;
  } else {
    if (params.try_egl) {
      made = impl->create_egl();
      if (!made) tried = made.error().message;
    }
    if (!made && params.try_hidden_window) {
      made = impl->create_glfw(false, params);
      if (!made) tried += (tried.empty() ? "" : "; ") + made.error().message;
    }
  }
  if (!made)
    return Error{
        "renderer: no OpenGL context (" + (tried.empty() ? made.error().message : tried) + ")", {}};
  if (auto st = impl->init_gl(); !st) return st.error();
  return Renderer(std::move(impl));
}

std::string Renderer::backend() const {
  return impl_->backend;
}

Result<MeshId> Renderer::add_mesh(const MeshData& mesh, const std::string& origin) {
  if (auto st = validate_mesh(mesh, origin); !st) return st.error();
  if (!impl_->make_current())
    return Error{"renderer: cannot make the OpenGL context current on this thread", {}};
  GpuMesh g;
  glGenVertexArrays(1, &g.vao);
  glGenBuffers(3, g.vbo.data());
  glGenBuffers(1, &g.ebo);
  glGenBuffers(1, &g.edge_ebo);
  glBindVertexArray(g.vao);
  const std::vector<float>* arrays[3] = {&mesh.positions, &mesh.normals, &mesh.colors};
  for (GLuint i = 0; i < 3; ++i) {
    glBindBuffer(GL_ARRAY_BUFFER, g.vbo[i]);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(arrays[i]->size() * sizeof(float)),
                 arrays[i]->data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(i);
    glVertexAttribPointer(i, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  }
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
               mesh.indices.data(), GL_STATIC_DRAW);
  const std::vector<std::uint32_t> edges = unique_edges(mesh.indices);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.edge_ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(edges.size() * sizeof(std::uint32_t)), edges.data(),
               GL_STATIC_DRAW);
  // The VAO keeps the triangle indices bound; wireframes rebind the edges per draw.
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ebo);
  glBindVertexArray(0);
  g.index_count = static_cast<GLsizei>(mesh.indices.size());
  g.edge_index_count = static_cast<GLsizei>(edges.size());
  impl_->meshes.push_back(g);
  return MeshId{static_cast<int>(impl_->meshes.size()) - 1};
}

Result<MeshId> Renderer::load_mesh(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::path key = std::filesystem::weakly_canonical(path, ec);
  if (ec) key = path;
  if (auto it = impl_->mesh_by_path.find(key.string()); it != impl_->mesh_by_path.end())
    return it->second;
  auto mesh = annex::load_mesh(path);
  if (!mesh) return mesh.error();
  auto id = add_mesh(*mesh, path.string());
  if (!id) return id.error();
  impl_->mesh_by_path.emplace(key.string(), *id);
  return id;
}

Status Renderer::render(const RenderScene& scene, std::span<const Eye> eyes, RgbaImage& out) {
  if (auto st = impl_->draw(scene, eyes); !st) return st;
  out.width = impl_->fbo_width;
  out.height = impl_->fbo_height;
  out.rgba.resize(static_cast<std::size_t>(out.width) * out.height * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, impl_->fbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, out.width, out.height, GL_RGBA, GL_UNSIGNED_BYTE, out.rgba.data());
  return Ok{};
}

Result<RgbaImage> Renderer::render(const RenderScene& scene, std::span<const Eye> eyes) {
  RgbaImage out;
  if (auto st = render(scene, eyes, out); !st) return st.error();
  return out;
}

Result<bool> Renderer::present(const RenderScene& scene, std::span<const Eye> eyes) {
  if (impl_->window == nullptr || impl_->target != RenderTarget::window)
    return Error{"renderer: present() needs a Renderer created with RenderTarget::window", {}};
  if (auto st = impl_->draw(scene, eyes); !st) return st.error();
  int ww = 0, wh = 0;
  glfwGetFramebufferSize(impl_->window, &ww, &wh);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  glViewport(0, 0, ww, wh);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  // Fit the image into the window, aspect kept; rows flipped, since the offscreen
  // image has its top row at framebuffer row 0 and the window at the top.
  const int iw = impl_->fbo_width, ih = impl_->fbo_height;
  const double s = std::min(static_cast<double>(ww) / iw, static_cast<double>(wh) / ih);
  const int dw = static_cast<int>(iw * s), dh = static_cast<int>(ih * s);
  const int dx = (ww - dw) / 2, dy = (wh - dh) / 2;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, impl_->fbo);
  glBlitFramebuffer(0, 0, iw, ih, dx, dy + dh, dx + dw, dy, GL_COLOR_BUFFER_BIT, GL_LINEAR);
  glfwSwapBuffers(impl_->window);
  glfwPollEvents();
  return !glfwWindowShouldClose(impl_->window);
}

}  // namespace annex
